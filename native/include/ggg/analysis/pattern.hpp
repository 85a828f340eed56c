#pragma once
// What the analyzer (paper 5.1) finds and counts: a pattern is a small geometric graph in a
// canonical frame, an occurrence is one place in the host graph where it sits, an isogroup
// (paper 3.1) is a pattern with all its occurrences.
//
// The canonical frame only removes translation and size (centroid at the origin, RMS distance
// to the centroid 1). It keeps the rotation: there is no stable way to pick an orientation of
// a noisy, possibly symmetric street pattern, and comparisons (geometric_isomorphism.hpp)
// solve for the rotation anyway. The size that the frame removes is kept in metres_per_unit,
// because to a planner a 100 m block and a 1 km block are different patterns (rigid and
// range comparisons need it back).
#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "ggg/graph/geometric_graph.hpp"
#include "ggg/graph/similarity.hpp"

namespace ggg {

// Same alias as in grammar.hpp (the compiler checks that they agree); repeated because the
// analysis sits below the grammar in the pipeline and must not include it.
using Symbol = std::uint32_t; // 0 = terminal

struct Pattern {
    std::vector<Vec2> positions;           // canonical coordinates, one per vertex
    std::vector<Symbol> symbols;           // one per vertex, 0 = terminal street vertex
    std::vector<std::array<int, 2>> edges; // induced edges, a < b, sorted, no duplicates
    // How long one coordinate unit is in metres: the RMS radius of the vertices it was cut
    // from. 1 for a pattern whose coordinates are metres (or for a degenerate one).
    double metres_per_unit = 1.0;

    std::size_t size() const noexcept { return positions.size(); }
};

// Empty when `p` is well formed (at least one vertex, one symbol per vertex, finite
// coordinates, metres_per_unit > 0, edges in range with a < b, sorted, no duplicates),
// else the first problem. The comparison functions throw UsageError with this message.
std::string check_pattern(const Pattern& p);

// A pattern and every place it occurs (its occurrences). Occurrences are stored flat,
// because the analyzer makes millions of them: occurrence i maps pattern vertex j to graph
// vertex vertices[i * k + j] (k = order), and transforms[i] maps pattern coordinates to
// graph coordinates (metres) for it. An occurrence is an induced subgraph: the graph edges
// among its vertices are exactly the pattern's edges under that mapping.
struct Isogroup {
    Pattern pattern;
    std::vector<VertexId> vertices;
    std::vector<Similarity2> transforms;

    std::size_t order() const noexcept { return pattern.size(); }
    std::size_t frequency() const noexcept { return transforms.size(); }
    std::span<const VertexId> occurrence(std::size_t i) const {
        return {vertices.data() + i * order(), order()};
    }
};

// Empty when every occurrence of `group` is what Isogroup promises in `g` (ids in range and
// distinct, the induced edges equal to the pattern's, symbols equal, no two occurrences on
// the same vertex set) and its transform puts each pattern vertex within
// `max_residual` x (transform scale) of its graph vertex; else the first problem. The
// invariant checker of the analyzer's tests and a guard for isogroups built elsewhere.
std::string check_isogroup(const GeometricGraph& g, const Adjacency& adjacency, const Isogroup& group,
                           double max_residual);

// The subgraph of `g` induced by `vertices` (every edge of g with both ends among them),
// vertex i of the pattern being vertices[i], in the canonical frame. `frame`, when given,
// receives the map canonical -> graph coordinates: exactly the occurrence transform of
// these vertices. Throws UsageError for an empty list, an id out of range or a repeated id.
// A graph whose symbols column is empty counts as all terminal.
//
// This overload scans every edge of g (O(edges)); use the one with an Adjacency when
// cutting many patterns from the same graph.
Pattern induced_pattern(const GeometricGraph& g, std::span<const VertexId> vertices,
                        Similarity2* frame = nullptr);
// Same, in O(k log k + sum of degrees) with a prebuilt adjacency of `g`.
Pattern induced_pattern(const GeometricGraph& g, const Adjacency& adjacency,
                        std::span<const VertexId> vertices, Similarity2* frame = nullptr);

// Centroid and RMS radius of a point set: the canonical frame of a pattern. Degenerate when
// the radius is lost in the rounding of the coordinates themselves (all points at one place),
// where dividing by it would be noise.
struct Spread {
    Vec2 centroid = Vec2::Zero();
    double rms = 0.0;
    bool degenerate = true;
};
Spread spread_of(std::span<const Vec2> points);

struct SimilarityFit {
    Similarity2 transform;
    double rms_residual = 0.0; // sqrt(mean |transform(from_i) - to_i|^2), in `to` units
};

// Least-squares similarity (rotation, uniform scale, translation; no reflection) mapping
// from[i] onto to[i]: 2-D Umeyama in complex form, closed form and exact for exact data.
// When every `from` point coincides any linear part fits equally well; the result then is
// the pure translation between the centroids. When `to` collapses to a point (or is
// uncorrelated with `from`) the best fit has scale 0: check scale() before inverting.
// Throws UsageError when the spans are empty or of different lengths.
SimilarityFit fit_similarity(std::span<const Vec2> from, std::span<const Vec2> to);

} // namespace ggg
