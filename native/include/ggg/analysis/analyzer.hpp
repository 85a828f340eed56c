#pragma once
// The graph analyzer (paper 5): isogroup detection followed by selection, the one call
// behind `ggg analyze`, the Python module and the Blender operators.
#include <cstddef>
#include <vector>

#include "ggg/analysis/isogroup_detection.hpp"
#include "ggg/analysis/seeded_search.hpp"
#include "ggg/graph/geometric_graph.hpp"
#include "ggg/progress.hpp"
#include "ggg/analysis/isogroup_selection.hpp"

namespace ggg {

struct AnalyzeOptions {
    DetectionOptions detection;
    SelectionConstraints constraints;
    SelectionOptions selection;
    // Empty: automatic analysis from every edge. Else the user's seed: the subgraph
    // induced by these vertices, searched with `tolerance` (see SeedSearchOptions; the
    // scale mode is detection.scale_mode) and grown from there.
    std::vector<VertexId> seed;
    // How far a copy may be from a pattern, relative to the pattern's size, for the seed
    // search and the recount.
    double tolerance = SeedSearchOptions{}.tolerance;
    // The seed's copies (Find Similar, the seeded analysis) also include every copy that the
    // automatic analysis with these options groups with the seed (see find_similar); false =
    // only the copies within `tolerance` of the seed.
    bool include_analysis_group = true;
    // The leading isogroups are recounted exactly: their occurrences become every induced
    // copy within `tolerance` of a pattern that is the mean of those copies
    // (find_settled_pattern), whichever path the expansion took to them. Their counts then
    // no longer depend on what the frequency cut kept (the full and the pruned analysis
    // agree on the groups they both rank first), and they no longer include loose copies
    // that the coarse polar grid let in. 0 = keep the counts of the expansion.
    // A recount is a search over the whole graph: milliseconds on a district, seconds per
    // pattern on a metropolitan graph, so it is off unless asked for.
    std::size_t recount_top = 0;
};

struct AnalyzedIsogroup {
    Isogroup group;
    long parent = -1;   // index in Analysis::isogroups of the group it grew from, or -1
    double score = 0.0; // DetectionResult::scores
    SelectedIsogroup selection; // selection.index is the group's place in detection order
    bool recounted = false;     // occurrences are every copy within the tolerance
};

struct Analysis {
    // Best gain first; with a seed, the seed's own group first, then the groups grown
    // from it by gain. Groups failing the constraints are left out (but not the seed's).
    std::vector<AnalyzedIsogroup> isogroups;
    std::vector<OrderReport> orders;
    std::size_t detected = 0; // groups found before the constraints
    bool stopped_by_budget = false;
};

// Throws UsageError naming the first option out of its range (NaN included).
void check_options(const AnalyzeOptions& options);

Analysis analyze(const GeometricGraph& g, const AnalyzeOptions& options = {}, const ProgressCallback& progress = {});

// Find Similar: every copy of the piece induced by `seed` (the seed itself first, in the
// seed's order, then in the order of the graph's edges): the copies within
// `options.tolerance` of the seed (find_occurrences), and (include_analysis_group) every copy
// that the automatic analysis with these options groups with the seed. The seed search alone compares each
// copy with one noisy seed; the analysis's polar grid compares them with each other, and a
// user who picks one block of a district the analysis found must find at least that
// district. Throws as find_occurrences.
Isogroup find_similar(const GeometricGraph& g, std::span<const VertexId> seed, const AnalyzeOptions& options = {},
                      const ProgressCallback& progress = {});

} // namespace ggg
