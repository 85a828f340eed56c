#pragma once
// Forward rewriting (paper 3.2-3.3). One derivation step rewrites every nonterminal vertex
// of the graph at once: for each, the rule's S is mapped into the vertex's frame, the vertex
// and its edges are erased, S is placed, and the embedding points are connected to host
// vertices found within the tolerance. Steps are applied sequentially in vertex order so a
// step is deterministic; it reads as simultaneous because every rewrite of a step sees the
// host as it was plus what the step has placed so far, never a half-rewritten vertex.
//
// Merging: a placed vertex that lands within the tolerance of a vertex already there is that
// vertex, so every place is one vertex. Where two nonterminals with different rewrites meet,
// the vertex keeps both (GeometricGraph::more_rewrites) and the next step rewrites it once for
// each: the corners two Sierpinski triangles share stay one vertex, step after step. Vertices
// of an instance of a learned grammar are the exception: they never merge with another
// nonterminal, since each must decode to its own streets.
#include <cstdint>
#include <string>
#include <vector>

#include "ggg/graph/geometric_graph.hpp"
#include "ggg/grammar/grammar.hpp"
#include "ggg/progress.hpp"

namespace ggg {

struct DeriveOptions {
    int max_steps = 1;
    std::size_t max_vertices = 1'000'000;
    // Distance within which an embedding point finds its partner and placed vertices merge.
    double tolerance = 0.05;
    // true: `tolerance` is a fraction of the rewritten vertex's frame scale; false: metres.
    bool tolerance_relative = true;
    // true: a rewrite happens only when every embedding point finds a partner among the
    // vertices that the step does not rewrite; false (relaxed, paper 3.3): missing partners
    // are skipped.
    bool strict = false;
    // The caller has already checked the grammar with validate(): derive skips doing it again
    // (it costs time in the size of the grammar, which matters to callers deriving thousands of
    // small graphs with one large learned grammar).
    bool grammar_validated = false;
};

struct StepReport {
    std::size_t rewrites = 0;          // nonterminals rewritten
    std::size_t refused = 0;           // strict mode: rewrites refused for a missing partner
    std::size_t embedding_edges = 0;   // edges made by embedding points
    std::size_t missed_embeddings = 0; // relaxed mode: points with no partner
    std::size_t merged_vertices = 0;   // placed vertices that landed on existing ones
};

// Which rewrite placed a vertex: the instance of a learned grammar (-1: a rule used without
// one) and the index of the rule vertex it is. {-1, -1} for a vertex that was there before.
struct Placement {
    std::int32_t instance = -1;
    std::int32_t rule_vertex = -1;
    bool operator==(const Placement&) const = default;
};

struct DeriveReport {
    int steps = 0;                  // steps applied
    bool stopped_by_budget = false; // a step was not applied because it would pass max_vertices
    bool nothing_to_rewrite = false;
    bool converged = false;         // a step changed nothing (e.g. P -> P), so no later one would
    StepReport totals;
    // For each vertex of the result, the vertex of the input graph it is (-1 for a vertex a
    // rule placed), so callers can carry their own per-vertex data across a derivation.
    std::vector<VertexId> source_vertex;
    // For each vertex of the result, the rewrite that placed it (see Placement).
    std::vector<Placement> placed_by;
};

// One step on `graph` in place. Returns false and leaves the graph unchanged when the
// step would pass `options.max_vertices` (or nothing can be rewritten).
// `source`, when given, receives for each vertex of the new graph the vertex of the old one
// it is, or -1 for a placed vertex; `placed`, the rewrite that placed it.
//
// A nonterminal vertex that carries an instance of a learned grammar (graph.instances) is
// rewritten with that instance's frame correction, residuals, embedding and road classes,
// and the nonterminals it places carry the instance's children: that is how a learned
// grammar decodes back to the streets it came from, by the same rewriting as any other.
bool derive_step(GeometricGraph& graph, const Grammar& grammar, const DeriveOptions& options, StepReport* report = nullptr,
                 bool* over_budget = nullptr, std::vector<VertexId>* source = nullptr,
                 std::vector<Placement>* placed = nullptr);

// Up to options.max_steps steps from `graph` (the axiom, or a road network to grow).
DeriveReport derive(GeometricGraph& graph, const Grammar& grammar, const DeriveOptions& options,
                    const ProgressCallback& progress = {});

// Places nonterminal `symbol` of `grammar` as a new vertex of `graph` at `position` with the
// given frame (what a user does with the 3D cursor). Returns the new vertex.
VertexId place_nonterminal(GeometricGraph& graph, Symbol symbol, const Vec2& position, const Frame& frame);

} // namespace ggg
