#pragma once
// User-seeded search (paper 5.1, "user-assisted learning", Fig. 17): the user picks a piece
// of the network, e.g. one city block, and asks where else it occurs.
//
// The answer is exact for the definition of geometrically_isomorphic: every induced
// subgraph of the graph that passes that test against the seed, and nothing else. The
// search walks the seed's vertices from its longest edge outwards over the graph, placing
// each next vertex by the similarity that the first edge fixes; the window it accepts is
// derived from the tolerance (an error of tau at both ends of an edge of length L moves a
// point at distance d from its middle by at most tau (1 + 2 d / L)), so no true copy is cut
// off early, and each complete candidate is then decided by the isomorphism test itself.
#include <span>

#include "ggg/analysis/geometric_isomorphism.hpp"
#include "ggg/analysis/pattern.hpp"
#include "ggg/graph/geometric_graph.hpp"
#include "ggg/progress.hpp"

namespace ggg {

struct SeedSearchOptions {
    // Largest distance of a vertex from its partner, relative to the seed's RMS radius (as in
    // IsomorphismOptions): 0.2 finds the blocks a person would call "the same shape". The
    // one default of the seed search, the analysis's recount, the CLI, Python and Blender.
    double tolerance = 0.2;
    IsomorphismOptions::Scale mode = IsomorphismOptions::Scale::similarity;
    double min_scale = 0.5;
    double max_scale = 2.0;
    bool respect_symbols = true;
};

// The seed's isogroup: its pattern (the subgraph induced by `seed`, canonical) and every
// occurrence, the seed itself first, then in the order of the graph's edges. Throws
// UsageError when the seed has fewer than two vertices, an id out of range or repeated,
// is not connected, or its vertices all lie at one point.
Isogroup find_occurrences(const GeometricGraph& g, std::span<const VertexId> seed,
                          const SeedSearchOptions& options = {}, const ProgressCallback& progress = {});

// Every induced copy of a pattern (e.g. an isogroup's mean pattern) in g, in the order of
// g's edges: the same search without a seed in the graph. The pattern must be connected,
// with at least one edge; sizes compare as options.mode says (patterns from the analyzer
// carry their size in metres_per_unit). Throws UsageError for a malformed pattern.
Isogroup find_pattern(const GeometricGraph& g, const Pattern& pattern, const SeedSearchOptions& options = {},
                      const ProgressCallback& progress = {});

// The copies of a pattern, counted so that the count does not depend on where the pattern
// came from: find_pattern, then the pattern becomes the mean of the copies it found (a
// Procrustes average, made as symmetric as it nearly is), and so on until the copies no
// longer change (at most max_rounds rounds). Two estimates of one street pattern, e.g. the
// means that a pruned and a full analysis reached over different occurrences, settle on the
// same copies, where a single search around each would count the copies near the
// tolerance's edge differently. The result's pattern is the estimate its copies were found
// with (the mean of the previous round's copies). Throws as find_pattern.
Isogroup find_settled_pattern(const GeometricGraph& g, const Pattern& pattern, const SeedSearchOptions& options = {},
                              int max_rounds = 12);

// The Procrustes mean of `group`'s occurrences, seen through their transforms, in the
// canonical frame, with metres_per_unit their mean scale; the pattern itself when the
// group has no occurrence or the mean collapses to a point.
Pattern mean_pattern(const GeometricGraph& g, const Isogroup& group);

} // namespace ggg
