#pragma once
// The stages of the isogroup detection (analysis/isogroup_detection.hpp), private to it:
// the patterns fitted to their occurrences (isogroup_fitting.cpp), the expansion of a parent
// into its children (isogroup_expansion.cpp), occurrences de-duplicated within and across
// groups (isogroup_deduplication.cpp), and groups merged (isogroup_merging.cpp).
// isogroup_detection.cpp runs them order by order.
#include <cstddef>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "ggg/analysis/geometric_isomorphism.hpp"
#include "ggg/analysis/isogroup_detection.hpp"
#include "ggg/analysis/pattern.hpp"
#include "ggg/graph/geometric_graph.hpp"
#include "polar_grid.hpp"

namespace ggg::detection_detail {

inline constexpr int max_pattern_order = 64; // vertex masks are 64-bit

struct Symmetry {
    std::vector<int> perm; // pattern vertex j corresponds to perm[j]
    Similarity2 map;       // pattern coordinates: x -> rotation about the centroid
};

// A parent group ready for expansion.
struct Parent {
    const Isogroup* group = nullptr;
    long index = -1; // in the result
    std::vector<Symmetry> symmetries; // identity first
};

struct Candidate {
    std::uint64_t mask;      // pattern vertices the new vertex touches, after the symmetry
    std::uint32_t symbol;    // of the new vertex
    std::uint32_t occurrence;
    VertexId vertex;
    std::uint16_t cell;
    std::uint8_t symmetry;
    float x, y;              // new vertex in the parent's canonical frame, after the symmetry
};

inline bool candidate_less(const Candidate& a, const Candidate& b) {
    if (a.mask != b.mask) return a.mask < b.mask;
    if (a.symbol != b.symbol) return a.symbol < b.symbol;
    if (a.cell != b.cell) return a.cell < b.cell;
    if (a.occurrence != b.occurrence) return a.occurrence < b.occurrence;
    return a.vertex < b.vertex;
}

// A group found at the current order, with what ranking and merging need.
struct Found {
    Isogroup group;
    long parent = -1;
    double added_area = 0.0; // hull area the last vertex added, canonical units
    std::uint64_t hash = 0;
    std::vector<double> radii; // sorted distances from the centroid, canonical
    // What isomorphism keeps up to the tolerance, per class that it keeps exactly:
    // distances from the centroid sorted by (degree, symbol, distance) and edge lengths
    // sorted by (end degrees, length). Equal hashes make the classes line up.
    std::vector<std::pair<std::uint64_t, double>> vertex_profile;
    std::vector<std::pair<std::uint64_t, double>> edge_profile;
    // The 99th percentile over the occurrences of their largest vertex residual from the
    // pattern (canonical units): how far this group's own copies stray (see absorb_fragments).
    double spread = -1.0; // not computed yet
    bool merged_away = false;
};

inline double score_of(const Found& f) { return static_cast<double>(f.group.frequency()) * f.added_area; }

// Fitting (isogroup_fitting.cpp)

double hull_area(std::span<const Vec2> points);

// The similarity mapping the canonical pattern `p` (centroid 0, sum of squares k) onto the
// graph points `y`: closed-form least squares, no allocation (the analyzer's hot path).
Similarity2 fit_canonical(const std::vector<Vec2>& p, const Vec2* y, std::size_t k);

// Generalised Procrustes: fit every occurrence to the pattern, replace the pattern by the
// mean of the occurrences seen through their fits, fit again. One round settles it: the
// first pattern is already close (it is the parent's mean plus the new vertex's mean).
void refine(Isogroup& group, const GeometricGraph& g, int rounds = 1);

// Expansion (isogroup_expansion.cpp)

std::vector<Symmetry> symmetries_of(const Pattern& p, const DetectionOptions& o);

// Candidates of occurrences [begin, end) of `parent`, appended to `out` in occurrence order.
void collect_candidates(const GeometricGraph& g, const Adjacency& adjacency, const Parent& parent,
                        const PolarGrid& grid, bool with_symbols, std::size_t begin, std::size_t end,
                        std::vector<Candidate>& out);

// Builds the children of one parent from its sorted candidates.
std::vector<Found> children_of(const GeometricGraph& g, const Parent& parent, std::vector<Candidate>& candidates,
                               const PolarGrid& grid, const DetectionOptions& o);

// The order-2 groups: every edge, one group per (sorted) symbol pair, oriented from the
// smaller symbol (equal symbols: from the smaller vertex id).
std::vector<Found> edge_groups(const GeometricGraph& g, const DetectionOptions& o);

// De-duplication (isogroup_deduplication.cpp)

// Removes occurrences whose vertex set repeats an earlier one (the first one stays).
void deduplicate(Isogroup& group);

// One subgraph, one isogroup: a vertex set found in several groups (groups whose patterns
// are alike but not within the merge tolerance, e.g. at a cell border) stays only in the
// most frequent of them. Without this, near-duplicate groups would multiply with every
// order instead of competing for the same occurrences.
void assign_to_one_group(std::vector<Found>& found, const GeometricGraph& g);

// Merging (isogroup_merging.cpp)

// Sets what merging compares (the invariant hash, radii, profiles) and the added area.
void describe(Found& f, bool with_symbols);

// Folds groups that are geometrically isomorphic into the most frequent of them.
void merge_isomorphic(std::vector<Found>& found, const GeometricGraph& g, const DetectionOptions& o);

// Noise splits a pattern's copies: most land in one group, a few take other paths through
// the polar grids and form small groups whose mean patterns are pulled off by the noise, too
// far for merge_isomorphic. A small group is folded into one of the dominant groups of its
// topology when its copies look like that group's own: the median of their residuals from
// the dominant pattern is within the dominant group's 99th-percentile residual plus the
// merge tolerance. Only groups at most a quarter as frequent are folded,
// and only into the four most frequent groups of the topology, so distinct patterns that
// are both common stay apart. Folding changes only the groups reported: the groups that
// are grown keep their own copies (so a folded group never widens the next order, where it
// would fold more), and groups marked in keep_apart are neither folded nor removed.
// Folded groups are marked merged_away.
void absorb_fragments(std::vector<Found>& found, const GeometricGraph& g, const DetectionOptions& o,
                      const std::vector<char>& keep_apart);

} // namespace ggg::detection_detail
