#pragma once
// Isogroup detection by vertex expansion (paper 5.1): the patterns that repeat in a road
// graph, grown one vertex at a time from every edge or from a seed the user picked.
//
// One expansion step takes an isogroup of order k and, for every occurrence, looks at the
// graph vertices next to it. Each candidate is placed in the occurrence's own frame (its
// least-squares similarity transform, so one noisy edge cannot tilt it), relative to the
// pattern vertex it hangs from, and binned in a polar grid (angle x log distance). The
// candidates whose cell and induced topology (which pattern vertices they touch) agree
// form a child isogroup of order k + 1. Cells are grouped around local maxima of the
// counts (a peak takes its unclaimed neighbour cells), so a cluster that straddles a cell
// border stays one child; that is what makes the search robust to noise (paper Fig. 14).
// Expansions of a symmetric pattern are counted once: each candidate is keyed by the
// smallest of its images under the pattern's symmetries (geometric_automorphisms).
//
// Children reached from different parents are merged when their patterns are
// geometrically isomorphic; occurrences are de-duplicated by vertex set; groups with fewer
// than min_count occurrences are dropped. The frequency cut then keeps only the most
// frequent groups for further expansion; the groups it cuts stay in the result (their
// counts are exact), they are only not grown.
//
// Pattern geometry is the mean of the occurrences (a generalised Procrustes average), not
// a cell centre, so a pattern is as precise as its data allows whatever the grid.
// Results are deterministic and independent of the number of threads.
#include <cstddef>
#include <vector>

#include "ggg/analysis/geometric_isomorphism.hpp"
#include "ggg/analysis/pattern.hpp"
#include "ggg/graph/geometric_graph.hpp"
#include "ggg/progress.hpp"

namespace ggg {

struct DetectionOptions {
    // Polar grid of the expansion: cells around the expanded vertex, and log-spaced distance
    // cells from 1/8 to 8 times the pattern's RMS radius (candidates farther or nearer are
    // not considered). The paper's default is 12 x 10; finer grids find fewer but closer
    // copies (paper Fig. 8, 11).
    int angle_cells = 12;
    int distance_cells = 10;

    // Frequency cut (paper 5.1): after expansion to order k + 1 the least frequent fraction
    // cut * (1 - 2^-(k-1)) of the groups is not expanded further (40 %, 60 %, 70 %, 75 %, ...
    // of the groups; the paper uses about 80 % once the groups are well formed).
    double cut = 0.8;
    // Expand every group (the paper's "full" analysis, its ground truth in Table 1).
    bool full = false;

    // Largest order (number of vertices) of a pattern; 0 = until nothing repeats.
    int max_order = 8;
    // Fewest occurrences for a pattern to count as repeated.
    std::size_t min_count = 2;

    // How sizes compare. similarity: any size; rigid: one size per isogroup (within
    // scale_tolerance); range: sizes within a factor max_scale / min_scale of each other.
    IsomorphismOptions::Scale scale_mode = IsomorphismOptions::Scale::similarity;
    double scale_tolerance = 0.1;
    double min_scale = 0.5;
    double max_scale = 2.0;
    // Vertices with different symbols never match (needed on encoded graphs, whose
    // nonterminal vertices stand for whole patterns).
    bool respect_symbols = true;
    // Tolerance of the isomorphism test that merges groups reached from different
    // directions and finds the symmetries of a pattern, relative to its RMS radius.
    double merge_tolerance = 0.1;

    // Stop growing (with stopped_by_budget set) before one order would hold more than
    // this many occurrence vertex ids, which bounds memory (4 bytes each).
    std::size_t max_occurrence_vertices = 200'000'000;
    // Budgets that bound "until nothing repeats" (max_order 0), which on a city grows without
    // end: growing stops, with stopped_by_budget set and the groups found so far kept, once the
    // detection has run this many seconds or its groups and candidates would take more than
    // this many megabytes. The defaults fit a 2-core, 24 GB machine and are far beyond what
    // the default analysis of a city needs (seconds, a few hundred megabytes). 0 = no limit.
    // The time budget, < 0 = automatic: default_time_budget_s with max_order 0, none with a
    // largest order (which ends by itself), so that a bounded analysis gives the same result
    // on a slow machine as on a fast one.
    double max_seconds = -1.0;
    double max_memory_mb = 8192.0;
};

inline constexpr double default_time_budget_s = 120.0;

// The time budget max_seconds stands for, in seconds (0 = none).
inline double time_budget_seconds(const DetectionOptions& o) {
    if (o.max_seconds >= 0) return o.max_seconds;
    return o.max_order == 0 ? default_time_budget_s : 0.0;
}

// Throws UsageError naming the first bad option.
void check_options(const DetectionOptions& options);

// What happened at one order.
struct OrderReport {
    int order = 0;
    std::size_t parents = 0;       // groups of order - 1 that were expanded
    std::size_t candidates = 0;    // (occurrence, neighbour) pairs binned
    std::size_t children = 0;      // child groups before merging
    std::size_t groups = 0;        // after merging and min_count
    std::size_t expanded_next = 0; // of those, kept by the frequency cut
    std::size_t occurrences = 0;   // over all groups of this order
};

struct DetectionResult {
    // Every group found, by order, then by frequency (highest first). The order-2 groups
    // (single edges, one per symbol pair) come first, or the seed's group when seeded.
    std::vector<Isogroup> isogroups;
    // Index of each group's parent in `isogroups` (the group it was first expanded from),
    // or -1 for the order-2 groups and the seed.
    std::vector<long> parents;
    // The paper's expansion score of each group: frequency x the convex-hull area its last
    // vertex added (in the pattern's canonical units, so independent of size). 0 for the
    // order-2 groups and the seed.
    std::vector<double> scores;
    std::vector<OrderReport> orders;
    bool stopped_by_budget = false;
};

// The automatic analysis: seeds are all edges.
DetectionResult detect_isogroups(const GeometricGraph& g, const DetectionOptions& options = {},
                                 const ProgressCallback& progress = {});

// The user-seeded analysis: expansion starts from `seed` (usually from find_occurrences)
// instead of the edges; the seed group is reported first.
DetectionResult detect_isogroups_from(const GeometricGraph& g, Isogroup seed, const DetectionOptions& options = {},
                                      const ProgressCallback& progress = {});

} // namespace ggg
