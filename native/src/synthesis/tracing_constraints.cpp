// The local constraints of tracing (Parish & Müller): a traced street is joined to what it
// meets instead of being dropped. It stops at a street it crosses, ends at a junction near its
// end or meets a street near it in a T-junction, squared as often as the city's junctions are
// right angles; where none of that fits, it is dropped (tracing_stages.hpp).
#include "tracing_stages.hpp"

#include "ggg/graph/plane_geometry.hpp"

namespace ggg::growth_detail::tracing {

namespace {

// A street that meets another at less than this angle (radians) runs along it.
constexpr double kAlongStreet = 5.0 * M_PI / 180.0;

} // namespace

bool Tracer::fits_to_vertex(VertexId from, const std::vector<Vec2>& line, VertexId to) {
    if (to == from || degree(to) >= 4 || adjacent(from, to)) return false;
    if (first_hit(line, from, to)) return false;
    const Vec2 arrive = line[line.size() - 2] - line.back();
    if (clearance(to, arrive) < min_angle_) return false;
    for (std::size_t k = 1; k + 1 < line.size(); ++k) {
        if (!inside(region_, line[k])) return false;
    }
    return !closes_small_block(from, to);
}

void Tracer::squared(const Street& s, std::vector<Vec2>& line, EdgeId e, std::size_t piece) {
    const Vec2 from_point = line[line.size() - 2];
    const Vec2* q = g_.geometry_begin(e);
    const Vec2 d = q[piece + 1] - q[piece];
    const double slant = std::abs(std::cos(angle_of(line.back() - from_point) - angle_of(d))); // 0: square
    // (Where the streets around run on a grid, every one is squared.)
    if (slant > std::sin(M_PI / 5) && !local_grid(from_point) && !std::bernoulli_distribution(right_share_)(rng_)) return;
    const double t = (from_point - q[piece]).dot(d) / std::max(d.squaredNorm(), 1e-300);
    if (t < 0.05 || t > 0.95) return;
    const Vec2 foot = q[piece] + t * d;
    if ((foot - line.back()).norm() > 0.5 * typical_ || (foot - from_point).norm() < 0.2 * typical_) return;
    std::vector<Vec2> moved = line;
    moved.back() = foot;
    if (first_hit(moved, s.from, -1, e)) return;
    line = std::move(moved);
}

bool Tracer::end_at(const Street& s, const std::vector<Vec2>& line, VertexId w) {
    const std::vector<Vec2> to_w = warped(line, g_.positions[static_cast<std::size_t>(w)]);
    if (!fits_to_vertex(s.from, to_w, w)) return false;
    // Where the streets around run on a grid, a join does not bend a street off it (by more
    // than 10 degrees, or than its own shape was).
    if (const auto grid = local_grid(line.front())) {
        auto off = [&](const std::vector<Vec2>& l) {
            const double a = wrap(angle_of(l.back() - l.front()) - *grid);
            return std::abs(a - std::round(a / (M_PI / 2)) * (M_PI / 2));
        };
        if (off(to_w) > std::max(off(line), M_PI / 18)) return false;
    }
    // A street of the base traced on joins what it meets only once it is in the region, and
    // runs in the region for most of its length: one that joins another street of the base on
    // the way there, or cuts across a corner of the region to a street just inside it, adds a
    // street to the city around instead of continuing it into the region.
    if (s.generation == 0 && (!enters_region(to_w) || share_inside(to_w) < 0.5)) return false;
    // A grown street joins a street outside the region only across the border band: one that
    // runs on out of the region to a street further away lays a street in the city around.
    if (s.generation > 0 && length_outside(to_w) > std::max(s_.border_m, 0.1 * typical_)) return false;
    add_street(s.from, w, to_w, s.highway);
    ++report_.joined;
    return true;
}

void Tracer::go_on_across(const Street& s, const std::vector<Vec2>& line, VertexId x) {
    // Across a street it meets about square (within 30 degrees): a slanting crossing makes
    // two sharp corners, which cities avoid.
    const Vec2 in = (line.back() - line[line.size() - 2]).normalized();
    const Vec2 px = g_.positions[static_cast<std::size_t>(x)];
    const auto street = static_cast<EdgeId>(g_.edge_count() - 1); // the one just added, which arrives
    for (const EdgeId e : adjacency_[static_cast<std::size_t>(x)]) {
        if (e == street) continue;
        const Vec2 d = leaving(g_, e, x) - px;
        if (d.norm() < 1e-9 || std::abs(in.dot(d.normalized())) > 0.5) return;
    }
    // One of the city's junctions where a street arrives at a street passing across it (a
    // street leaves it to either side), seen from the arriving street: where it is a crossing,
    // its street straight on. A T seen from its stem ends there; seen from its bar it says
    // nothing of whether streets cross (no street arrives at one across it there). Counted as
    // a T, as it was, it made grids of T's: Oakland grew 2 to 3 times its T-junctions.
    auto across_it = [](const Example& example) {
        bool left = false, right = false;
        for (const Branch& b : example.branches) {
            left |= b.turn > M_PI / 6 && b.turn < 5 * M_PI / 6;
            right |= b.turn < -M_PI / 6 && b.turn > -5 * M_PI / 6;
        }
        return left && right;
    };
    const Example* junction = nullptr;
    for (int attempt = 0; attempt < 32 && !junction; ++attempt) {
        const Example& example = example_for(s.main);
        if (across_it(example)) junction = &example;
    }
    if (!junction) return;
    const Branch* straight = nullptr;
    for (const Branch& b : junction->branches) {
        if (std::abs(b.turn) < M_PI / 6 && (!straight || std::abs(b.turn) < std::abs(straight->turn))) straight = &b;
    }
    if (!straight) return;
    const double arriving = angle_of(line.back() - line[line.size() - 2]);
    queue_branch(x, arriving, *straight, std::bernoulli_distribution(0.5)(rng_), s.highway, s.generation + 1, true);
    ++report_.crossed;
}

Tracer::Settled Tracer::settle(const Street& s, const std::vector<Vec2>& line) {
    const double snap = 0.3 * snap_scale();
    // A junction this close is joined rather than met beside it: less where the city's share of
    // short streets allows one more.
    const double join = spacing(snap);

    // A street it crosses: it stops there, at the junction near by or a new one.
    if (const auto hit = first_hit(line, s.from)) {
        std::vector<Vec2> cut(line.begin(), line.begin() + static_cast<long>(hit->piece) + 1);
        cut.push_back(hit->where);
        double travelled = 0.0;
        for (std::size_t k = 1; k < cut.size(); ++k) travelled += (cut[k] - cut[k - 1]).norm();
        if (travelled < spacing(0.25 * typical_) || leaves_region_inside_line(cut)) return Settled::dropped;
        const auto [a, b] = g_.edges[static_cast<std::size_t>(hit->edge)];
        for (const VertexId end : {a, b}) {
            if ((g_.positions[static_cast<std::size_t>(end)] - hit->where).norm() < join) {
                return end_at(s, cut, end) ? Settled::joined : Settled::dropped;
            }
        }
        if (a == s.from || b == s.from) return Settled::dropped; // it would come back to where it started
        squared(s, cut, hit->edge, hit->edge_piece);
        const Vec2* q = g_.geometry_begin(hit->edge);
        const Vec2 along = q[hit->edge_piece + 1] - q[hit->edge_piece];
        const Vec2 arrive = cut[cut.size() - 2] - cut.back();
        const double crossing_angle = std::abs(std::sin(angle_of(arrive) - angle_of(along)));
        if (crossing_angle < std::sin(min_angle_)) return Settled::dropped;
        if (!inside(region_, cut.back()) || static_cast<std::size_t>(hit->edge) < fixed_edges_) return Settled::dropped;
        if (s_.min_block_m2 > 0 && splits_small_block(s.from, hit->edge, cut.back())) return Settled::dropped;
        const VertexId x = split(hit->edge, cut.back());
        add_street(s.from, x, cut, s.highway);
        ++report_.t_junctions;
        go_on_across(s, cut, x);
        return Settled::joined;
    }
    // Out of the region: only to join a street there.
    const Vec2 end = line.back();
    if (leaves_region_inside_line(line) || !inside(region_, end)) {
        const auto w = nearest_vertex(end, snap, s.from);
        return w && end_at(s, line, *w) ? Settled::joined : Settled::dropped;
    }
    // A junction near its end: it ends there.
    if (const auto w = nearest_vertex(end, join, s.from)) return end_at(s, line, *w) ? Settled::joined : Settled::dropped;
    // A street near its end: it meets it.
    const auto near = nearest_street(end, snap, s.from);
    if (near) {
        const EdgeId e = near->edge;
        std::vector<Vec2> to_x = warped(line, near->where);
        squared(s, to_x, e, near->piece);
        const Vec2 x = to_x.back();
        const auto [a, b] = g_.edges[static_cast<std::size_t>(e)];
        const bool room = (g_.positions[static_cast<std::size_t>(a)] - x).norm() > join && (g_.positions[static_cast<std::size_t>(b)] - x).norm() > join;
        // Not along it: a street bent onto a street beside it at a few degrees would run on
        // along it (Helsinki grew one at 1 degree). Narrow junctions are the city's own where
        // it has them (Washington's streets meet its avenues at 20 to 30 degrees).
        const Vec2* q = g_.geometry_begin(e);
        const Vec2 along = q[near->piece + 1] - q[near->piece];
        const bool across = std::abs(std::sin(angle_of(to_x[to_x.size() - 2] - x) - angle_of(along))) >= std::sin(kAlongStreet);
        if (room && across && inside(region_, x) && static_cast<std::size_t>(e) >= fixed_edges_ && !first_hit(to_x, s.from, -1, e) && !(s_.min_block_m2 > 0 && splits_small_block(s.from, e, x))) {
            const VertexId junction = split(e, x);
            add_street(s.from, junction, to_x, s.highway);
            ++report_.t_junctions;
            go_on_across(s, to_x, junction);
            return Settled::joined;
        }
    }
    // No room to meet a street beside a junction near its end: it ends at the junction, as it
    // would without short streets.
    if (join < snap) {
        if (const auto w = nearest_vertex(end, snap, s.from)) return end_at(s, line, *w) ? Settled::joined : Settled::dropped;
    }
    return near ? Settled::dropped : Settled::open;
}

} // namespace ggg::growth_detail::tracing
