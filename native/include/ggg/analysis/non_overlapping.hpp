#pragma once
// Non-overlapping selection (pipeline step 3, paper 5.2): of all occurrences of an
// isogroup, keep the largest set in which no two share a graph vertex. The paper phrases
// it as the largest clique of the "non-overlap" graph; we solve the equivalent maximum
// independent set of the overlap graph, which is sparse (bounded degree) where the
// complement is dense. On real cities the overlap graph falls apart into many small
// components: those are solved exactly, the few large ones by a greedy minimum-degree
// pass and an iterated (1,2)-swap local search.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "ggg/graph/geometric_graph.hpp"

namespace ggg {

// Occurrences are passed flat: occurrence i is vertices[i*k .. (i+1)*k). Two occurrences
// overlap when they share at least one graph vertex (a repeated id inside one occurrence
// is harmless). Vertex ids must be >= 0; they need not be dense.

// Which occurrences overlap which, as CSR: the neighbours of occurrence i are
// neighbors[offsets[i] .. offsets[i+1]), sorted ascending, without i itself and without
// repeats. Each overlapping pair is stored twice (once per side).
struct OverlapGraph {
    std::vector<std::int64_t> offsets{0};
    std::vector<std::uint32_t> neighbors;

    std::size_t size() const noexcept { return offsets.size() - 1; }
    std::size_t edge_count() const noexcept { return neighbors.size() / 2; }
    std::size_t degree(std::uint32_t i) const {
        return static_cast<std::size_t>(offsets[i + 1] - offsets[i]);
    }
    std::span<const std::uint32_t> neighbours_of(std::uint32_t i) const {
        return {neighbors.data() + offsets[i], degree(i)};
    }
};

// Built by bucketing the occurrences per graph vertex, so the cost is
// O(n*k + sum over graph vertices of (occurrences through it)^2), i.e. linear in the
// input plus the overlaps, never O(n^2) pair tests.
// Throws UsageError when k == 0, vertices.size() % k != 0, an id is negative, or there
// are 2^32 or more occurrences.
OverlapGraph build_overlap_graph(std::span<const VertexId> vertices, std::size_t k);

struct SelectionOptions {
    // Connected components of the overlap graph with at most this many occurrences are
    // solved exactly by branch and bound; larger ones by the heuristic. Values above
    // 16384 act as 16384 (the branch and bound keeps a bit matrix of the component).
    std::size_t exact_limit = 64;
    // Iterated local search on the components above exact_limit, after the greedy pass
    // and (1,2)-swaps to a local optimum: each round makes as many perturb-and-repair
    // steps as the component has occurrences (about 1-3 us each). 0 = no perturbation.
    // On hard synthetic inputs round 1 adds about 4 % over the greedy set, later rounds
    // well under 1 % each; on grid-like inputs the greedy set is already optimal.
    int local_search_rounds = 1;
    // false: only the greedy minimum-degree set and its (1,2)-swap local optimum, no upper
    // bounds, no branch and bound (`exact` then holds only where every component has at
    // most two occurrences, and upper_bound is the number of occurrences). For ranking
    // thousands of groups, where a few per cent do not matter.
    bool prove = true;
    // Seed of the perturbations; the same input, options and seed give the same result.
    std::uint64_t seed = 1;
    // Branch-and-bound nodes allowed per component; a node of a component of s > 64
    // occurrences counts (s / 64)^2 times, as its work grows so, which makes the budget a
    // time limit (the default: about 0.2 s for a hard 128-occurrence component). When it
    // runs out, the best set found so far (at least the greedy one) goes through the
    // local search of the large components, and exact becomes false.
    std::uint64_t node_budget = 1'000'000;
};

struct SelectionResult {
    std::vector<std::uint32_t> chosen; // occurrence indices, sorted ascending
    // True when `chosen` is proven maximum: every component was solved by a finished
    // branch and bound, or its heuristic solution met its upper bound.
    bool exact = true;
    // "exact branch and bound" when every component was proven by the exact path (size up
    // to exact_limit, search finished within node_budget); "greedy min-degree + local
    // search" when some component is larger or its search was cut short. A large
    // component whose heuristic set meets its bound is still proven, so `exact` may be
    // true with the heuristic method.
    std::string method;
    // An upper bound on the maximum: per component the exact value when proven, else the
    // size of a greedy clique cover (each clique holds at most one chosen occurrence; the
    // smaller of one in input order and one seeded by the solution found). Only a bound:
    // on irregular inputs it can be 10-30 % above the optimum. Equals chosen.size()
    // exactly when `exact`.
    std::size_t upper_bound = 0;
};

// The largest (exactly, or as found by the heuristic) set of pairwise non-overlapping
// occurrences. Always an independent set of the overlap graph, and maximal: no
// unchosen occurrence is free of overlaps with the chosen ones. Deterministic.
// Throws UsageError for the bad arguments listed at build_overlap_graph, or a negative
// local_search_rounds.
SelectionResult select_non_overlapping(std::span<const VertexId> vertices, std::size_t k,
                                       const SelectionOptions& options = {});

// The same on an overlap graph built elsewhere (for another notion of overlap, or to
// reuse one). The graph must be symmetric with rows as described at OverlapGraph;
// throws UsageError when it is not well formed.
SelectionResult select_independent_set(const OverlapGraph& graph, const SelectionOptions& options = {});

} // namespace ggg
