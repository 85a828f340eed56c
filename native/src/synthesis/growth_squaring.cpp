// Grown T-junctions squared as often as the city's are square (street_cleanup.hpp:
// square_junctions). A traced street ends where it runs into another, at whatever angle it
// had: in a city whose side streets meet their streets square, a grown district then has
// T's a little askew (15 to 35 degrees off a right angle) that its city seldom has.
#include <algorithm>
#include <cmath>
#include <optional>

#include "street_cleanup.hpp"
#include "tracing_stages.hpp"

#include "ggg/graph/plane_geometry.hpp"
#include "ggg/graph/spatial_index.hpp"
#include "ggg/measures/network_comparison.hpp"

namespace ggg::growth_detail {

namespace {

constexpr double kStraightBar = 155.0; // degrees: the two streets of a T's bar run on through it
constexpr double kSquare = 15.0;       // off a right angle: square
constexpr double kAskew = 35.0;        // up to this: askew, and squared where the city has fewer
constexpr double kMostMove = 40.0;     // metres a junction may move along its bar
constexpr double kClear = 5.0;         // metres it stays from every other vertex
constexpr double kSharp = 30.0;        // degrees: a sharper corner is one growth does not make

double degrees_between(const Vec2& a, const Vec2& b) {
    return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) * 180.0 / M_PI;
}

// A T: the stem among three streets and how far it is off a right angle with the bar (the other
// two, running on through the junction); none where no two run on.
struct Tee {
    std::size_t stem = 0;
    double off = 0.0;
    Vec2 bar;
};

std::optional<Tee> tee_of(const std::array<Vec2, 3>& d) {
    for (std::size_t k = 0; k < 3; ++k) {
        const Vec2 &a = d[(k + 1) % 3], &b = d[(k + 2) % 3];
        if (degrees_between(a, b) < kStraightBar) continue;
        const Vec2 bar = (a.normalized() - b.normalized()).normalized();
        return Tee{k, std::abs(90.0 - degrees_between(bar, d[k])), bar};
    }
    return std::nullopt;
}

} // namespace

std::size_t square_junctions(GeometricGraph& g, std::size_t base_vertices, std::size_t base_edges, const std::vector<Vec2>& region) {
    if (region.size() < 3) return 0;
    const std::vector<std::vector<EdgeId>> arms = tracing::streets_at(g);
    auto tee_at = [&](VertexId v) -> std::optional<Tee> {
        const auto& at = arms[static_cast<std::size_t>(v)];
        if (at.size() != 3) return std::nullopt;
        // Read as `ggg compare` reads a junction's angles.
        return tee_of({leaving_direction(g, at[0], v), leaving_direction(g, at[1], v), leaving_direction(g, at[2], v)});
    };
    // The city's T's around the region (within its size of it): how many are square, how many
    // askew.
    Eigen::AlignedBox2d near = bounds(region.begin(), region.end());
    const double size = near.diagonal().norm();
    near.extend(near.min() - Vec2(size, size)).extend(near.max() + Vec2(size, size));
    std::size_t city_square = 0, city_askew = 0;
    for (std::size_t v = 0; v < base_vertices; ++v) {
        if (!near.contains(g.positions[v]) || inside(region, g.positions[v])) continue;
        const auto& at = arms[v];
        if (std::any_of(at.begin(), at.end(), [&](EdgeId e) { return static_cast<std::size_t>(e) >= base_edges; })) continue;
        if (const auto t = tee_at(static_cast<VertexId>(v))) {
            city_square += t->off <= kSquare;
            city_askew += t->off > kSquare && t->off <= kAskew;
        }
    }
    if (city_square + city_askew < 12) return 0; // too few to say
    const double city_share = static_cast<double>(city_askew) / static_cast<double>(city_square + city_askew);

    struct Candidate {
        VertexId v;
        Vec2 to;
        double move;
    };
    std::vector<Candidate> candidates;
    std::size_t grown_square = 0, grown_askew = 0;
    for (std::size_t v = base_vertices; v < g.vertex_count(); ++v) {
        const auto id = static_cast<VertexId>(v);
        if (!inside(region, g.positions[v])) continue;
        const auto t = tee_at(id);
        if (!t) continue;
        grown_square += t->off <= kSquare;
        if (!(t->off > kSquare && t->off <= kAskew)) continue; // NaN too: a street of no length
        ++grown_askew;
        const auto& at = arms[v];
        std::array<std::vector<Vec2>, 3> lines;
        for (std::size_t k = 0; k < 3; ++k) lines[k] = polyline_from(g, at[k], id);
        const std::size_t i = (t->stem + 1) % 3, j = (t->stem + 2) % 3;
        // Along the bar's own line where it is one straight piece through the junction (a base
        // street split there keeps its shape), else along its mean direction (grown streets only).
        const Vec2 along = (lines[i][1] - lines[j][1]).normalized();
        const bool straight = std::abs(cross(along, g.positions[v] - lines[j][1])) < 0.01;
        const bool on_base = static_cast<std::size_t>(at[i]) < base_edges || static_cast<std::size_t>(at[j]) < base_edges;
        if (static_cast<std::size_t>(at[t->stem]) < base_edges || (on_base && !straight)) continue;
        const Vec2 bar = straight ? along : t->bar;
        // Slid along its bar to below the stem's first bend, the junction is square.
        const double move = (lines[t->stem][1] - lines[t->stem][0]).dot(bar);
        const double room = std::min((lines[i][1] - g.positions[v]).norm(), (lines[j][1] - g.positions[v]).norm());
        if (!(std::abs(move) <= std::min(kMostMove, 0.8 * room))) continue;
        candidates.push_back({id, g.positions[v] + move * bar, std::abs(move)});
    }
    if (candidates.empty()) return 0;
    std::sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) { return a.move < b.move; });

    namespace bgi = spatial::bgi;
    std::vector<spatial::EdgeEntry> entries;
    for (std::size_t e = 0; e < g.edge_count(); ++e) entries.push_back({spatial::edge_box(g, static_cast<EdgeId>(e)), static_cast<EdgeId>(e)});
    const spatial::RTree<spatial::EdgeEntry> streets(entries.begin(), entries.end());
    std::vector<spatial::VertexEntry> points;
    for (std::size_t v = 0; v < g.vertex_count(); ++v) points.push_back({spatial::point(g.positions[v]), static_cast<VertexId>(v)});
    const spatial::RTree<spatial::VertexEntry> vertices(points.begin(), points.end());

    auto set_end = [&](EdgeId e, VertexId v, const Vec2& to) {
        const auto first = static_cast<std::size_t>(g.geometry_offsets[static_cast<std::size_t>(e)]);
        const std::size_t at = g.edges[static_cast<std::size_t>(e)][0] == v ? first : first + g.geometry_size(e) - 1;
        g.geometry[at] = to;
    };
    // The narrowest corner where the first piece of street e from v ends: between the streets
    // at its far vertex (their first pieces, as growth's own checks read a corner), or, where
    // it ends at a bend, between the piece and the next.
    auto narrowest_beyond = [&](EdgeId e, VertexId v) {
        const std::vector<Vec2> line = polyline_from(g, e, v);
        if (line.size() > 2) return degrees_between(line[0] - line[1], line[2] - line[1]);
        const auto [a, b] = g.edges[static_cast<std::size_t>(e)];
        const VertexId w = a == v ? b : a;
        double narrowest = 180.0;
        const auto& there = arms[static_cast<std::size_t>(w)];
        for (std::size_t x = 0; x < there.size(); ++x) {
            for (std::size_t y = x + 1; y < there.size(); ++y) {
                narrowest = std::min(narrowest, degrees_between(first_piece(g, there[x], w), first_piece(g, there[y], w)));
            }
        }
        return narrowest;
    };
    std::size_t squared = 0;
    for (const Candidate& c : candidates) {
        const auto total = static_cast<double>(grown_square + grown_askew);
        if (static_cast<double>(grown_askew) / total <= city_share) break;
        const Vec2 from = g.positions[static_cast<std::size_t>(c.v)];
        const auto& at = arms[static_cast<std::size_t>(c.v)];
        std::array<double, 3> corners{};
        for (std::size_t k = 0; k < 3; ++k) corners[k] = narrowest_beyond(at[k], c.v);
        // Moved, is it square, and do its streets' first pieces and itself keep clear of the
        // others (the indexes are of the graph as it was: what moved since, moved kMostMove at most)?
        g.positions[static_cast<std::size_t>(c.v)] = c.to;
        for (const EdgeId e : at) set_end(e, c.v, c.to);
        bool fits = false;
        if (const auto t = tee_at(c.v); t && t->off <= kSquare) {
            fits = true;
            for (auto it = vertices.qbegin(bgi::intersects(spatial::around(c.to, kClear + kMostMove))); it != vertices.qend() && fits; ++it) {
                fits = it->second == c.v || (g.positions[static_cast<std::size_t>(it->second)] - c.to).norm() > kClear;
            }
            // No corner where its streets' first pieces end made sharp (turned under 30 degrees).
            for (std::size_t k = 0; k < 3 && fits; ++k) fits = narrowest_beyond(at[k], c.v) >= std::min(corners[k], kSharp);
            for (std::size_t k = 0; k < 3 && fits; ++k) {
                const std::vector<Vec2> line = polyline_from(g, at[k], c.v);
                const Vec2 &p = line[0], &q = line[1];
                for (auto it = streets.qbegin(bgi::intersects(spatial::around(p, q, kMostMove + 1.0))); it != streets.qend() && fits; ++it) {
                    const EdgeId f = it->second;
                    if (std::find(at.begin(), at.end(), f) != at.end()) continue;
                    const Vec2* r = g.geometry_begin(f);
                    for (std::size_t i = 0; i + 1 < g.geometry_size(f) && fits; ++i) fits = !segments_meet(p, q, r[i], r[i + 1]);
                }
            }
        }
        if (!fits) {
            g.positions[static_cast<std::size_t>(c.v)] = from;
            for (const EdgeId e : at) set_end(e, c.v, from);
            continue;
        }
        ++squared;
        --grown_askew;
        ++grown_square;
    }
    return squared;
}

} // namespace ggg::growth_detail
