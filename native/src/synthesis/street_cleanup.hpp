#pragma once
// The last stage of growth (synthesis/growth.hpp), private to it: the grown streets tidied
// once everything is placed. Each takes the graph with the base first (base_vertices,
// base_edges: what growth started from, never changed) and the grown streets after it.
#include <cstddef>
#include <vector>

#include "ggg/graph/geometric_graph.hpp"

namespace ggg::growth_detail {

// A street to keep, between two vertices of the graph as it was.
struct Street {
    VertexId a = -1, b = -1;
    EdgeAttributes attributes;
    std::vector<Vec2> polyline;
};

// The graph again with the vertices not dropped (the base first, unchanged; grown ids shift
// down) and these streets, given in the old vertex ids.
GeometricGraph rebuilt(const GeometricGraph& g, const std::vector<char>& drop_vertex, const std::vector<Street>& streets);

// The last guard of the rule that no two streets cross without an intersection: a grown street
// that crosses another street is taken out again, the newer of two grown ones. Returns how many.
std::size_t remove_crossing_streets(GeometricGraph& g, std::size_t base_vertices, std::size_t base_edges);

// A grown vertex where two grown streets of one class meet and nothing else is no junction:
// the two become one street through it (a bend of its polyline). Returns how many went.
std::size_t dissolve_bends(GeometricGraph& g, std::size_t base_vertices, std::size_t base_edges);

} // namespace ggg::growth_detail
