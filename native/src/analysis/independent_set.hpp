#pragma once
// The maximum independent set solvers behind the non-overlapping selection
// (analysis/non_overlapping.hpp), private to it: one connected component of the overlap
// graph at a time, a heuristic that is always run and an exact search for the components
// small enough to prove.
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "ggg/analysis/non_overlapping.hpp"
#include "ggg/random.hpp"

namespace ggg::non_overlapping_detail {

inline constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

// One connected component with local ids 0..s-1 (ascending in the global ids, so rows
// stay sorted and the input order, which often follows the geometry, is kept).
struct LocalGraph {
    std::vector<std::size_t> offsets{0};
    std::vector<std::uint32_t> nbrs;

    std::uint32_t size() const { return static_cast<std::uint32_t>(offsets.size() - 1); }
    const std::uint32_t* begin(std::uint32_t v) const { return nbrs.data() + offsets[v]; }
    const std::uint32_t* end(std::uint32_t v) const { return nbrs.data() + offsets[v + 1]; }
    std::uint32_t degree(std::uint32_t v) const { return static_cast<std::uint32_t>(offsets[v + 1] - offsets[v]); }
};

// Upper bounds on the independent set of a component, by greedy clique covers
// (branch_and_bound.cpp).

// The cover in index order: on grid-like inputs listed row by row it finds the 2x2
// blocks, which is tight.
std::uint32_t index_cover_bound(const LocalGraph& g);

// The cover seeded by an independent set: its vertices first (one clique each), then the
// others by how many chosen neighbours they have, fewest first (they have the fewest
// cliques to choose from). Unlike the index cover it does not depend on the input
// order; neither is tight in general (on a shuffled grid of squares both are ~25 % high).
std::uint32_t guided_cover_bound(const LocalGraph& g, const std::vector<std::uint8_t>& chosen);

// Greedy minimum degree: repeatedly take a vertex of least degree in what is left, delete
// it and its neighbours. Degrees live in a bucket queue (doubly linked list per degree),
// so the pass is O(n + m). The result is maximal.
std::vector<std::uint8_t> greedy_min_degree(const LocalGraph& g);

// Throws UsageError unless `graph` is a well-formed overlap graph (what build_overlap_graph
// makes): rows spanning the neighbour array, sorted, symmetric, without self-loops.
void check_graph(const OverlapGraph& graph);

// Local search on an independent set, after Andrade, Resende and Werneck (2012):
// (1,2)-swaps remove one chosen vertex x and insert two non-adjacent vertices whose only
// chosen neighbour is x; free vertices are inserted as they appear. Iterated: a
// perturbation forces a random unchosen vertex in, the swaps repair around it, and the
// step is undone when it made the set smaller (equal is kept, to walk plateaus).
class LocalSearch {
public:
    LocalSearch(const LocalGraph& g, const std::vector<std::uint8_t>& initial);

    std::uint32_t count() const { return count_; }
    const std::vector<std::uint8_t>& solution() const { return in_; }

    // (1,2)-swaps until none applies: each strictly grows the set, so this terminates.
    void descend();

    // Perturb-and-repair steps until `steps` are done or the set reaches `bound`.
    void iterate(std::uint64_t steps, std::uint32_t bound, Random& random);

private:
    void insert(std::uint32_t v);
    void remove(std::uint32_t v);
    void enqueue(std::uint32_t v);
    // After x left the set, its unchosen neighbours with one chosen neighbour y are new
    // swap candidates of y; free ones go straight in.
    void after_removal(std::uint32_t x);
    void try_swap(std::uint32_t x);
    void force(std::uint32_t v);

    const LocalGraph& g_;
    std::vector<std::uint8_t> in_;
    std::vector<std::uint32_t> tight_; // chosen neighbours of each vertex
    // XOR of the ids of the chosen neighbours: when tight_ is 1 it is that neighbour.
    std::vector<std::uint32_t> xor_;
    // Of a chosen vertex: how many neighbours have it as their only chosen neighbour (a
    // swap needs two), so most queued vertices are dismissed in O(1).
    std::vector<std::uint32_t> one_tight_;
    std::vector<std::uint8_t> queued_;
    std::vector<std::uint32_t> queue_;
    std::vector<std::uint32_t> candidates_;
    std::vector<std::uint32_t> removed_;
    std::vector<std::uint32_t> log_;
    bool logging_ = true;
    std::uint32_t count_ = 0;
};

// Exact maximum independent set of one component by branch and bound on bit rows.
// A node takes every vertex of degree <= 1 (always safe), then bounds by a greedy clique
// cover of what is left, then branches on a vertex of maximum degree: take it (drop its
// neighbours) or drop it. Taking removes at least three vertices, so the depth is at
// most s/3 + 1.
class BranchAndBound {
public:
    // A node costs about s * s / 64 word operations, so a node of a component above 64
    // occurrences is charged (s / 64)^2 of the budget: the budget bounds time, not nodes.
    BranchAndBound(const LocalGraph& g, std::uint64_t budget);

    // Returns false when the node budget ran out; `best` then holds the best set found
    // (never worse than the one passed in).
    bool solve(std::vector<std::uint32_t>& best);

private:
    const std::uint64_t* row(std::uint32_t v) const { return adjacency_.data() + static_cast<std::size_t>(v) * words_; }

    std::uint32_t degree_in(std::uint32_t v, const std::uint64_t* set) const;

    // Cliques in a greedy cover of `set`, counted only up to `enough` (past that the node
    // cannot be pruned, so the exact count does not matter).
    std::size_t cover(const std::uint64_t* set, std::size_t enough);

    void search(std::uint64_t* set, std::size_t depth);

    std::uint32_t s_;
    std::size_t words_;
    std::uint64_t budget_;
    std::uint64_t charge_;
    std::uint64_t spent_ = 0;
    bool aborted_ = false;
    std::vector<std::uint64_t> adjacency_;
    std::vector<std::uint64_t> pool_; // one bit row per recursion level, consecutive
    std::vector<std::uint64_t> scratch_;
    std::vector<std::uint32_t> current_;
    std::vector<std::uint32_t> best_;
};

} // namespace ggg::non_overlapping_detail
