// Streets traced into a region after the city's own junctions; see street_tracing.hpp. This
// file runs the stages (tracing_stages.hpp): the examples learned, the seeds found, then the
// streets traced one at a time, main roads first, each laid, settled and continued.
#include "street_tracing.hpp"

#include <algorithm>
#include <array>
#include <limits>

#include "tracing_stages.hpp"

#include "ggg/graph/plane_geometry.hpp"

namespace ggg::growth_detail {
namespace tracing {

Tracer::Tracer(GeometricGraph& g, std::size_t base_vertices, const GeometricGraph& city, const std::vector<Vec2>& region,
               const TracingSettings& settings, std::mt19937_64& rng, const ProgressCallback& progress)
    : g_(g), base_vertices_(base_vertices), region_(region), s_(settings), rng_(rng), progress_(progress) {
    // The streets around the region are the closest example of how the streets it continues
    // run (their curves included, which a grammar's city, decoded from rules, has not);
    // the grammar's city is the example where the base has too few of them.
    double size = 0.0;
    for (const Vec2& p : region_) size = std::max(size, (p - region_.front()).norm());
    region_size_ = size;
    // The nearest streets first (the parts of a city differ), further out until there are
    // enough of them.
    for (double radius = 0.25 * size; radius <= 2.0 * size; radius *= 2) {
        main_examples_.clear();
        other_examples_.clear();
        learn_examples(g_, radius);
        if (main_examples_.size() + other_examples_.size() >= 400) break;
    }
    if (main_examples_.size() + other_examples_.size() < 200) {
        main_examples_.clear();
        other_examples_.clear();
        learn_examples(city, std::numeric_limits<double>::infinity());
        measure_density(city, std::numeric_limits<double>::infinity());
        measure_empty_ground(city, std::numeric_limits<double>::infinity());
    } else if (s_.no_street_reaches) {
        measure_density(g_, std::numeric_limits<double>::infinity());
        measure_empty_ground(g_, std::numeric_limits<double>::infinity());
    } else {
        // The density of the ground next to the region, which says best how dense the streets
        // it continues are (a city's parts differ: a port beside a grid of houses); further
        // out where there is too little of it.
        double measured = 0.0;
        for (double band = 3.0 * typical_; band <= 2.0 * size; band *= 2) {
            measure_density(g_, measured = band);
            if (density_cells_ >= 64) break;
        }
        if (measured > 0.0) measure_empty_ground(g_, measured);
    }
}

TracingReport Tracer::run() {
    if (main_examples_.empty() && other_examples_.empty()) return report_;
    fixed_edges_ = g_.edge_count();
    index();
    across_.assign(base_vertices_, 0);
    join_across();
    seed();
    std::size_t steps = 0;
    const std::size_t max_steps = 50 * s_.max_vertices + 1000;
    auto drain = [&] {
        while (!queue_.empty() && g_.vertex_count() < s_.max_vertices && steps++ < max_steps) {
            Street street = queue_.top();
            queue_.pop();
            if (steps % 256 == 0) report(progress_, std::min(0.99, static_cast<double>(report_.streets) / static_cast<double>(expected_streets_)), "tracing streets");
            trace(street);
            // A corner is closed as soon as it is left, before other streets take the ground
            // (closed after them, a district grew a tenth more streets).
            if (!street.closes_corner) close_corner(street.from, street.generation + 1);
        }
    };
    drain();
    // Rounds while empty ground is left and a round still adds streets into it.
    for (int round = 0; round < 8 && g_.vertex_count() < s_.max_vertices; ++round) {
        const std::size_t before = report_.streets;
        if (!open_empty_ground()) break;
        drain();
        if (report_.streets == before) break;
    }
    close_corners();
    drain();
    offset_crossings();
    junction_islands();
    join_close_ends();
    report_.density = density_;
    report_.junction_density = junction_density_;
    report_.typical_m = typical_;
    return report_;
}

void Tracer::open_end(const Street& s, const std::vector<Vec2>& line, const Example* example, bool mirror) {
    const VertexId v = add_vertex(line.back());
    add_street(s.from, v, line, s.highway);
    if (!example) return;
    const double arriving = angle_of(line.back() - line[line.size() - 2]);
    for (const Branch& b : example->branches) queue_branch(v, arriving, b, mirror, s.highway, s.generation + 1);
}

void Tracer::queue_branch(VertexId from, double arriving, const Branch& branch, bool mirror, HighwayClass own, std::size_t generation,
                          bool through) {
    Street next;
    next.from = from;
    next.heading = arriving + (mirror ? -branch.turn : branch.turn);
    next.length = branch.length;
    next.shape = branch.shape;
    if (mirror) {
        for (Vec2& q : next.shape) q.y() = -q.y();
    }
    next.highway = branch.keeps_class ? own : branch.highway;
    next.main = main_class(next.highway);
    next.generation = generation;
    next.through = through;
    next.order = order_++;
    queue_.push(std::move(next));
}

void Tracer::retry(const Street& s) {
    Street again = s;
    ++again.retries;
    const double step = (again.retries + 1) / 2 * (M_PI / 30); // 6, 6, 12, 12, ... degrees
    again.heading = s.heading + (again.retries % 2 ? step : -step);
    again.length = std::max(s.min_length, s.length * std::uniform_real_distribution<double>(0.7, 1.3)(rng_));
    again.order = order_++;
    queue_.push(std::move(again));
}

void Tracer::trace(const Street& s) {
    if (degree(s.from) >= 4) return;
    if (s.closes_corner && !corner_at(s.from)) return; // the other street closed it first
    std::vector<Vec2> line = lay(s);
    if (line.size() < 2 || clearance(s.from, line[1] - line[0]) < min_angle_) return;
    if (s.closes_corner) {
        // It goes on until the first street it meets, or not at all: a street that ended
        // in the open would open a junction there, and corners with it. It is let on up to a
        // quarter again the city's density where it would end (corner_slack): it makes the
        // junction the corner was meant to be.
        std::vector<Vec2> reach = line;
        if (const auto hit = first_hit(line, s.from)) {
            reach.resize(hit->piece + 1);
            reach.push_back(hit->where);
        }
        if (s.generation > 0 && denser_than_city(reach, corner_slack)) {
            ++report_.dense;
            return;
        }
        if (settle(s, line) == Settled::joined) ++report_.closed_corners;
        else drop();
        return;
    }
    // A street is traced only where the streets around are not yet as dense as the city's;
    // the streets that join the city always are. A street going on across a crossing is let
    // on up to half again the city's density: it turns a T-junction into the crossing the
    // city would have there, and without it a grid grows staggered T's. (The first street
    // on from a street's end was let on whatever the density, so that a street ended in a
    // dead end only where the city's junctions have them; with a dead end left so going on
    // straight to the street it meets (close_corner), it is held to the density too, but for
    // the street on from a street of the base: a street of the city continued into the region
    // and ended there would be a stub, cut when growth ends.)
    const std::size_t held_from = s.generation > 1 ? 1 : 2;
    if (s.generation > 0 && degree(s.from) >= held_from && denser_than_city(line, s.through ? 1.5 : 1.0)) {
        ++report_.dense;
        if (degree(s.from) == 1) {
            if (dense_end_.size() <= static_cast<std::size_t>(s.from)) dense_end_.resize(g_.vertex_count(), 0);
            dense_end_[static_cast<std::size_t>(s.from)] = 1;
        }
        return;
    }
    // Where the example is a bend of the street (a junction with one street on, of the same
    // class), the street goes on without a junction: a vertex of degree two would only
    // split one street in two. `open` is the line up to its last such bend.
    std::vector<Vec2> open;
    for (int bends = 0;; ++bends) {
        const Settled settled = settle(s, line);
        if (settled == Settled::joined) return;
        const double crowd = spacing(crowd_ * typical_);
        if (settled == Settled::dropped || nearest_vertex(line.back(), crowd, s.from)) {
            // Dropped: it ends at its last bend, if it had one.
            if (!open.empty() && !nearest_vertex(open.back(), crowd, s.from)) open_end(s, open, nullptr, false);
            else if (s.generation == 0 && s.retries < 8) retry(s);
            else drop();
            return;
        }
        const Example& example = example_for(s.main);
        const bool mirror = std::bernoulli_distribution(0.5)(rng_);
        if (bends < 16 && example.branches.size() == 1 && (example.branches.front().keeps_class || example.branches.front().highway == s.highway)) {
            const Branch& b = example.branches.front();
            Street on = s;
            on.heading = angle_of(line.back() - line[line.size() - 2]) + (mirror ? -b.turn : b.turn);
            on.length = b.length;
            on.shape = b.shape;
            if (mirror) {
                for (Vec2& q : on.shape) q.y() = -q.y();
            }
            std::vector<Vec2> piece = lay_from(line.back(), on);
            open = line;
            line.insert(line.end(), piece.begin() + 1, piece.end());
            continue;
        }
        open_end(s, line, &example, mirror);
        return;
    }
}

bool Tracer::corner_at(VertexId v) const {
    if (static_cast<std::size_t>(v) < base_vertices_ || degree(v) < 1 || degree(v) > 2) return false;
    // A dead end where the density stopped the street on (not one of the city's own).
    if (degree(v) == 1) return static_cast<std::size_t>(v) < dense_end_.size() && dense_end_[static_cast<std::size_t>(v)];
    const auto& at = adjacency_[static_cast<std::size_t>(v)];
    const Vec2 p = g_.positions[static_cast<std::size_t>(v)];
    const Vec2 a = (leaving(g_, at[0], v) - p).normalized(), b = (leaving(g_, at[1], v) - p).normalized();
    return a.dot(b) > -std::cos(M_PI / 4); // a turn of more than 45 degrees
}

void Tracer::close_corner(VertexId v, std::size_t generation) {
    // A junction opened at a street's end of which one street on was laid, turning off, is a
    // corner: the city's streets turn one without a junction seldom (Rome's a few times in
    // ten km, its grown streets five times as often). One of its two streets goes on
    // straight across it, to the first street it meets, and the corner is a T-junction; a
    // dead end goes on the same way.
    const auto i = static_cast<std::size_t>(v);
    if (corner_tried_.size() <= i) corner_tried_.resize(g_.vertex_count(), 0);
    if (corner_tried_[i] || !corner_at(v)) return;
    corner_tried_[i] = 1;
    const auto& at = adjacency_[i];
    const Vec2 p = g_.positions[i];
    // The street laid on from the junction first (the later street at v): going on straight
    // across, it is the street of the junction that was not laid.
    std::array<std::size_t, 2> order{0, 1};
    if (at.size() == 2 && at[0] < at[1]) std::swap(order[0], order[1]);
    for (const std::size_t k : order) {
        if (k >= at.size()) continue;
        Street on;
        on.from = v;
        on.heading = angle_of(p - leaving(g_, at[k], v));
        on.length = corner_reach * typical_;
        on.shape = {Vec2(0, 0), Vec2(1, 0)};
        on.highway = g_.edge_highway[static_cast<std::size_t>(at[k])];
        on.main = main_class(on.highway);
        on.generation = generation;
        on.closes_corner = true;
        on.order = order_++;
        queue_.push(std::move(on));
    }
}

void Tracer::close_corners() {
    for (std::size_t i = base_vertices_; i < g_.vertex_count(); ++i) close_corner(static_cast<VertexId>(i), std::numeric_limits<std::size_t>::max() / 2);
}

bool Tracer::open_empty_ground() {
    if (empty_share_ >= 1.0) return false;
    const double cell = typical_, far = empty_reach * typical_;
    const Eigen::AlignedBox2d box = bounds(region_.begin(), region_.end());
    const double size = box.diagonal().norm();
    // The region's empty places, farthest from a street first.
    std::vector<std::pair<double, Vec2>> empty;
    std::size_t all = 0;
    for (double y = box.min().y() + 0.5 * cell; y < box.max().y(); y += cell) {
        for (double x = box.min().x() + 0.5 * cell; x < box.max().x(); x += cell) {
            const Vec2 p(x, y);
            if (!inside(region_, p)) continue;
            ++all;
            if (nearest_street(p, far, -1)) continue;
            double d = 2.0 * far;
            while (d < 2.0 * size && !nearest_street(p, d, -1)) d *= 2.0;
            const std::optional<Near> near = nearest_street(p, d, -1);
            if (near) empty.push_back({(near->where - p).norm(), p});
        }
    }
    // As much empty ground as around the region is left empty.
    if (empty.empty() || static_cast<double>(empty.size()) <= empty_share_ * static_cast<double>(all)) return false;
    std::sort(empty.begin(), empty.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
    std::vector<Vec2> opened;
    for (const auto& place : empty) {
        const double d = place.first;
        const Vec2 p = place.second;
        // One street into each empty place a round: those near it wait for the next round.
        if (std::any_of(opened.begin(), opened.end(), [&](const Vec2& o) { return (o - p).norm() < 2.0 * d; })) continue;
        const std::optional<Near> near = nearest_street(p, 1.01 * d, -1);
        if (!near || !inside(region_, near->where)) continue;
        // From a junction there: the vertex near it, or a new one on a grown street.
        VertexId from = -1;
        if (const auto v = nearest_vertex(near->where, crowd_ * typical_, -1)) {
            if (degree(*v) >= 4 || static_cast<std::size_t>(*v) < base_vertices_) continue;
            from = *v;
        } else {
            if (static_cast<std::size_t>(near->edge) < fixed_edges_) continue;
            from = split(near->edge, near->where);
        }
        const Vec2 ahead = (p - g_.positions[static_cast<std::size_t>(from)]).normalized();
        if (clearance(from, ahead) < min_angle_) continue;
        // Shaped and as long as one of the city's side streets.
        const Example& example = example_for(false);
        Street s;
        s.from = from;
        s.heading = angle_of(ahead);
        s.length = typical_;
        s.shape = {Vec2(0, 0), Vec2(1, 0)};
        s.highway = common_class_;
        if (!example.branches.empty()) {
            const Branch& b = example.branches[std::uniform_int_distribution<std::size_t>(0, example.branches.size() - 1)(rng_)];
            s.length = b.length;
            s.shape = b.shape;
        }
        s.generation = 1;
        s.order = order_++;
        queue_.push(std::move(s));
        opened.push_back(p);
        ++report_.empty_ground;
    }
    return !opened.empty();
}

bool Tracer::join_offset(EdgeId link, const std::array<EdgeId, 2>& sides) {
    const auto ends = g_.edges[static_cast<std::size_t>(link)];
    // The longer side street moved first: bent to end the link's length along, it turns less.
    std::array<std::size_t, 2> order{0, 1};
    if (g_.edge_length(sides[1]) > g_.edge_length(sides[0])) std::swap(order[0], order[1]);
    for (const std::size_t k : order) {
        const VertexId u = ends[k], t = ends[1 - k];
        const EdgeId side = sides[k];
        // A main road keeps its line; the street the side street leaves from stays as it is.
        if (static_cast<std::size_t>(side) < fixed_edges_ || main_class(g_.edge_highway[static_cast<std::size_t>(side)])) continue;
        const VertexId far = other_end(side, u);
        if (far == u || far == t || adjacent(far, t)) continue;
        std::vector<Vec2> line = warped(line_from(side, far), g_.positions[static_cast<std::size_t>(t)]);
        if (clearance(t, line[line.size() - 2] - line.back()) < min_angle_ || first_hit(line, far, t, side)) continue;
        move_end(side, u, t, std::move(line));
        return true;
    }
    return false;
}

void Tracer::offset_crossings() {
    const double room = std::max(shortest_, 1.0);
    std::vector<VertexId> crossings;
    for (std::size_t i = base_vertices_; i < g_.vertex_count(); ++i) {
        if (degree(static_cast<VertexId>(i)) == 4) crossings.push_back(static_cast<VertexId>(i));
    }
    // The grown offset crossings: their T's as near as the city's (crowd_ typical streets).
    std::vector<std::pair<double, EdgeId>> links;
    for (std::size_t e = fixed_edges_; e < g_.edge_count(); ++e) {
        const auto [a, b] = g_.edges[e];
        if (static_cast<std::size_t>(a) < base_vertices_ || static_cast<std::size_t>(b) < base_vertices_) continue;
        const double length = g_.edge_length(static_cast<EdgeId>(e));
        if (length < crowd_ * typical_ && offset_sides(g_, adjacency_, static_cast<EdgeId>(e))) links.emplace_back(length, static_cast<EdgeId>(e));
    }
    // Of the crossings and offset crossings grown, as many offset as in the city: where more
    // grew (two streets traced to one street from either side, each ending where it met it),
    // the two T's of the nearest become one crossing, one side street moved along to the other
    // T, where it then crosses nothing; where fewer, crossings are offset (below).
    const double all = static_cast<double>(links.size() + crossings.size());
    std::sort(links.begin(), links.end());
    std::size_t offset = links.size();
    for (const auto& [length, link] : links) {
        if (static_cast<double>(offset) <= offset_share_ * all + 0.5) break;
        // (Each checked again: a join before it may have changed its T's.)
        const auto sides = offset_sides(g_, adjacency_, link);
        if (sides && join_offset(link, *sides)) {
            --offset;
            ++report_.joined_offsets;
        }
    }
    if (offsets_.empty() || offset_share_ <= 0.0) return;
    std::shuffle(crossings.begin(), crossings.end(), rng_);
    // Each one made turns a crossing into two T's: made as the city's share of the crossings.
    // (Made only up to the city's share of the crossings and offset ones together, the
    // offset links grown already taken off, Porto's grown hole differed more from its real one:
    // compare distance 1.39-1.54x its ring's against 1.37-1.49x.)
    const double wanted = offset_share_ * static_cast<double>(crossings.size());
    // The side street `side` moved d metres along `along` from v, where it then crosses nothing.
    auto move = [&](VertexId v, EdgeId side, EdgeId along, double d) {
        // (One street twice at v is a loop: nothing to move along.) A main road keeps its line:
        // the side street that moves is one of the streets between them.
        if (side == along || static_cast<std::size_t>(side) < fixed_edges_ || static_cast<std::size_t>(along) < fixed_edges_ ||
            main_class(g_.edge_highway[static_cast<std::size_t>(side)])) {
            return false;
        }
        if (g_.edge_length(along) < d + room) return false;
        const std::optional<Vec2> where = point_along(line_from(along, v), d);
        if (!where || !inside(region_, *where) || nearest_vertex(*where, 0.5 * d, v)) return false;
        // The side street from its far end, bent to end there.
        const VertexId far = other_end(side, v);
        std::vector<Vec2> line = warped(line_from(side, far), *where);
        if (first_hit(line, far, v, side)) return false;
        move_end(side, v, split(along, *where), std::move(line));
        return true;
    };
    for (const VertexId v : crossings) {
        if (static_cast<double>(report_.offset_crossings) + 0.5 > wanted) break;
        const auto& at = adjacency_[static_cast<std::size_t>(v)];
        if (at.size() != 4) continue;
        const Vec2 pv = g_.positions[static_cast<std::size_t>(v)];
        // The four streets as two straight pairs: each with the one most nearly opposite it.
        std::array<Vec2, 4> out;
        for (std::size_t k = 0; k < 4; ++k) out[k] = (leaving(g_, at[k], v) - pv).normalized();
        std::size_t opposite = 1;
        for (std::size_t k = 2; k < 4; ++k) {
            if (out[0].dot(out[k]) < out[0].dot(out[opposite])) opposite = k;
        }
        std::array<std::size_t, 2> rest{};
        for (std::size_t k = 1, r = 0; k < 4; ++k) {
            if (k != opposite) rest[r++] = k;
        }
        const double straight = -std::cos(M_PI / 6);
        if (out[0].dot(out[opposite]) > straight || out[rest[0]].dot(out[rest[1]]) > straight) continue;
        // Which street goes through, which side street moves, which way along: the eight ways
        // in a random order, until one fits.
        const std::array<std::array<std::size_t, 2>, 2> pairs = {{{0, opposite}, rest}};
        std::array<std::size_t, 8> ways{0, 1, 2, 3, 4, 5, 6, 7};
        std::shuffle(ways.begin(), ways.end(), rng_);
        const double d = offsets_[std::uniform_int_distribution<std::size_t>(0, offsets_.size() - 1)(rng_)];
        for (const std::size_t w : ways) {
            const auto& crossed = pairs[w & 1];
            const auto& sides = pairs[1 - (w & 1)];
            if (move(v, at[sides[(w >> 1) & 1]], at[crossed[(w >> 2) & 1]], d)) {
                ++report_.offset_crossings;
                break;
            }
        }
    }
}

void Tracer::junction_islands() {
    const double room = std::max(shortest_, 1.0);
    std::vector<VertexId> candidates;
    for (std::size_t i = base_vertices_; i < g_.vertex_count(); ++i) {
        if (degree(static_cast<VertexId>(i)) == 3) candidates.push_back(static_cast<VertexId>(i));
    }
    for (const VertexId v : candidates) {
        const auto& at = adjacency_[static_cast<std::size_t>(v)];
        if (at.size() != 3) continue;
        const Vec2 pv = g_.positions[static_cast<std::size_t>(v)];
        std::array<Vec2, 3> out;
        for (std::size_t k = 0; k < 3; ++k) out[k] = (leaving(g_, at[k], v) - pv).normalized();
        const std::optional<TShape> t = t_shape(out);
        if (!t) continue;
        // Not where the corner is cut already.
        if (adjacent(other_end(at[t->side], v), other_end(at[t->near], v))) continue;
        const std::size_t kind = main_class(g_.edge_highway[static_cast<std::size_t>(at[t->near])]) ? 1 : 0;
        const std::size_t bin = island_bin(t->corner);
        if (!std::bernoulli_distribution(std::min(0.5, island_rate_[kind][bin]))(rng_)) continue;
        // The sides of one of the city's islands at a corner like this one (the nearest bin
        // that has any, of the same kind of street where it has any).
        const std::vector<std::pair<double, double>>* like = nullptr;
        for (const std::size_t k : {kind, 1 - kind}) {
            for (std::size_t step = 0; step < island_bins && !like; ++step) {
                for (const std::size_t b : {bin + step, bin - step}) {
                    if (b < island_bins && !islands_[k][b].empty()) {
                        like = &islands_[k][b];
                        break;
                    }
                }
            }
        }
        if (!like) continue;
        const auto [d_side, d_through] = (*like)[std::uniform_int_distribution<std::size_t>(0, like->size() - 1)(rng_)];
        const EdgeId side_edge = at[t->side], through_edge = at[t->near];
        if (side_edge == through_edge || static_cast<std::size_t>(side_edge) < fixed_edges_ || static_cast<std::size_t>(through_edge) < fixed_edges_) continue;
        if (g_.edge_length(side_edge) < d_side + room || g_.edge_length(through_edge) < d_through + room) continue;
        const std::optional<Vec2> q = point_along(line_from(side_edge, v), d_side), r = point_along(line_from(through_edge, v), d_through);
        if (!q || !r || !inside(region_, *q) || !inside(region_, *r)) continue;
        const double near = 0.5 * std::min(d_side, d_through);
        if (nearest_vertex(*q, near, v) || nearest_vertex(*r, near, v)) continue;
        if (0.5 * std::abs(cross(*q - pv, *r - pv)) < s_.min_block_m2) continue;
        // The new street meets both at 20 degrees or more and crosses nothing.
        const Vec2 link = (*r - *q).normalized();
        if (std::abs(link.dot((pv - *q).normalized())) > std::cos(M_PI / 9) || std::abs(link.dot((pv - *r).normalized())) > std::cos(M_PI / 9)) continue;
        const std::vector<Vec2> line{*q, *r};
        if (first_hit(line, v, v)) continue;
        const HighwayClass highway = g_.edge_highway[static_cast<std::size_t>(side_edge)];
        const VertexId x = split(side_edge, *q);
        const VertexId y = split(through_edge, *r);
        add_street(x, y, line, highway);
        ++report_.junction_islands;
    }
}

} // namespace tracing

double street_length_within(const GeometricGraph& g, const spatial::RTree<spatial::EdgeEntry>& segments, const Vec2& centre, double r) {
    double length = 0.0;
    for (auto it = segments.qbegin(spatial::bgi::intersects(spatial::around(centre, r))); it != segments.qend(); ++it) {
        const Vec2* q = g.geometry_begin(it->second);
        for (std::size_t i = 0; i + 1 < g.geometry_size(it->second); ++i) length += piece_within(q[i], q[i + 1], centre, r);
    }
    return length;
}

TracingReport trace_streets(GeometricGraph& g, std::size_t base_vertices, const GeometricGraph& city,
                            const std::vector<Vec2>& region, const TracingSettings& settings, std::mt19937_64& rng,
                            const ProgressCallback& progress) {
    return tracing::Tracer(g, base_vertices, city, region, settings, rng, progress).run();
}

} // namespace ggg::growth_detail
