#pragma once
// The first stage of the seeded search (analysis/seeded_search.hpp), private to it: the
// subgraphs of the graph that could be copies of a pattern, walked out from every edge.
// seeded_search.cpp then lets the isomorphism test decide them.
#include <vector>

#include "ggg/analysis/pattern.hpp"
#include "ggg/analysis/seeded_search.hpp"
#include "ggg/graph/geometric_graph.hpp"

namespace ggg::seeded_search_detail {

// The induced subgraphs that could be copies of `pattern` within o.tolerance, one per
// vertex set, in the order of g's edges; the isomorphism test has not decided them yet.
std::vector<std::vector<VertexId>> candidates_for(const GeometricGraph& g, const Adjacency& adj, const Pattern& pattern,
                                                  const SeedSearchOptions& o);

} // namespace ggg::seeded_search_detail
