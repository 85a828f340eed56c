// The first stage of tracing, before any street is traced on its own: streets of the base that
// reach the region from opposite sides, each pointing at the other, are one street the region
// cut, and are joined straight across it (tracing_stages.hpp), where the streets around both
// run on a grid, or where they are a main road in line with itself. A grid goes on as a grid
// through the region, its streets meeting in crossings, and two grid cities stitched across a
// gap are joined street to street where their streets line up.
#include "tracing_stages.hpp"

#include <algorithm>

#include "ggg/graph/plane_geometry.hpp"

namespace ggg::growth_detail::tracing {

using namespace spatial; // bg, bgi, point, Box

namespace {

// How far a street's heading may miss the street across (radians), and how far aside it may
// end (as a share of the way across): a street that was cut goes on as it ran.
constexpr double kAcrossTurn = 6.0 * M_PI / 180.0;
constexpr double kAcrossAside = 0.08;
// How far the line may run from the grid of the streets around its ends (their four-fold mean
// direction, which two grids meeting or a few diagonal streets pull aside by some degrees).
constexpr double kAcrossGrid = 15.0 * M_PI / 180.0;
// Two ends this well in line are one straight street the region cut.
constexpr double kStraightTurn = 2.0 * M_PI / 180.0;
constexpr double kStraightAside = 0.02;
// The least distance between two junctions of a main road laid across (m): about the width of
// a carriageway, as where two dual carriageways cross.
constexpr double kCarriagewaysApart = 8.0;
// An avenue across a grid: straight within this turn, and meeting the streets it crosses at
// this angle at least (Washington's avenues cross its grid at 20 to 30 degrees, too).
constexpr double kAvenueTurn = 3.0 * M_PI / 180.0;
constexpr double kAvenueAngle = 20.0 * M_PI / 180.0;
// Two avenues meet at this angle at least (less, they are one road or do not meet).
constexpr double kAvenueMeeting = 30.0 * M_PI / 180.0;

} // namespace

void Tracer::join_across() {
    // In a winding city two streets that happen to face each other across the region (within
    // a few degrees, each square to the streets around it) are not one street (Monaco's hole
    // was crossed by a straight main road 1.3 km long).
    const double reach = s_.border_m + std::max(3.0 * typical_, long_);
    // The loose ends of the base that point into the region, with their heading.
    std::vector<End> ends;
    for (std::size_t v = 0; v < base_vertices_; ++v) {
        const auto id = static_cast<VertexId>(v);
        if (degree(id) != 1) continue;
        const EdgeId e = adjacency_[v][0];
        if (!traced_class(g_.edge_highway[static_cast<std::size_t>(e)])) continue;
        const Vec2 p = g_.positions[v];
        const Vec2 back = leaving(g_, e, id) - p;
        if (back.norm() < 1e-9) continue;
        const Vec2 ahead = -back.normalized();
        // At the region's border (a street the region cut), not one that ends further out.
        const double enters = entry_distance(p, ahead, reach);
        if (enters < 0 || enters > 0.3 * typical_) continue;
        if (inside(region_, p) && distance_to_ring(region_, p) > 0.3 * typical_) continue; // (deep inside)
        ends.push_back({id, ahead, g_.edge_highway[static_cast<std::size_t>(e)]});
    }
    // Pairs that face each other, the best aligned first.
    std::vector<std::tuple<double, std::size_t, std::size_t, bool>> pairs; // (turn, end, end, a main road)
    for (std::size_t i = 0; i < ends.size(); ++i) {
        for (std::size_t j = i + 1; j < ends.size(); ++j) {
            const Vec2 a = g_.positions[static_cast<std::size_t>(ends[i].v)], b = g_.positions[static_cast<std::size_t>(ends[j].v)];
            const Vec2 d = b - a;
            const double length = d.norm();
            if (length < typical_) continue;
            const Vec2 u = d / length;
            const double turn_a = std::acos(std::clamp(u.dot(ends[i].ahead), -1.0, 1.0));
            const double turn_b = std::acos(std::clamp(-u.dot(ends[j].ahead), -1.0, 1.0));
            const double aside = std::max(std::abs(cross(ends[i].ahead, d)), std::abs(cross(ends[j].ahead, d)));
            if (turn_a > kAcrossTurn || turn_b > kAcrossTurn || aside > kAcrossAside * length) continue;
            // Only where the streets around both ends run on a grid and the line keeps to it:
            // in a winding city two streets that happen to face each other are not one.
            // Both ends on one grid, too (its directions within a few degrees at both): two
            // streets of a winding city may each run square to the streets around them. Unless
            // the two ends are one straight street cut in two (within 2 degrees and 2 % of the
            // way across of each other's line): the mean direction of the streets around each
            // end is pulled aside by a main road or a neighbouring grid (by 13 degrees in
            // Oakland, whose hole is crossed by four such streets).
            const bool straight_on = std::max(turn_a, turn_b) <= kStraightTurn && aside <= kStraightAside * length;
            // A main road cut in two goes on across where no grid would join it: in a city
            // not on a grid (Rome's dual carriageways), or across the grid (a diagonal avenue).
            // Along a grid, the grid's streets are joined as below. Only a road that runs
            // straight up to the cut on one side at least: two ends of Monaco's winding roads
            // that happened to face each other were crossed by a straight road 1.3 km long.
            auto along_grid = [&](const Vec2& end) {
                const std::optional<double> grid = local_grid(end);
                if (!grid) return false;
                const double off = wrap(angle_of(u) - *grid);
                return std::abs(off - std::round(off / (M_PI / 2)) * (M_PI / 2)) <= kAcrossGrid;
            };
            if (straight_on && main_class(ends[i].highway) && main_class(ends[j].highway) &&
                !(s_.grid_city && (along_grid(a) || along_grid(b))) && (runs_straight(ends[i]) || runs_straight(ends[j]))) {
                pairs.emplace_back(std::max(turn_a, turn_b), i, j, true);
                continue;
            }
            if (!s_.grid_city) continue;
            bool on_grids = true;
            std::optional<double> first_grid;
            for (const Vec2& end : {a, b}) {
                const std::optional<double> grid = local_grid(end);
                if (!grid) {
                    on_grids = false;
                    break;
                }
                if (first_grid) {
                    const double apart = wrap(*grid - *first_grid);
                    on_grids = on_grids && (straight_on || std::abs(apart - std::round(apart / (M_PI / 2)) * (M_PI / 2)) <= kAcrossTurn);
                }
                first_grid = grid;
                const double off = wrap(angle_of(u) - *grid);
                const double k = std::round(off / (M_PI / 2));
                on_grids = on_grids && std::abs(off - k * (M_PI / 2)) <= kAcrossGrid;
            }
            if (!on_grids) continue;
            pairs.emplace_back(std::max(turn_a, turn_b), i, j, false);
        }
    }
    std::sort(pairs.begin(), pairs.end());
    std::vector<char> used(ends.size(), 0);
    const double spacing = 0.3 * typical_;
    std::vector<Across> laid;
    for (const auto& [turn, i, j, main_road] : pairs) {
        if (used[i] || used[j] || g_.vertex_count() + 8 >= s_.max_vertices) continue;
        const VertexId from = ends[i].v, to = ends[j].v;
        const Vec2 a = g_.positions[static_cast<std::size_t>(from)], b = g_.positions[static_cast<std::size_t>(to)];
        {
            // Inside the region all the way, but for its ends.
            const double length = (b - a).norm();
            const Vec2 u = (b - a) / length;
            bool out = false;
            for (double t = spacing; t < length - spacing && !out; t += std::max(spacing, length / 64)) out = !inside(region_, a + t * u);
            // Across the region, not along its border.
            if (out || distance_to_ring(region_, 0.5 * (a + b)) < spacing) continue;
        }
        // What it crosses: only streets joined across before it (the base's are never split),
        // each at an angle a street may meet another at, with room for the junctions. Where
        // two dual carriageways cross, their four junctions are one carriageway's width apart.
        const double room = main_road ? std::min(spacing, kCarriagewaysApart) : spacing;
        const Vec2 d = b - a;
        const double length = d.norm();
        std::vector<std::pair<double, EdgeId>> hits;
        bool fits = true;
        Box box(point(a), point(a));
        bg::expand(box, point(b));
        bg::expand(box, point(a - Vec2(spacing, spacing)));
        bg::expand(box, point(b + Vec2(spacing, spacing)));
        for (auto it = segments_.qbegin(bgi::intersects(box)); fits && it != segments_.qend(); ++it) {
            const EdgeId e = it->second;
            const auto [p, q] = g_.edges[static_cast<std::size_t>(e)];
            if (p == from || p == to || q == from || q == to) continue;
            const Vec2* pts = g_.geometry_begin(e);
            for (std::size_t k = 0; fits && k + 1 < g_.geometry_size(e); ++k) {
                const Vec2 r = pts[k + 1] - pts[k];
                const auto m = segment_meeting(a, b, pts[k], pts[k + 1]);
                const double sine = std::abs(cross(d, r)) / std::max(length * r.norm(), 1e-300);
                if (!m) {
                    // A street alongside, too close to have a block between them (but for the
                    // other carriageway of a main road, laid across or cut where it ends).
                    const bool carriageway = main_road && main_class(g_.edge_highway[static_cast<std::size_t>(e)]);
                    if (sine < std::sin(min_angle_) && distance_to_segment(pts[k], a, b) < spacing &&
                        (pts[k] - a).dot(d) > 0 && (pts[k] - b).dot(d) < 0 && !carriageway) {
                        fits = false;
                    }
                    continue;
                }
                const Vec2 x = a + m->first * d;
                if (static_cast<std::size_t>(e) < fixed_edges_ || sine < std::sin(min_angle_) ||
                    m->first * length < spacing || (1.0 - m->first) * length < spacing ||
                    (x - g_.positions[static_cast<std::size_t>(p)]).norm() < room ||
                    (x - g_.positions[static_cast<std::size_t>(q)]).norm() < room) {
                    fits = false;
                } else {
                    hits.emplace_back(m->first, e);
                }
            }
        }
        if (!fits) continue;
        std::sort(hits.begin(), hits.end());
        for (std::size_t k = 1; k < hits.size(); ++k) fits = fits && (hits[k].first - hits[k - 1].first) * length >= room;
        if (!fits) continue;
        std::vector<std::pair<EdgeId, Vec2>> crossings;
        for (const auto& [t, e] : hits) crossings.emplace_back(e, a + t * d);
        lay_straight(from, to, crossings, ends[i].highway);
        used[i] = used[j] = 1;
        across_[static_cast<std::size_t>(from)] = across_[static_cast<std::size_t>(to)] = 1;
        laid.push_back({from, to, ends[i].highway});
        ++report_.across;
    }
    if (s_.grid_city) lay_avenues(ends, used, laid);
    for (const Across& street : laid) open_junctions(street);
}

bool Tracer::runs_straight(const End& end) const {
    // Straight for two typical streets back from the cut, through the junctions on the way
    // (on along the street that goes on straightest, within a few degrees).
    const VertexId v = end.v;
    const Vec2 p = g_.positions[static_cast<std::size_t>(v)];
    double run = 0.0, aside = 0.0;
    VertexId at = v;
    EdgeId e = adjacency_[static_cast<std::size_t>(v)][0];
    for (int steps = 0; steps < 16 && run < 2.0 * typical_; ++steps) {
        const Vec2* pts = g_.geometry_begin(e);
        for (std::size_t k = 0; k < g_.geometry_size(e); ++k) {
            const Vec2 d = pts[k] - p;
            run = std::max(run, -d.dot(end.ahead));
            aside = std::max(aside, std::abs(cross(end.ahead, d)));
        }
        const VertexId next = other_end(e, at);
        const Vec2 back = g_.positions[static_cast<std::size_t>(next)] - g_.positions[static_cast<std::size_t>(at)];
        EdgeId on = -1;
        double straightest = kAvenueTurn;
        for (const EdgeId f : adjacency_[static_cast<std::size_t>(next)]) {
            if (f == e) continue;
            const Vec2 d = leaving(g_, f, next) - g_.positions[static_cast<std::size_t>(next)];
            const double turn = std::abs(wrap(angle_of(d) - angle_of(back)));
            if (turn < straightest) straightest = turn, on = f;
        }
        if (on < 0) break;
        at = next;
        e = on;
    }
    return run >= 2.0 * typical_ && aside <= std::max(3.0, std::tan(kAvenueTurn) * run);
}

void Tracer::lay_avenues(const std::vector<End>& ends, std::vector<char>& used, std::vector<Across>& laid) {
    // A main road that runs straight across the grid up to the region (Washington's diagonal
    // avenues) goes on straight into it, to where it meets another such road. Traced from the
    // city's junctions instead, each would turn onto the grid at its first junction.
    const double spacing = 0.3 * typical_;
    const double room = std::min(spacing, kCarriagewaysApart);
    std::vector<std::size_t> avenues;
    for (std::size_t i = 0; i < ends.size(); ++i) {
        if (used[i] || !main_class(ends[i].highway)) continue;
        const VertexId v = ends[i].v;
        const Vec2 p = g_.positions[static_cast<std::size_t>(v)];
        const std::optional<double> grid = local_grid(p);
        if (!grid) continue;
        const double off = wrap(angle_of(ends[i].ahead) - *grid);
        if (std::abs(off - std::round(off / (M_PI / 2)) * (M_PI / 2)) <= kAcrossGrid) continue; // along the grid
        if (runs_straight(ends[i])) avenues.push_back(i);
    }
    // The crossings of a leg from `a` to `x` (way along, street): only of streets laid across,
    // at kAvenueAngle or more, with room between the junctions; none when it does not fit.
    auto leg = [&](VertexId from, const Vec2& a, const Vec2& x) -> std::optional<std::vector<std::pair<double, EdgeId>>> {
        const Vec2 d = x - a;
        const double length = d.norm();
        if (length < spacing) return std::nullopt;
        const Vec2 u = d / length;
        std::vector<std::pair<double, EdgeId>> hits;
        Box box(point(a), point(a));
        bg::expand(box, point(x));
        for (auto it = segments_.qbegin(bgi::intersects(box)); it != segments_.qend(); ++it) {
            const EdgeId e = it->second;
            const auto [p, q] = g_.edges[static_cast<std::size_t>(e)];
            if (p == from || q == from) continue;
            const Vec2* pts = g_.geometry_begin(e);
            for (std::size_t k = 0; k + 1 < g_.geometry_size(e); ++k) {
                const auto m = segment_meeting(a, x, pts[k], pts[k + 1]);
                if (!m) continue;
                const Vec2 at = a + m->first * d;
                const Vec2 r = pts[k + 1] - pts[k];
                const double sine = std::abs(cross(u, r)) / std::max(r.norm(), 1e-300);
                if (static_cast<std::size_t>(e) < fixed_edges_ || sine < std::sin(std::min(min_angle_, kAvenueAngle)) ||
                    m->first * length < spacing || (1.0 - m->first) * length < room ||
                    (at - g_.positions[static_cast<std::size_t>(p)]).norm() < room || (at - g_.positions[static_cast<std::size_t>(q)]).norm() < room) {
                    return std::nullopt;
                }
                hits.emplace_back(m->first * length, e);
            }
        }
        std::sort(hits.begin(), hits.end());
        for (std::size_t k = 1; k < hits.size(); ++k) {
            if (hits[k].first - hits[k - 1].first < room) return std::nullopt;
        }
        // No street alongside, too close to have a block between them.
        for (auto it = vertices_.qbegin(bgi::intersects(spatial::around(a, x, room))); it != vertices_.qend(); ++it) {
            if (it->second == from) continue;
            const Vec2 w = g_.positions[static_cast<std::size_t>(it->second)];
            const double along = (w - a).dot(u);
            if (along > spacing && along < length - room && distance_to_segment(w, a, x) < room) return std::nullopt;
        }
        return hits;
    };
    // Two avenues meet where their lines do (as Washington's meet at its circles), the
    // nearest meetings first, at an angle two streets meet at.
    std::vector<std::tuple<double, std::size_t, std::size_t, Vec2>> meetings;
    for (std::size_t m = 0; m < avenues.size(); ++m) {
        for (std::size_t n = m + 1; n < avenues.size(); ++n) {
            const End& i = ends[avenues[m]];
            const End& j = ends[avenues[n]];
            const Vec2 a = g_.positions[static_cast<std::size_t>(i.v)], b = g_.positions[static_cast<std::size_t>(j.v)];
            const double det = cross(i.ahead, j.ahead);
            if (std::abs(det) < std::sin(kAvenueMeeting)) continue; // (near parallel, or one straight road)
            const double s = cross(b - a, j.ahead) / det, t = cross(b - a, i.ahead) / det;
            const Vec2 x = a + s * i.ahead;
            if (s < spacing || t < spacing || !inside(region_, x) || distance_to_ring(region_, x) < spacing) continue;
            meetings.emplace_back(std::max(s, t), avenues[m], avenues[n], x);
        }
    }
    std::sort(meetings.begin(), meetings.end(), [](const auto& l, const auto& r) { return std::get<0>(l) < std::get<0>(r); });
    for (const auto& [far, i, j, x] : meetings) {
        if (used[i] || used[j] || g_.vertex_count() + 16 >= s_.max_vertices) continue;
        const Vec2 a = g_.positions[static_cast<std::size_t>(ends[i].v)], b = g_.positions[static_cast<std::size_t>(ends[j].v)];
        const auto first = leg(ends[i].v, a, x);
        const auto second = leg(ends[j].v, b, x);
        if (!first || !second) continue;
        // (Not two legs across one street: each is split where it was before either.)
        bool shared = false;
        for (const auto& [t, e] : *first) {
            for (const auto& [u, f] : *second) shared = shared || e == f;
        }
        if (shared) continue;
        const VertexId meeting = add_vertex(x);
        for (const auto& [k, hits] : {std::pair{i, *first}, std::pair{j, *second}}) {
            const VertexId from = ends[k].v;
            const Vec2 p = g_.positions[static_cast<std::size_t>(from)];
            const Vec2 u = (x - p).normalized();
            std::vector<std::pair<EdgeId, Vec2>> crossings;
            for (const auto& [t, e] : hits) crossings.emplace_back(e, p + t * u);
            lay_straight(from, meeting, crossings, ends[k].highway);
            used[k] = 1;
            across_[static_cast<std::size_t>(from)] = 1;
            laid.push_back({from, meeting, ends[k].highway});
            ++report_.avenues;
        }
    }
}

void Tracer::lay_straight(VertexId from, VertexId to, const std::vector<std::pair<EdgeId, Vec2>>& crossings, HighwayClass highway) {
    // A junction at every crossing, the street in pieces between them.
    VertexId last = from;
    for (const auto& [e, at] : crossings) {
        const VertexId x = split(e, at);
        add_street(last, x, {g_.positions[static_cast<std::size_t>(last)], g_.positions[static_cast<std::size_t>(x)]}, highway);
        last = x;
    }
    add_street(last, to, {g_.positions[static_cast<std::size_t>(last)], g_.positions[static_cast<std::size_t>(to)]}, highway);
}

void Tracer::open_junctions(const Across& street) {
    const Vec2 a = g_.positions[static_cast<std::size_t>(street.from)], b = g_.positions[static_cast<std::size_t>(street.to)];
    const double length = (b - a).norm();
    const Vec2 u = (b - a) / length;
    const double spacing = 0.3 * typical_;
    // The street's vertices in order: its ends and the crossings made on it since.
    std::vector<std::pair<double, VertexId>> chain;
    for (auto it = vertices_.qbegin(bgi::intersects(spatial::around(a, b, 1e-6 * length))); it != vertices_.qend(); ++it) {
        const Vec2 p = g_.positions[static_cast<std::size_t>(it->second)];
        if (distance_to_segment(p, a, b) <= 1e-6 * length) chain.emplace_back((p - a).dot(u), it->second);
    }
    std::sort(chain.begin(), chain.end());
    const bool main = main_class(street.highway);
    for (double at = 0.0;;) {
        // The next junction one of the city's streets on from here, where the street has room.
        const Branch* on = nullptr;
        const Example* example = nullptr;
        for (int attempt = 0; attempt < 16 && !on; ++attempt) {
            example = &example_for(main);
            for (const Branch& br : example->branches) {
                if (std::abs(br.turn) < min_angle_) on = &br;
            }
        }
        if (!on || example->branches.size() < 2) break;
        at += std::max(on->length, spacing);
        if (at > length - spacing) break;
        const auto next = std::lower_bound(chain.begin(), chain.end(), std::pair{at, VertexId{-1}});
        if (next == chain.begin() || next == chain.end()) break;
        const auto before = std::prev(next);
        if (at - before->first < spacing || next->first - at < spacing) continue;
        EdgeId piece = -1;
        for (const EdgeId e : adjacency_[static_cast<std::size_t>(before->second)]) {
            if (other_end(e, before->second) == next->second) piece = e;
        }
        if (piece < 0 || g_.vertex_count() >= s_.max_vertices) break;
        const VertexId x = split(piece, a + at * u);
        chain.insert(next, {at, x});
        const bool mirror = std::bernoulli_distribution(0.5)(rng_);
        for (const Branch& br : example->branches) {
            if (&br != on) queue_branch(x, angle_of(u), br, mirror, street.highway, 1);
        }
    }
}

} // namespace ggg::growth_detail::tracing
