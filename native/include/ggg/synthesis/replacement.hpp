#pragma once
// Terminal replacement (paper Fig. 1): every chosen occurrence of an isogroup is replaced by
// another piece of street network (a round plaza for the blocks of Barcelona), fitted into
// the occurrence (its own frame, inside its area, clear of the streets around) and joined to
// the junctions around it.
//
// An occurrence gives up its own streets and the vertices no other street reaches; a vertex
// where streets of the surroundings meet stays where it is, so the streets around keep their
// course. It is a grammar rewriting, not a second mechanism: each occurrence becomes a
// nonterminal whose rule is the piece, with an embedding point for every junction it kept,
// aimed from the piece's vertex nearest to it (relaxed embedding, paper 3.3); one derivation
// step (rewriting.hpp) places them all. Where a new street still crosses one, both get an
// intersection there.
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "ggg/analysis/pattern.hpp"
#include "ggg/graph/geometric_graph.hpp"
#include "ggg/graph/road_class.hpp"

namespace ggg {

// A piece of street network to put in place of a pattern's occurrences.
struct ReplacementGraph {
    std::vector<Vec2> positions;
    std::vector<std::array<int, 2>> edges;
    std::vector<HighwayClass> edge_highway; // one per edge; empty = residential
};

// The replacement as a user drew it (in metres anywhere), fitted to a pattern: centred on the
// pattern's centre and scaled to its size, in the pattern's canonical coordinates, keeping its
// orientation on the map relative to the pattern's.
ReplacementGraph fit_replacement(const ReplacementGraph& drawn, const Pattern& pattern);

struct ReplaceReport {
    std::size_t replaced = 0;          // occurrences replaced
    std::size_t removed_vertices = 0;
    std::size_t added_vertices = 0;
    std::size_t joined_streets = 0;      // streets made to join a piece to the junctions around it
    std::size_t intersections = 0;       // crossings of a replacement's streets made junctions
};

// `graph` with the occurrences `chosen` of `group` (indices, pairwise without shared vertices)
// replaced by `replacement` (in the pattern's canonical coordinates, e.g. from
// fit_replacement). Vertices and edges the replacement does not touch keep their order.
// Throws UsageError for an empty replacement, an edge or index out of range, or occurrences
// that share a vertex.
GeometricGraph replace_occurrences(const GeometricGraph& graph, const Isogroup& group, std::span<const std::uint32_t> chosen,
                                   const ReplacementGraph& replacement, ReplaceReport* report = nullptr);

} // namespace ggg
