// What every stage of tracing queries and changes: the graph with its adjacency and its
// indexes, and the questions asked of them (what a line hits, what is near, whether a street
// would close a sliver of a block); see tracing_stages.hpp.
#include "tracing_stages.hpp"

#include <algorithm>

#include "ggg/graph/plane_geometry.hpp"

namespace ggg::growth_detail::tracing {

using namespace spatial; // bg, bgi, Point, Box, point, RTree, VertexEntry, EdgeEntry

void Tracer::index() {
    adjacency_.assign(g_.vertex_count(), {});
    for (std::size_t e = 0; e < g_.edge_count(); ++e) {
        const auto [a, b] = g_.edges[e];
        adjacency_[static_cast<std::size_t>(a)].push_back(static_cast<EdgeId>(e));
        adjacency_[static_cast<std::size_t>(b)].push_back(static_cast<EdgeId>(e));
        index_edge(static_cast<EdgeId>(e));
    }
    for (std::size_t v = 0; v < g_.vertex_count(); ++v) vertices_.insert({point(g_.positions[v]), static_cast<VertexId>(v)});
    double area = 0.0;
    for (std::size_t i = 0, j = region_.size() - 1; i < region_.size(); j = i++) area += cross(region_[j], region_[i]);
    expected_streets_ = std::max(1.0, 2.0 * std::abs(area) / 2.0 / (typical_ * typical_));
}

bool Tracer::denser_than_city(const std::vector<Vec2>& line, double slack) const {
    if (density_ <= 0.0 || line.size() < 2) return false;
    // The disc around the line's far end, two typical streets across: small enough to be
    // local, large enough to hold a block or two.
    const double r = 2.0 * typical_;
    const Vec2 centre = line.back();
    double length = 0.0;
    for (std::size_t k = 0; k + 1 < line.size(); ++k) length += piece_within(line[k], line[k + 1], centre, r);
    length += street_length_within(g_, segments_, centre, r);
    if (length > slack * density_ * M_PI * r * r) return true;
    // As many junctions as the city has there, too: streets as long as the city's between
    // them, not more and shorter ones that each end on the next.
    if (junction_density_ <= 0.0) return false;
    const std::size_t junctions = 1 + junctions_within(g_, vertices_, adjacency_, centre, r); // (its end may become one)
    return static_cast<double>(junctions) > slack * junction_density_ * M_PI * r * r;
}

void Tracer::move_end(EdgeId e, VertexId v, VertexId to, std::vector<Vec2> line) {
    const bool from_v = g_.edges[static_cast<std::size_t>(e)][0] == v;
    if (from_v) std::reverse(line.begin(), line.end());
    std::copy(line.begin(), line.end(), g_.geometry.begin() + static_cast<long>(g_.geometry_offsets[static_cast<std::size_t>(e)]));
    g_.edges[static_cast<std::size_t>(e)][from_v ? 0 : 1] = to;
    auto& at_v = adjacency_[static_cast<std::size_t>(v)];
    at_v.erase(std::find(at_v.begin(), at_v.end(), e));
    adjacency_[static_cast<std::size_t>(to)].push_back(e);
    index_edge(e);
}

bool Tracer::adjacent(VertexId v, VertexId w) const {
    for (const EdgeId e : adjacency_[static_cast<std::size_t>(v)]) {
        if (other_end(e, v) == w) return true;
    }
    return false;
}

double Tracer::clearance(VertexId v, const Vec2& d) const {
    double smallest = M_PI;
    const Vec2 pv = g_.positions[static_cast<std::size_t>(v)];
    for (const EdgeId e : adjacency_[static_cast<std::size_t>(v)]) {
        const Vec2 other = leaving(g_, e, v) - pv;
        smallest = std::min(smallest, std::abs(wrap(angle_of(other) - angle_of(d))));
    }
    return smallest;
}

std::optional<Tracer::Hit> Tracer::first_hit(const std::vector<Vec2>& line, VertexId from, VertexId to, EdgeId ignore) const {
    for (std::size_t k = 0; k + 1 < line.size(); ++k) {
        const Vec2 a = line[k], b = line[k + 1];
        Box box(point(a), point(a));
        bg::expand(box, point(b));
        std::optional<Hit> best;
        for (auto it = segments_.qbegin(bgi::intersects(box)); it != segments_.qend(); ++it) {
            const EdgeId e = it->second;
            if (e == ignore) continue;
            const auto [u, v] = g_.edges[static_cast<std::size_t>(e)];
            const bool at_from = u == from || v == from;
            const bool at_to = to >= 0 && (u == to || v == to);
            const Vec2* q = g_.geometry_begin(e);
            for (std::size_t i = 0; i + 1 < g_.geometry_size(e); ++i) {
                const auto m = segment_meeting(a, b, q[i], q[i + 1]);
                if (m) {
                    // Streets at this street's own ends meet it there, which is no crossing.
                    if ((at_from && k == 0 && m->first < 1e-6) || (at_to && k + 2 == line.size() && m->first > 1 - 1e-6)) continue;
                    if (!best || m->first < best->t) best = Hit{k, m->first, a + m->first * (b - a), e, i};
                } else if (segments_meet(a, b, q[i], q[i + 1])) {
                    // Overlapping (parallel) pieces: counted as meeting at this piece's start.
                    if ((at_from && k == 0) || (at_to && k + 2 == line.size())) continue;
                    if (!best) best = Hit{k, 0.0, a, e, i};
                }
            }
        }
        if (best) return best;
    }
    return std::nullopt;
}

bool Tracer::leaves_region(const std::vector<Vec2>& line, std::size_t from_piece) const {
    for (std::size_t k = from_piece; k < line.size(); ++k) {
        if (!inside(region_, line[k])) return true;
    }
    return false;
}

bool Tracer::enters_region(const std::vector<Vec2>& line) const {
    auto well_inside = [&](const Vec2& q) { return inside(region_, q) && distance_to_ring(region_, q) > 0.1 * typical_; };
    for (std::size_t k = 0; k + 1 < line.size(); ++k) {
        if (well_inside(0.5 * (line[k] + line[k + 1])) || well_inside(line[k + 1])) return true;
    }
    return false;
}

double Tracer::length_outside(const std::vector<Vec2>& line) const {
    double out = 0.0;
    for (std::size_t k = 0; k + 1 < line.size(); ++k) {
        // Each piece in eight steps: a piece may cross the border.
        const Vec2 d = (line[k + 1] - line[k]) / 8.0;
        for (int i = 0; i < 8; ++i) out += inside(region_, line[k] + (i + 0.5) * d) ? 0.0 : d.norm();
    }
    return out;
}

double Tracer::share_inside(const std::vector<Vec2>& line) const {
    double total = 0.0;
    for (std::size_t k = 0; k + 1 < line.size(); ++k) total += (line[k + 1] - line[k]).norm();
    return total > 0 ? 1.0 - length_outside(line) / total : 0.0;
}

bool Tracer::leaves_region_inside_line(const std::vector<Vec2>& line) const {
    for (std::size_t k = 1; k + 1 < line.size(); ++k) {
        if (!inside(region_, line[k])) return true;
    }
    return false;
}

bool Tracer::small_blocks(double left, double right) {
    auto below = [](double area, double floor) { return area > 0 && area < floor; };
    if (below(left, s_.min_block_m2) || below(right, s_.min_block_m2)) return true;
    if (left <= 0 && right <= 0) return false;
    const bool small = below(left, s_.usual_block_m2) || below(right, s_.usual_block_m2);
    if (small && static_cast<double>(small_blocks_closed_ + 1) > s_.small_block_share * static_cast<double>(blocks_closed_ + 1)) return true;
    ++blocks_closed_;
    if (small) ++small_blocks_closed_;
    return false;
}

bool Tracer::closes_small_block(VertexId v, VertexId w) {
    if (s_.min_block_m2 <= 0) return false;
    auto neighbours = [&](VertexId x) -> std::vector<VertexId> {
        std::vector<VertexId> out;
        for (const EdgeId e : adjacency_[static_cast<std::size_t>(x)]) out.push_back(other_end(e, x));
        if (x == v) out.push_back(w);
        if (x == w) out.push_back(v);
        return out;
    };
    return small_blocks(block_left_of(g_.positions, neighbours, v, w), block_left_of(g_.positions, neighbours, w, v));
}

bool Tracer::splits_small_block(VertexId v, EdgeId e, const Vec2& x) {
    const VertexId a = g_.edges[static_cast<std::size_t>(e)][0], b = g_.edges[static_cast<std::size_t>(e)][1];
    const auto x_id = static_cast<VertexId>(g_.vertex_count());
    std::vector<Vec2>& positions = g_.positions;
    positions.push_back(x);
    auto neighbours = [&](VertexId w) -> std::vector<VertexId> {
        std::vector<VertexId> out;
        if (w == x_id) return {a, b, v};
        for (const EdgeId f : adjacency_[static_cast<std::size_t>(w)]) {
            const VertexId o = other_end(f, w);
            if (f == e) out.push_back(x_id);
            else out.push_back(o);
        }
        if (w == v) out.push_back(x_id);
        return out;
    };
    const double left = block_left_of(positions, neighbours, v, x_id);
    const double right = block_left_of(positions, neighbours, x_id, v);
    positions.pop_back();
    return small_blocks(left, right);
}

std::optional<VertexId> Tracer::nearest_vertex(const Vec2& p, double within, VertexId besides) const {
    std::optional<VertexId> best;
    double best_d = within;
    const Box window = spatial::around(p, within);
    for (auto it = vertices_.qbegin(bgi::intersects(window)); it != vertices_.qend(); ++it) {
        const VertexId w = it->second;
        if (w == besides || degree(w) == 0) continue;
        const double d = (g_.positions[static_cast<std::size_t>(w)] - p).norm();
        if (d < best_d) best = w, best_d = d;
    }
    return best;
}

std::optional<Tracer::Near> Tracer::nearest_street(const Vec2& p, double within, VertexId besides) const {
    std::optional<Near> best;
    double best_d = within;
    const Box window = spatial::around(p, within);
    for (auto it = segments_.qbegin(bgi::intersects(window)); it != segments_.qend(); ++it) {
        const EdgeId e = it->second;
        const auto [a, b] = g_.edges[static_cast<std::size_t>(e)];
        if (a == besides || b == besides) continue;
        const Vec2* q = g_.geometry_begin(e);
        for (std::size_t i = 0; i + 1 < g_.geometry_size(e); ++i) {
            const Vec2 d = q[i + 1] - q[i];
            const double t = std::clamp((p - q[i]).dot(d) / std::max(d.squaredNorm(), 1e-300), 0.0, 1.0);
            const Vec2 x = q[i] + t * d;
            const double dist = (x - p).norm();
            if (dist < best_d) best = Near{e, x, i}, best_d = dist;
        }
    }
    return best;
}

VertexId Tracer::add_vertex(const Vec2& p) {
    const VertexId v = g_.add_vertex(p);
    adjacency_.emplace_back();
    vertices_.insert({point(p), v});
    return v;
}

void Tracer::add_street(VertexId v, VertexId w, const std::vector<Vec2>& line, HighwayClass highway) {
    EdgeAttributes attributes;
    attributes.highway = highway;
    const EdgeId e = g_.add_edge(v, w, attributes, line);
    adjacency_[static_cast<std::size_t>(v)].push_back(e);
    adjacency_[static_cast<std::size_t>(w)].push_back(e);
    index_edge(e);
    ++report_.streets;
    count_street(g_.positions[static_cast<std::size_t>(v)], g_.positions[static_cast<std::size_t>(w)]);
}

void Tracer::count_street(const Vec2& a, const Vec2& b) {
    ++streets_made_;
    if ((b - a).norm() < crowd_ * typical_) ++short_made_;
}

VertexId Tracer::split(EdgeId e, const Vec2& where) {
    const VertexId b = g_.edges[static_cast<std::size_t>(e)][1];
    const VertexId x = g_.split_edge(e, where);
    const auto second = static_cast<EdgeId>(g_.edge_count() - 1);
    adjacency_.emplace_back();
    vertices_.insert({point(where), x});
    auto& at_b = adjacency_[static_cast<std::size_t>(b)];
    std::replace(at_b.begin(), at_b.end(), e, second);
    adjacency_[static_cast<std::size_t>(x)] = {e, second};
    index_edge(second); // e stays indexed by its whole box, which holds its first half
    // One street more, as long as the shorter of the two halves.
    const Vec2 a_end = g_.positions[static_cast<std::size_t>(g_.edges[static_cast<std::size_t>(e)][0])];
    const Vec2 b_end = g_.positions[static_cast<std::size_t>(b)];
    count_street(where, (a_end - where).norm() < (b_end - where).norm() ? a_end : b_end);
    return x;
}

} // namespace ggg::growth_detail::tracing
