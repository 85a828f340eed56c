#pragma once
// Geometric isomorphism of two patterns (paper 3.1), the test behind merging isogroups that
// the analyzer reached from different directions (paper 5.1).
//
// Two patterns are isomorphic when a bijection f of their vertices
//  - preserves adjacency exactly (an edge in a iff an edge in b: induced subgraphs),
//  - preserves symbols (unless respect_symbols is false),
//  - and the least-squares transform of the mode, with the centroids matched, brings every
//    vertex within `tolerance` of its partner.
// Reflections are never allowed: a mirrored street pattern is another pattern.
//
// Sizes and tolerance. Distances are measured relative to the RMS radius (RMS distance of the
// vertices to their centroid), so that a 5 % wobble means the same for a small and a large
// pattern. Each pattern's real size is its coordinates' RMS radius times metres_per_unit.
//  - similarity: any size; both shapes are brought to RMS radius 1 and compared there.
//  - range:      as similarity, and size(b) / size(a) must lie in [min_scale, max_scale].
//  - rigid:      no scaling at all in metres; the tolerance is relative to the mean of the
//                two sizes.
// So rigid and range compare the absolute sizes given by the coordinates you pass: patterns
// from induced_pattern carry their size in metres_per_unit; hand-made ones should give
// coordinates in metres (metres_per_unit = 1).
//
// Fixing the scale by the sizes (instead of fitting it) makes the test symmetric:
// isomorphic(a, b) and isomorphic(b, a) agree, so merging does not depend on which group
// came first. The decision is exact for this definition: every bijection that could pass is
// examined, up to a budget of a million search steps (a street pattern needs a few hundred);
// only a crowd of a dozen or more nearly coincident vertices of equal degree could exhaust it,
// and then the best match found so far, or "not isomorphic", is the answer.
//
// A degenerate pattern (all vertices at one point, e.g. every 1-vertex pattern) is
// isomorphic only to a degenerate pattern, by topology and symbols alone.
#include <cstdint>
#include <memory>
#include <optional>
#include <string_view>
#include <vector>

#include "ggg/analysis/pattern.hpp"
#include "ggg/graph/similarity.hpp"

namespace ggg {

struct IsomorphismOptions {
    enum class Scale { similarity, rigid, range };

    // Largest distance of a vertex from its partner, relative to the RMS radius (see above).
    double tolerance = 0.05;
    Scale mode = Scale::similarity;
    // range mode only: bounds of size(b) / size(a) in metres.
    double min_scale = 0.5;
    double max_scale = 2.0;
    bool respect_symbols = true;
};

// "similarity", "rigid", "range" (the names the CLI and Python use); UsageError otherwise.
IsomorphismOptions::Scale scale_mode_from_name(std::string_view name);

struct IsomorphismMatch {
    std::vector<int> mapping; // vertex i of a corresponds to vertex mapping[i] of b
    Similarity2 transform;    // coordinates of a -> coordinates of b
    // Distances |transform(a_i) - b_mapping[i]| in the tolerance's unit (RMS radius of b;
    // rigid: mean RMS radius in metres), so max_residual <= tolerance.
    double rms_residual = 0.0;
    double max_residual = 0.0;
};

// The best match (lowest rms_residual) when `a` and `b` are geometrically isomorphic, else
// nullopt. Deterministic. Throws UsageError for a malformed pattern (check_pattern), a
// tolerance that is negative or not finite, and in range mode for bounds that are not
// 0 < min_scale <= max_scale < infinity.
std::optional<IsomorphismMatch> geometrically_isomorphic(const Pattern& a, const Pattern& b,
                                                         const IsomorphismOptions& options = {});

// A pattern prepared once for many comparisons: checked, normalised, its invariants
// computed. A recount compares one pattern with thousands of candidates, round after round,
// and the preparation is most of the cost of a comparison that fails. Cheap to copy (the
// prepared data is shared and never changes). Throws UsageError for a malformed pattern.
class PreparedPattern {
public:
    explicit PreparedPattern(Pattern p);
    const Pattern& pattern() const;

private:
    struct Impl;
    std::shared_ptr<const Impl> impl_;
    friend std::optional<IsomorphismMatch> geometrically_isomorphic(const PreparedPattern& a, const PreparedPattern& b,
                                                                    const IsomorphismOptions& options);
};

// The same test as above, on prepared patterns; the same answer.
std::optional<IsomorphismMatch> geometrically_isomorphic(const PreparedPattern& a, const PreparedPattern& b,
                                                         const IsomorphismOptions& options = {});

// The symmetries of `p`: every bijection of p onto itself that passes the test above in
// similarity mode (options.mode and the scale bounds are ignored: a symmetry never scales),
// the identity first, then in lexicographic order of the mappings, at most `limit` in all.
// transform is the rotation about the centroid that realises each. A square street block
// has four, a plain edge two; the analyzer uses them so that the same expansion of a
// symmetric pattern is counted once, not once per symmetry. A degenerate pattern reports
// only the identity.
std::vector<IsomorphismMatch> geometric_automorphisms(const Pattern& p, const IsomorphismOptions& options = {},
                                                     std::size_t limit = 64);

// A hash of what isomorphism cannot change and noise cannot blur: vertex and edge counts,
// the multiset of (degree, symbol) over vertices and of (degree, degree) over edges. Equal
// for isomorphic patterns, so it buckets candidates before the full test. Pass
// with_symbols = false to bucket for respect_symbols = false. No geometry goes in: any
// quantised geometric quantity would split isomorphic patterns lying near a bin border.
// Stable across runs and platforms.
std::uint64_t invariant_hash(const Pattern& p, bool with_symbols = true);

} // namespace ggg
