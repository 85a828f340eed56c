#pragma once
// Isogroup selection (paper 5.2): which of the detected isogroups is worth a grammar rule.
//
// The paper takes "the largest from the most frequently repeated" isogroups. We make that
// a number, the description-length gain of encoding an isogroup (pipeline step 4), counted
// in the numbers a graph file stores: 2 per vertex (its coordinates), 2 per edge (its
// ends). Each of the m non-overlapping occurrences (k vertices, e edges inside, x edges to
// the rest of the graph) becomes one nonterminal vertex with a symbol and a frame (5
// numbers), and each of its x outside edges must say which inside vertex it meets (1
// number); one rule of k vertices and e edges is stored once:
//
//     gain = sum over the m occurrences of (2k + 2e - 5 - x)  -  (2k + 2e)
//
// It grows with size and frequency, it is negative for a pattern that occurs once, and it
// is negative for single edges and most short paths, whose outside edges cost more than
// they save: what is worth a rule is what a grammar compresses.
//
// Constraints (paper Fig. 18a) filter the ranking: a near-square overall shape, many
// leaves (dead ends and streets that leave the pattern), or an irregular street layout.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "ggg/analysis/pattern.hpp"
#include "ggg/graph/geometric_graph.hpp"
#include "ggg/progress.hpp"
#include "ggg/analysis/non_overlapping.hpp"

namespace ggg {

// Shape measures of a pattern.
struct PatternShape {
    // sqrt(smaller / larger principal variance) of the vertex positions: 1 for a square or
    // a round shape, 0 for vertices on a line.
    double aspect = 0.0;
    // Vertices of degree 1 inside the pattern.
    std::size_t leaves = 0;
    // Mean angle, in degrees (0 to 45), between an edge and the nearest of the pattern's
    // two dominant perpendicular directions, weighted by edge length: 0 for a grid.
    double irregularity_deg = 0.0;
};
PatternShape shape_of(const Pattern& p);

struct SelectionConstraints {
    double min_aspect = 0.0;            // keep shapes with aspect >= this (0..1)
    std::size_t min_leaves = 0;         // keep patterns with at least this many leaves
    double min_irregularity_deg = 0.0;  // keep patterns at least this irregular (0..45)
    bool operator==(const SelectionConstraints&) const = default;
};
// Empty when p passes, else why not.
std::string violated_constraint(const PatternShape& shape, const SelectionConstraints& c);

// `outside_edges`: the sum of x over the m occurrences.
double description_gain(std::size_t order, std::size_t edges, std::size_t non_overlapping, std::size_t outside_edges);

struct SelectedIsogroup {
    std::size_t index = 0;                    // into the isogroups passed in
    std::vector<std::uint32_t> non_overlapping; // occurrence indices, ascending
    bool exact = true;                        // the selection is proven maximum
    std::string method;                       // how it was found (SelectionResult::method)
    double gain = 0.0;
    PatternShape shape;
};

// The isogroups that meet the constraints with their non-overlapping occurrences, best
// gain first (ties: more occurrences, larger order, lower index). Every group is first
// ranked with a quick greedy selection (occurrences sharing the fewest vertices first,
// no overlap graph, no bounds); the 16 leading groups are then selected again with `options`, so the
// groups a user or the encoder picks carry the full answer and its method. Deterministic;
// independent of the number of threads.
std::vector<SelectedIsogroup> select_isogroups(const GeometricGraph& g, const std::vector<Isogroup>& isogroups,
                                               const SelectionConstraints& constraints = {},
                                               const SelectionOptions& options = {},
                                               const ProgressCallback& progress = {});

// The ranking select_isogroups uses: best gain first, then more occurrences, larger order,
// lower index. For re-ranking after some groups changed.
void sort_by_gain(std::vector<SelectedIsogroup>& selected, const std::vector<Isogroup>& isogroups);

// The full selection (with `options`) of one group, as select_isogroups reports it.
SelectedIsogroup select_one(const GeometricGraph& g, const Isogroup& group, std::size_t index, const SelectionOptions& options = {});

} // namespace ggg
