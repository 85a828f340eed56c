// Grown streets joined to nothing given a street to the city (street_cleanup.hpp:
// join_grown_islands). A region no street of the base reaches (drawn a little away from the
// city, or beside a park its streets stop at) is grown from a rule placed in its middle, and
// what grows there stood apart: a district no one could drive to.
#include <algorithm>
#include <cmath>
#include <numeric>

#include "street_cleanup.hpp"
#include "tracing_stages.hpp"

#include "ggg/graph/plane_geometry.hpp"
#include "ggg/graph/spatial_index.hpp"

namespace ggg::growth_detail {

namespace {

constexpr double kSharp = 30.0;    // degrees: the new street meets the streets at its ends no sharper
constexpr std::size_t kNearest = 12; // city vertices tried for each grown vertex, nearest first

VertexId root_of(std::vector<VertexId>& parent, VertexId v) {
    while (parent[static_cast<std::size_t>(v)] != v) {
        parent[static_cast<std::size_t>(v)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(v)])];
        v = parent[static_cast<std::size_t>(v)];
    }
    return v;
}

// The narrowest angle (degrees) between direction d and the first pieces of the streets at v.
double narrowest_with(const GeometricGraph& g, const std::vector<EdgeId>& streets, VertexId v, const Vec2& d) {
    double narrowest = 180.0;
    for (const EdgeId e : streets) {
        const double c = std::clamp(first_piece(g, e, v).normalized().dot(d.normalized()), -1.0, 1.0);
        narrowest = std::min(narrowest, std::acos(c) * 180.0 / M_PI);
    }
    return narrowest;
}

} // namespace

std::size_t join_grown_islands(GeometricGraph& g, std::size_t base_vertices, std::size_t base_edges, double reach) {
    if (base_edges == 0 || g.edge_count() == base_edges || !(reach > 0)) return 0;
    std::vector<VertexId> parent(g.vertex_count());
    std::iota(parent.begin(), parent.end(), 0);
    for (const auto& [a, b] : g.edges) parent[static_cast<std::size_t>(root_of(parent, a))] = root_of(parent, b);
    const std::vector<std::vector<EdgeId>> streets = tracing::streets_at(g);
    // The city: every vertex joined to a street of the base.
    std::vector<char> city_root(g.vertex_count(), 0);
    for (std::size_t e = 0; e < base_edges; ++e) city_root[static_cast<std::size_t>(root_of(parent, g.edges[e][0]))] = 1;
    std::vector<spatial::VertexEntry> city_points;
    std::vector<std::vector<VertexId>> islands(g.vertex_count());
    for (std::size_t v = 0; v < g.vertex_count(); ++v) {
        if (streets[v].empty()) continue;
        const VertexId r = root_of(parent, static_cast<VertexId>(v));
        if (city_root[static_cast<std::size_t>(r)]) city_points.push_back({spatial::point(g.positions[v]), static_cast<VertexId>(v)});
        else if (v >= base_vertices) islands[static_cast<std::size_t>(r)].push_back(static_cast<VertexId>(v));
    }
    if (city_points.empty() || std::all_of(islands.begin(), islands.end(), [](const auto& island) { return island.empty(); })) return 0;
    namespace bgi = spatial::bgi;
    const spatial::RTree<spatial::VertexEntry> city(city_points.begin(), city_points.end());
    std::vector<spatial::EdgeEntry> entries;
    for (std::size_t e = 0; e < g.edge_count(); ++e) entries.push_back({spatial::edge_box(g, static_cast<EdgeId>(e)), static_cast<EdgeId>(e)});
    spatial::RTree<spatial::EdgeEntry> pieces(entries.begin(), entries.end());
    auto crosses_a_street = [&](const Vec2& p, const Vec2& q) {
        for (auto it = pieces.qbegin(bgi::intersects(spatial::around(p, q))); it != pieces.qend(); ++it) {
            const Vec2* r = g.geometry_begin(it->second);
            for (std::size_t i = 0; i + 1 < g.geometry_size(it->second); ++i) {
                if (segments_meet(p, q, r[i], r[i + 1])) return true;
            }
        }
        return false;
    };
    std::size_t joined = 0;
    for (const std::vector<VertexId>& island : islands) {
        if (island.empty()) continue;
        // The shortest street from the island to the city that crosses nothing and meets the
        // streets at both its ends at 30 degrees or more.
        struct Pair {
            double length;
            VertexId from, to;
        };
        std::vector<Pair> pairs;
        for (const VertexId u : island) {
            const Vec2 p = g.positions[static_cast<std::size_t>(u)];
            for (auto it = city.qbegin(bgi::nearest(spatial::point(p), static_cast<unsigned>(kNearest))); it != city.qend(); ++it) {
                const double length = (g.positions[static_cast<std::size_t>(it->second)] - p).norm();
                if (length > 0 && length <= reach) pairs.push_back({length, u, it->second});
            }
        }
        std::sort(pairs.begin(), pairs.end(), [](const Pair& a, const Pair& b) { return a.length < b.length; });
        for (const Pair& pair : pairs) {
            const Vec2 p = g.positions[static_cast<std::size_t>(pair.from)], q = g.positions[static_cast<std::size_t>(pair.to)];
            if (narrowest_with(g, streets[static_cast<std::size_t>(pair.from)], pair.from, q - p) < kSharp ||
                narrowest_with(g, streets[static_cast<std::size_t>(pair.to)], pair.to, p - q) < kSharp || crosses_a_street(p, q)) {
                continue;
            }
            // A street of the island's own kind.
            EdgeAttributes street = g.edge_attributes(streets[static_cast<std::size_t>(pair.from)].front());
            street.oneway = 0;
            street.way_id = 0;
            street.name.clear();
            const EdgeId e = g.add_edge(pair.from, pair.to, street);
            pieces.insert({spatial::edge_box(g, e), e});
            ++joined;
            break;
        }
    }
    return joined;
}

} // namespace ggg::growth_detail
