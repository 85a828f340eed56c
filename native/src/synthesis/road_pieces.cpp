// The road surface of the city layout: its pieces, and the edges that cross without a
// junction (city_stages.hpp).
#include "city_stages.hpp"

#include <algorithm>
#include <numbers>

namespace ggg::city_detail {

Box box_of(const Vec2* begin, const Vec2* end) {
    Box b{{begin->x(), begin->y()}, {begin->x(), begin->y()}};
    for (auto p = begin; p != end; ++p) bg::expand(b, spatial::point(*p));
    return b;
}

void ccw(std::vector<Vec2>& ring) {
    if (ring_area(ring.data(), ring.data() + ring.size()) < 0) std::reverse(ring.begin(), ring.end());
}

void road_pieces(const GeometricGraph& g, const std::vector<double>& half, int sides, CityLayout& out, PieceIndex& where) {
    const std::size_t m = g.edge_count();
    std::vector<double> vertex_radius(g.vertex_count(), 0.0);
    std::vector<EdgeId> vertex_edge(g.vertex_count(), -1);
    auto better = [&](EdgeId a, EdgeId b) { // a more important than b at a junction
        const int ra = highway_rank(g.edge_highway[static_cast<std::size_t>(a)]);
        const int rb = highway_rank(g.edge_highway[static_cast<std::size_t>(b)]);
        return ra < rb || (ra == rb && half[static_cast<std::size_t>(a)] > half[static_cast<std::size_t>(b)]);
    };
    std::vector<Vec2> line, ring;
    where.edge_begin.assign(m + 1, 0);
    where.vertex_disc.assign(g.vertex_count(), -1);
    for (std::size_t e = 0; e < m; ++e) {
        where.edge_begin[e] = out.roads.size();
        const double h = half[e];
        const auto id = static_cast<EdgeId>(e);
        for (VertexId v : g.edges[e]) {
            auto& r = vertex_radius[static_cast<std::size_t>(v)];
            r = std::max(r, h);
            auto& best = vertex_edge[static_cast<std::size_t>(v)];
            if (best < 0 || better(id, best)) best = id;
        }
        line.clear();
        if (g.geometry_size(id) >= 2) {
            line.assign(g.geometry_begin(id), g.geometry_begin(id) + g.geometry_size(id));
        } else {
            line = {g.positions[static_cast<std::size_t>(g.edges[e][0])], g.positions[static_cast<std::size_t>(g.edges[e][1])]};
        }
        // Drop repeated points: a zero-length segment has no direction.
        line.erase(std::unique(line.begin(), line.end(), [](const Vec2& a, const Vec2& b) { return (a - b).norm() < 1e-6; }),
                   line.end());
        Vec2 previous_normal = Vec2::Zero();
        for (std::size_t k = 0; k + 1 < line.size(); ++k) {
            const Vec2 d = (line[k + 1] - line[k]).normalized();
            const Vec2 normal{-d.y() * h, d.x() * h};
            out.roads.add({line[k] - normal, line[k + 1] - normal, line[k + 1] + normal, line[k] + normal}, id);
            out.road_piece.push_back(RoadPiece::segment);
            if (k > 0) {
                // The outer side of the bend is the one the road turns away from; fill it so
                // that every point within h of the bend point is road (a mitre up to 120
                // degrees of turn, a polygon around the circle beyond), as the kerb inset
                // and the clearance of the buildings assume.
                const double turn = previous_normal.x() * normal.y() - previous_normal.y() * normal.x();
                if (std::abs(turn) > 1e-9 * h * h) {
                    const double side = turn > 0 ? -1.0 : 1.0;
                    const Vec2 a = side * previous_normal, b = side * normal;
                    const Vec2 bisector = (a + b).normalized();
                    const double cos_half = bisector.dot(a) / h;
                    ring.clear();
                    if (cos_half > 0.5) {
                        ring = {line[k], line[k] + a, line[k] + bisector * (h / cos_half), line[k] + b};
                    } else {
                        const double r = h / std::cos(std::numbers::pi / 8);
                        for (int j = 0; j < 8; ++j) {
                            const double angle = 2.0 * std::numbers::pi * (j + 0.5) / 8;
                            ring.push_back(line[k] + Vec2{r * std::cos(angle), r * std::sin(angle)});
                        }
                    }
                    ccw(ring);
                    out.roads.add(ring, id);
                    out.road_piece.push_back(RoadPiece::bend);
                }
            }
            previous_normal = normal;
        }
    }
    where.edge_begin[m] = out.roads.size();
    // Discs circumscribe the circle, so that they cover every rectangle's end.
    const double grow = 1.0 / std::cos(std::numbers::pi / sides);
    for (std::size_t v = 0; v < g.vertex_count(); ++v) {
        if (vertex_edge[v] < 0) continue;
        const double r = vertex_radius[v] * grow;
        ring.clear();
        for (int k = 0; k < sides; ++k) {
            const double a = 2.0 * std::numbers::pi * (k + 0.5) / sides;
            ring.push_back(g.positions[v] + Vec2{r * std::cos(a), r * std::sin(a)});
        }
        where.vertex_disc[v] = static_cast<std::int64_t>(out.roads.size());
        out.roads.add(ring, vertex_edge[v]);
        out.road_piece.push_back(RoadPiece::junction);
    }
}

using SegmentEntry = std::pair<Box, std::pair<EdgeId, std::uint32_t>>;

std::vector<char> crossing_edges(const GeometricGraph& g) {
    auto line = [&](EdgeId e) -> std::pair<const Vec2*, std::size_t> {
        if (g.geometry_size(e) >= 2) return {g.geometry_begin(e), g.geometry_size(e)};
        return {nullptr, 0};
    };
    auto point = [&](EdgeId e, std::uint32_t k) {
        const auto [pts, n] = line(e);
        if (n) return pts[k];
        return g.positions[static_cast<std::size_t>(g.edges[static_cast<std::size_t>(e)][k])];
    };
    std::vector<SegmentEntry> entries;
    for (std::size_t e = 0; e < g.edge_count(); ++e) {
        const auto id = static_cast<EdgeId>(e);
        const std::size_t n = std::max<std::size_t>(line(id).second, 2);
        for (std::uint32_t k = 0; k + 1 < n; ++k) {
            const Vec2 a = point(id, k), b = point(id, k + 1);
            entries.push_back({spatial::around(a, b), {id, k}});
        }
    }
    const spatial::RTree<SegmentEntry> tree(entries.begin(), entries.end());
    std::vector<char> crossing(g.edge_count(), 0);
    std::vector<SegmentEntry> hits;
    for (const auto& [box, id] : entries) {
        hits.clear();
        tree.query(bgi::intersects(box), std::back_inserter(hits));
        const Vec2 a = point(id.first, id.second), b = point(id.first, id.second + 1);
        for (const auto& [other_box, other] : hits) {
            if (other.first <= id.first) continue;
            const Vec2 c = point(other.first, other.second), d = point(other.first, other.second + 1);
            const Vec2 r = b - a, q = d - c;
            const double denominator = r.x() * q.y() - r.y() * q.x();
            if (std::abs(denominator) < 1e-12) continue;
            const Vec2 ac = c - a;
            const double t = (ac.x() * q.y() - ac.y() * q.x()) / denominator;
            const double u = (ac.x() * r.y() - ac.y() * r.x()) / denominator;
            constexpr double inside = 1e-6;
            if (t > inside && t < 1 - inside && u > inside && u < 1 - inside) {
                crossing[static_cast<std::size_t>(id.first)] = crossing[static_cast<std::size_t>(other.first)] = 1;
            }
        }
    }
    return crossing;
}

} // namespace ggg::city_detail
