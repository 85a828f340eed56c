#include "ggg/graph/geometric_graph.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include "ggg/error.hpp"

namespace ggg {

VertexId GeometricGraph::add_vertex(const Vec2& position, std::int64_t osm_id) {
    const auto id = static_cast<VertexId>(positions.size());
    positions.push_back(position);
    vertex_osm_ids.push_back(osm_id);
    symbols.push_back(0);
    frames.push_back(Similarity2::from(1.0, 0.0, position));
    return id;
}

std::pair<const PendingRewrite*, const PendingRewrite*> GeometricGraph::more_rewrites_at(VertexId v) const {
    const auto [first, last] = std::equal_range(more_rewrites.begin(), more_rewrites.end(), PendingRewrite{v, 0, {}},
                                                [](const PendingRewrite& a, const PendingRewrite& b) { return a.vertex < b.vertex; });
    return {more_rewrites.data() + (first - more_rewrites.begin()), more_rewrites.data() + (last - more_rewrites.begin())};
}

void copy_more_rewrites(const GeometricGraph& from, VertexId v, GeometricGraph& to, VertexId w) {
    if (from.more_rewrites.empty()) return;
    const auto [first, last] = from.more_rewrites_at(v);
    for (const PendingRewrite* r = first; r != last; ++r) to.more_rewrites.push_back({w, r->symbol, r->frame});
}

std::uint32_t GeometricGraph::intern_name(const std::string& name) {
    if (name.empty()) return 0;
    if (name_lookup_size_ != names.size()) { // names was edited or copied in directly
        name_lookup_.clear();
        for (std::size_t i = 0; i < names.size(); ++i) {
            name_lookup_.emplace(names[i], static_cast<std::uint32_t>(i)); // the first of equal names wins
        }
    }
    const auto [it, inserted] = name_lookup_.emplace(name, static_cast<std::uint32_t>(names.size()));
    if (inserted) names.push_back(name);
    name_lookup_size_ = names.size();
    return it->second;
}

EdgeId GeometricGraph::add_edge(VertexId u, VertexId v, const EdgeAttributes& a,
                                const std::vector<Vec2>& polyline) {
    const auto id = static_cast<EdgeId>(edges.size());
    edges.push_back({u, v});
    edge_highway.push_back(a.highway);
    edge_oneway.push_back(a.oneway);
    edge_lanes.push_back(a.lanes);
    edge_width_m.push_back(a.width_m);
    edge_way_ids.push_back(a.way_id);
    edge_name_index.push_back(intern_name(a.name));
    if (polyline.size() >= 2) {
        geometry.insert(geometry.end(), polyline.begin(), polyline.end());
    } else {
        geometry.push_back(positions[static_cast<std::size_t>(u)]);
        geometry.push_back(positions[static_cast<std::size_t>(v)]);
    }
    geometry_offsets.push_back(static_cast<std::int64_t>(geometry.size()));
    return id;
}

VertexId GeometricGraph::split_edge(EdgeId e, const Vec2& where) {
    if (e < 0 || static_cast<std::size_t>(e) >= edges.size()) throw UsageError("split_edge: no edge " + std::to_string(e));
    if (!where.allFinite()) throw UsageError("split_edge: the point must be finite");
    const auto i = static_cast<std::size_t>(e);
    const EdgeAttributes attributes = edge_attributes(e);
    const VertexId b = edges[i][1];
    const std::size_t n = geometry_size(e);
    if (n == 2) {
        const VertexId x = add_vertex(where);
        edges[i][1] = x;
        geometry[static_cast<std::size_t>(geometry_offsets[i + 1] - 1)] = where;
        add_edge(x, b, attributes);
        return x;
    }
    // A polyline: split on its piece nearest to `where`. The points of e are stored between
    // those of its neighbours, so its first half is written in place and the rest shifted.
    const Vec2* p = geometry_begin(e);
    std::size_t piece = 0;
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k + 1 < n; ++k) {
        const Vec2 d = p[k + 1] - p[k];
        const double t = std::clamp((where - p[k]).dot(d) / std::max(d.squaredNorm(), 1e-300), 0.0, 1.0);
        const double distance = (p[k] + t * d - where).squaredNorm();
        if (distance < best) best = distance, piece = k;
    }
    std::vector<Vec2> second{where};
    second.insert(second.end(), p + piece + 1, p + n);
    const auto begin = static_cast<std::size_t>(geometry_offsets[i]);
    const std::size_t kept = piece + 2; // p[0] .. p[piece], where
    geometry[begin + piece + 1] = where;
    geometry.erase(geometry.begin() + static_cast<std::ptrdiff_t>(begin + kept), geometry.begin() + static_cast<std::ptrdiff_t>(begin + n));
    const auto removed = static_cast<std::int64_t>(n - kept);
    for (std::size_t k = i + 1; k < geometry_offsets.size(); ++k) geometry_offsets[k] -= removed;
    const VertexId x = add_vertex(where);
    edges[i][1] = x;
    add_edge(x, b, attributes, second);
    return x;
}

EdgeAttributes GeometricGraph::edge_attributes(EdgeId e) const {
    const auto i = static_cast<std::size_t>(e);
    return {edge_highway[i], edge_oneway[i], edge_lanes[i], edge_width_m[i], edge_way_ids[i],
            std::string(edge_name(e))};
}

double GeometricGraph::edge_length(EdgeId e) const {
    const Vec2* p = geometry_begin(e);
    const std::size_t n = geometry_size(e);
    double length = 0.0;
    for (std::size_t i = 1; i < n; ++i) length += (p[i] - p[i - 1]).norm();
    return length;
}

double GeometricGraph::total_length() const {
    double length = 0.0;
    for (std::size_t e = 0; e < edges.size(); ++e) length += edge_length(static_cast<EdgeId>(e));
    return length;
}

void GeometricGraph::reserve(std::size_t vertices, std::size_t edge_count_hint, std::size_t geometry_points) {
    positions.reserve(vertices);
    vertex_osm_ids.reserve(vertices);
    symbols.reserve(vertices);
    frames.reserve(vertices);
    edges.reserve(edge_count_hint);
    edge_highway.reserve(edge_count_hint);
    edge_oneway.reserve(edge_count_hint);
    edge_lanes.reserve(edge_count_hint);
    edge_width_m.reserve(edge_count_hint);
    edge_way_ids.reserve(edge_count_hint);
    edge_name_index.reserve(edge_count_hint);
    geometry_offsets.reserve(edge_count_hint + 1);
    geometry.reserve(geometry_points);
}

Adjacency::Adjacency(const GeometricGraph& g) {
    const std::size_t n = g.vertex_count();
    offsets.assign(n + 1, 0);
    for (const auto& e : g.edges) {
        ++offsets[static_cast<std::size_t>(e[0]) + 1];
        ++offsets[static_cast<std::size_t>(e[1]) + 1];
    }
    for (std::size_t v = 0; v < n; ++v) offsets[v + 1] += offsets[v];
    neighbors.resize(static_cast<std::size_t>(offsets[n]));
    edge_ids.resize(neighbors.size());
    std::vector<std::int64_t> fill(offsets.begin(), offsets.end() - 1);
    for (std::size_t i = 0; i < g.edges.size(); ++i) {
        const auto [u, v] = g.edges[i];
        auto& fu = fill[static_cast<std::size_t>(u)];
        neighbors[static_cast<std::size_t>(fu)] = v;
        edge_ids[static_cast<std::size_t>(fu++)] = static_cast<EdgeId>(i);
        auto& fv = fill[static_cast<std::size_t>(v)];
        neighbors[static_cast<std::size_t>(fv)] = u;
        edge_ids[static_cast<std::size_t>(fv++)] = static_cast<EdgeId>(i);
    }
}

std::string check_simple(const GeometricGraph& g) {
    const auto n = static_cast<VertexId>(g.vertex_count());
    std::vector<std::pair<VertexId, VertexId>> keys;
    keys.reserve(g.edge_count());
    for (std::size_t i = 0; i < g.edges.size(); ++i) {
        auto [u, v] = g.edges[i];
        std::ostringstream where;
        where << "edge " << i << " (" << u << ", " << v << ")";
        if (u < 0 || v < 0 || u >= n || v >= n) return where.str() + " has a vertex out of range";
        if (u == v) return where.str() + " is a self-loop";
        if (g.edge_length(static_cast<EdgeId>(i)) <= 0.0) return where.str() + " has zero length";
        const Vec2* p = g.geometry_begin(static_cast<EdgeId>(i));
        const std::size_t m = g.geometry_size(static_cast<EdgeId>(i));
        if (m < 2 || p[0] != g.positions[static_cast<std::size_t>(u)] ||
            p[m - 1] != g.positions[static_cast<std::size_t>(v)]) {
            return where.str() + " has a polyline that does not join its end vertices";
        }
        keys.emplace_back(std::min(u, v), std::max(u, v));
    }
    for (std::size_t i = 0; i < g.more_rewrites.size(); ++i) {
        const PendingRewrite& r = g.more_rewrites[i];
        std::ostringstream where;
        where << "pending rewrite " << i << " (vertex " << r.vertex << ")";
        if (r.vertex < 0 || r.vertex >= n) return where.str() + " has a vertex out of range";
        if (i > 0 && r.vertex < g.more_rewrites[i - 1].vertex) return where.str() + " is out of vertex order";
        if (r.symbol == 0 || g.symbols[static_cast<std::size_t>(r.vertex)] == 0) {
            return where.str() + " is not a nonterminal at a nonterminal vertex";
        }
        if (!std::isfinite(r.frame.a) || !std::isfinite(r.frame.b) || !r.frame.t.allFinite() || !(r.frame.scale() > 0)) {
            return where.str() + " has no valid frame";
        }
    }
    std::sort(keys.begin(), keys.end());
    const auto dup = std::adjacent_find(keys.begin(), keys.end());
    if (dup != keys.end()) {
        std::ostringstream s;
        s << "parallel edges between vertices " << dup->first << " and " << dup->second;
        return s.str();
    }
    return {};
}

} // namespace ggg
