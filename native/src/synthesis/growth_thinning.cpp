// Grown junctions thinned to the city's density (street_cleanup.hpp). Streets traced one at a
// time each end where they run into another: every such end is a T-junction, and where many
// streets arrive from both sides of one, its blocks are cut into slivers by rungs between
// streets that already run side by side. A rung is the street the city would not have there.
#include <algorithm>
#include <array>
#include <cmath>
#include <deque>

#include "street_cleanup.hpp"
#include "tracing_stages.hpp"

#include "ggg/graph/plane_geometry.hpp"
#include "ggg/graph/planar_faces.hpp"

namespace ggg::growth_detail {

namespace {

// How far round a rung the other way between its ends is looked for (as a share of the radius
// the density is measured in): a rung with no other way near is a street's only link, kept.
constexpr double kDetourReach = 2.0;
constexpr std::size_t kDetourVertices = 4096;

} // namespace

std::size_t thin_junctions(GeometricGraph& g, std::size_t base_vertices, std::size_t base_edges, const std::vector<Vec2>& region,
                           double junction_density, double radius) {
    if (junction_density <= 0.0 || radius <= 0.0 || region.size() < 3) return 0;
    const std::size_t n = g.vertex_count();
    const std::vector<std::vector<EdgeId>> at = tracing::streets_at(g);
    auto other = [&](EdgeId e, VertexId v) {
        const auto [a, b] = g.edges[static_cast<std::size_t>(e)];
        return a == v ? b : a;
    };
    std::vector<char> dropped(g.edge_count(), 0);
    std::vector<std::size_t> degree(n, 0);
    for (std::size_t v = 0; v < n; ++v) degree[v] = at[v].size();
    // The junctions in the region, against as many as the city has on as much ground.
    std::vector<VertexId> junctions;
    for (std::size_t v = 0; v < n; ++v) {
        if (degree[v] >= 3 && inside(region, g.positions[v])) junctions.push_back(static_cast<VertexId>(v));
    }
    const double area = std::abs(ring_area(region.data(), region.data() + region.size()));
    std::size_t count = junctions.size();
    const auto wanted = static_cast<std::size_t>(std::ceil(junction_density * area));
    if (count <= wanted) return 0;
    const double local_cap = junction_density * M_PI * radius * radius;
    auto junctions_near = [&](const Vec2& centre) {
        std::size_t k = 0;
        for (const VertexId v : junctions) {
            if (degree[static_cast<std::size_t>(v)] >= 3 && (g.positions[static_cast<std::size_t>(v)] - centre).norm() < radius) ++k;
        }
        return k;
    };
    // A rung: a grown street of the minor classes between two grown T-junctions, inside the
    // region, the stem of both (the other two streets of each run on through it), not a side
    // of a triangle (a junction island is the city's own).
    auto is_rung = [&](EdgeId e) {
        const auto [a, b] = g.edges[static_cast<std::size_t>(e)];
        if (static_cast<std::size_t>(e) < base_edges || static_cast<std::size_t>(a) < base_vertices || static_cast<std::size_t>(b) < base_vertices) return false;
        if (tracing::main_class(g.edge_highway[static_cast<std::size_t>(e)])) return false;
        for (const VertexId v : {a, b}) {
            if (degree[static_cast<std::size_t>(v)] != 3 || !inside(region, g.positions[static_cast<std::size_t>(v)])) return false;
            std::array<EdgeId, 3> es{};
            std::size_t k = 0;
            for (const EdgeId f : at[static_cast<std::size_t>(v)]) {
                if (!dropped[static_cast<std::size_t>(f)]) es[k++] = f;
            }
            std::array<Vec2, 3> out;
            const Vec2 pv = g.positions[static_cast<std::size_t>(v)];
            for (std::size_t i = 0; i < 3; ++i) out[i] = (tracing::leaving(g, es[i], v) - pv).normalized();
            const std::optional<tracing::TShape> t = tracing::t_shape(out);
            if (!t || es[t->side] != e) return false;
        }
        for (const EdgeId f : at[static_cast<std::size_t>(a)]) {
            if (dropped[static_cast<std::size_t>(f)] || f == e) continue;
            for (const EdgeId h : at[static_cast<std::size_t>(b)]) {
                if (!dropped[static_cast<std::size_t>(h)] && h != e && other(f, a) == other(h, b)) return false;
            }
        }
        return true;
    };
    // Another way between its ends, near it: taking it out then leaves every street joined.
    auto detour = [&](EdgeId e) {
        const auto [a, b] = g.edges[static_cast<std::size_t>(e)];
        const Vec2 centre = 0.5 * (g.positions[static_cast<std::size_t>(a)] + g.positions[static_cast<std::size_t>(b)]);
        std::vector<char> seen(n, 0);
        std::deque<VertexId> queue{a};
        seen[static_cast<std::size_t>(a)] = 1;
        for (std::size_t visited = 0; !queue.empty() && visited < kDetourVertices; ++visited) {
            const VertexId v = queue.front();
            queue.pop_front();
            for (const EdgeId f : at[static_cast<std::size_t>(v)]) {
                if (f == e || dropped[static_cast<std::size_t>(f)]) continue;
                const VertexId w = other(f, v);
                if (w == b) return true;
                if (seen[static_cast<std::size_t>(w)] || (g.positions[static_cast<std::size_t>(w)] - centre).norm() > kDetourReach * radius) continue;
                seen[static_cast<std::size_t>(w)] = 1;
                queue.push_back(w);
            }
        }
        return false;
    };
    // The most crowded places first, and there the shortest rungs (the narrowest slivers).
    struct Candidate {
        EdgeId e;
        std::size_t near;
        double length;
    };
    std::vector<Candidate> candidates;
    for (std::size_t e = base_edges; e < g.edge_count(); ++e) {
        if (!is_rung(static_cast<EdgeId>(e))) continue;
        const auto [a, b] = g.edges[e];
        const Vec2 centre = 0.5 * (g.positions[static_cast<std::size_t>(a)] + g.positions[static_cast<std::size_t>(b)]);
        candidates.push_back({static_cast<EdgeId>(e), junctions_near(centre), g.edge_length(static_cast<EdgeId>(e))});
    }
    std::sort(candidates.begin(), candidates.end(), [](const Candidate& l, const Candidate& r) {
        return l.near != r.near ? l.near > r.near : l.length < r.length;
    });
    std::size_t thinned = 0;
    for (const Candidate& c : candidates) {
        if (count <= wanted) break;
        if (!is_rung(c.e)) continue;
        const auto [a, b] = g.edges[static_cast<std::size_t>(c.e)];
        const Vec2 centre = 0.5 * (g.positions[static_cast<std::size_t>(a)] + g.positions[static_cast<std::size_t>(b)]);
        if (static_cast<double>(junctions_near(centre)) <= local_cap || !detour(c.e)) continue;
        dropped[static_cast<std::size_t>(c.e)] = 1;
        --degree[static_cast<std::size_t>(a)];
        --degree[static_cast<std::size_t>(b)];
        count -= 2;
        ++thinned;
    }
    if (thinned == 0) return 0;
    std::vector<Street> streets;
    for (std::size_t e = 0; e < g.edge_count(); ++e) {
        if (dropped[e]) continue;
        streets.push_back(street_of(g, static_cast<EdgeId>(e)));
    }
    g = rebuilt(g, std::vector<char>(n, 0), streets);
    return thinned;
}

} // namespace ggg::growth_detail
