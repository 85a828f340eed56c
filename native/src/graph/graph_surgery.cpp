#include "ggg/graph/graph_surgery.hpp"

#include <string>

#include "ggg/error.hpp"

namespace ggg {

namespace {

void check_keep(const GeometricGraph& graph, const std::vector<bool>& keep) {
    if (keep.size() != graph.vertex_count()) {
        throw UsageError("keep: one entry per vertex of the graph is needed (" + std::to_string(graph.vertex_count()) +
                         "), got " + std::to_string(keep.size()));
    }
}

// Appends vertex v of `from` to `to` with its columns.
VertexId copy_vertex(const GeometricGraph& from, VertexId v, GeometricGraph& to) {
    const auto i = static_cast<std::size_t>(v);
    const VertexId w = to.add_vertex(from.positions[i], from.vertex_osm_ids[i]);
    to.symbols.back() = from.symbols[i];
    to.frames.back() = from.frames[i];
    copy_more_rewrites(from, v, to, w);
    if (!from.instances.empty() || !to.instances.empty()) {
        to.instances.resize(static_cast<std::size_t>(w), -1);
        to.instances.push_back(from.instance_of(v));
    }
    return w;
}

// Appends edge e of `from` to `to` between u and v (ids in `to`), with its attributes and polyline.
void copy_edge(const GeometricGraph& from, EdgeId e, VertexId u, VertexId v, GeometricGraph& to) {
    const Vec2* first = from.geometry_begin(e);
    to.add_edge(u, v, from.edge_attributes(e), std::vector<Vec2>(first, first + from.geometry_size(e)));
}

// Every vertex of `to` gets an instance entry once any has one (the column is all or nothing).
void complete_instances(GeometricGraph& to) {
    if (!to.instances.empty()) to.instances.resize(to.vertex_count(), -1);
}

// Appends the vertices v of `graph` with keep[v] to `to`, in order; returns each vertex's id in
// `to` (-1 where not kept) and adds the kept ones' ids in `graph` to `kept`.
std::vector<VertexId> copy_kept(const GeometricGraph& graph, const std::vector<bool>& keep, GeometricGraph& to,
                                std::vector<VertexId>& kept) {
    std::vector<VertexId> index(graph.vertex_count(), -1);
    for (std::size_t v = 0; v < graph.vertex_count(); ++v) {
        if (!keep[v]) continue;
        index[v] = copy_vertex(graph, static_cast<VertexId>(v), to);
        kept.push_back(static_cast<VertexId>(v));
    }
    return index;
}

} // namespace

Subgraph induced_subgraph(const GeometricGraph& graph, const std::vector<bool>& keep) {
    check_keep(graph, keep);
    Subgraph out;
    out.graph.origin = graph.origin;
    const std::vector<VertexId> index = copy_kept(graph, keep, out.graph, out.vertex_ids);
    for (std::size_t e = 0; e < graph.edge_count(); ++e) {
        const auto [a, b] = graph.edges[e];
        const VertexId u = index[static_cast<std::size_t>(a)], v = index[static_cast<std::size_t>(b)];
        if (u < 0 || v < 0) continue;
        copy_edge(graph, static_cast<EdgeId>(e), u, v, out.graph);
        out.edge_ids.push_back(static_cast<EdgeId>(e));
    }
    complete_instances(out.graph);
    return out;
}

Regrown with_grown(const GeometricGraph& graph, const std::vector<bool>& keep, const Subgraph& part,
                   const GeometricGraph& grown) {
    check_keep(graph, keep);
    const std::size_t part_vertices = part.vertex_ids.size(), part_edges = part.edge_ids.size();
    if (grown.vertex_count() < part_vertices || grown.edge_count() < part_edges) {
        throw UsageError("the grown graph does not start with the vertices and edges of the part it was grown from");
    }
    Regrown out;
    out.graph.origin = graph.origin;
    const std::vector<VertexId> index = copy_kept(graph, keep, out.graph, out.source_vertex);
    // A vertex of `grown`: one of the part (kept), else a new one after the kept.
    std::vector<VertexId> grown_index(grown.vertex_count(), -1);
    for (std::size_t i = 0; i < part_vertices; ++i) {
        const auto v = static_cast<std::size_t>(part.vertex_ids[i]);
        if (v >= graph.vertex_count() || !keep[v]) {
            throw UsageError("vertex " + std::to_string(v) + " of the part grown from is not kept");
        }
        grown_index[i] = index[v];
    }
    for (std::size_t i = part_vertices; i < grown.vertex_count(); ++i) {
        grown_index[i] = copy_vertex(grown, static_cast<VertexId>(i), out.graph);
        out.source_vertex.push_back(-1);
    }
    // The part's edges come back as the growth left them (split where a street meets one).
    std::vector<EdgeId> part_edge(graph.edge_count(), -1);
    for (std::size_t j = 0; j < part_edges; ++j) {
        const auto e = static_cast<std::size_t>(part.edge_ids[j]);
        if (e >= graph.edge_count()) throw UsageError("edge " + std::to_string(e) + " of the part is not in the graph");
        part_edge[e] = static_cast<EdgeId>(j);
    }
    auto copy_grown_edge = [&](std::size_t j) {
        const auto [a, b] = grown.edges[j];
        copy_edge(grown, static_cast<EdgeId>(j), grown_index[static_cast<std::size_t>(a)],
                  grown_index[static_cast<std::size_t>(b)], out.graph);
    };
    for (std::size_t e = 0; e < graph.edge_count(); ++e) {
        if (part_edge[e] >= 0) {
            copy_grown_edge(static_cast<std::size_t>(part_edge[e]));
            continue;
        }
        const auto [a, b] = graph.edges[e];
        const VertexId u = index[static_cast<std::size_t>(a)], v = index[static_cast<std::size_t>(b)];
        if (u >= 0 && v >= 0) copy_edge(graph, static_cast<EdgeId>(e), u, v, out.graph);
    }
    for (std::size_t j = part_edges; j < grown.edge_count(); ++j) copy_grown_edge(j);
    complete_instances(out.graph);
    return out;
}

} // namespace ggg
