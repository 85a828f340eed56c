#pragma once
// Decoding a learned grammar: the forward derivation of its axiom (rewriting.hpp) with the
// settings the encoder recorded (Grammar::encoding), and the graph of each level of the
// hierarchy, for showing how a city was encoded (paper Fig. 13).
#include <vector>

#include "ggg/graph/geometric_graph.hpp"
#include "ggg/grammar/grammar.hpp"
#include "ggg/progress.hpp"
#include "ggg/grammar/rewriting.hpp"

namespace ggg {

// How a learned grammar is derived: its level count as steps, its absolute tolerance, a
// vertex budget that fits exactly what its instances place.
DeriveOptions decode_options(const Grammar& grammar);

// The length of a graph's streets, straight between their ends, in whole metres (-1 when it
// is not finite): what Encoding::decoded_length_m records.
std::int64_t street_length_m(const GeometricGraph& g);

// Per rule, its level in the hierarchy: 1 for a rule of street vertices only, else one
// more than the highest level among the nonterminals it places (any grammar).
std::vector<int> rule_levels(const Grammar& grammar);

// The streets a learned grammar encodes. `report`, when given, receives the derivation's
// report (placed_by tells which instance placed each vertex). Throws GrammarError for a
// grammar that is not a learned one or does not decode completely.
GeometricGraph decode_grammar(const Grammar& grammar, DeriveReport* report = nullptr,
                              const ProgressCallback& progress = {});

// The graph encoded to `level` (0 = the decoded streets, encoding.levels = the axiom): the
// nonterminal vertices of that level with their symbols and frames, joined to each other
// and to the streets as the streets they stand for are joined. Throws UsageError for a
// level out of range.
// `image`, when given, receives for each vertex of the decoded streets the vertex of the
// level's graph that stands for it.
GeometricGraph encoded_graph(const Grammar& grammar, int level, const ProgressCallback& progress = {},
                             std::vector<VertexId>* image = nullptr);

} // namespace ggg
