#pragma once
// Cutting a graph down to some of its vertices and putting back what was grown on the cut:
// Grow into Region and Stitch Cities grow the streets of a road graph without its
// nonterminals (growth would take them for street vertices) and then need the whole graph
// again with the new streets. Every column follows its vertex or edge, so OSM ids, names,
// widths and polylines survive the round trip.
#include <vector>

#include "ggg/graph/geometric_graph.hpp"

namespace ggg {

// The part of a graph on some of its vertices, and where each of its vertices and edges was.
struct Subgraph {
    GeometricGraph graph;
    std::vector<VertexId> vertex_ids; // per vertex of `graph`, its id in the whole graph
    std::vector<EdgeId> edge_ids;     // per edge of `graph`, its id in the whole graph
};

// The vertices v of `graph` with keep[v] and the edges between them, in `graph`'s order, with
// every column. Throws UsageError when `keep` does not have one entry per vertex.
Subgraph induced_subgraph(const GeometricGraph& graph, const std::vector<bool>& keep);

// A graph with what was grown on a part of it put back.
struct Regrown {
    GeometricGraph graph;
    std::vector<VertexId> source_vertex; // per vertex, its id in the old graph; -1 for a grown one
};

// `graph` cut down to the vertices with keep[v] (and the edges between them), followed by
// what `grown` added to `part`, where `grown` was made from part.graph by adding vertices and
// edges after its own (as grow_region does). An edge of the part that the growth split (a
// street a new one meets at a T-junction) comes back split. Every vertex of the part must be
// kept. Throws UsageError when `keep` does not fit `graph`, a vertex of the part is not kept,
// or `grown` does not start with the part's vertices and edges.
Regrown with_grown(const GeometricGraph& graph, const std::vector<bool>& keep, const Subgraph& part,
                   const GeometricGraph& grown);

} // namespace ggg
