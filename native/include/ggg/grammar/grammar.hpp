#pragma once
// Geometric graph grammar (paper 3.2): rules q -> S/B and an axiom. A rule's right side S
// is a small geometric graph in the rule's frame; each of its vertices carries a symbol
// (0 = terminal street vertex, k = nonterminal of rule k), a transform T_i that gives the
// frame of the vertex for the next rewriting, and embedding points p_ij: offsets from the
// vertex, in the rule's frame, where a vertex of the host graph is expected to connect.
//
// Frames are kept as scale and rotation in degrees, the numbers a person writes in a
// grammar file, so that a file reads back to exactly the grammar that wrote it.
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "ggg/graph/geometric_graph.hpp"
#include "ggg/graph/similarity.hpp"

namespace ggg {

using Symbol = std::uint32_t; // 0 = terminal

struct Frame {
    double scale = 1.0;
    double rotation_deg = 0.0;

    // The similarity with this scale and rotation whose origin sits at `origin`.
    Similarity2 at(const Vec2& origin) const;
    bool operator==(const Frame&) const = default;
};

struct EmbeddingPoint {
    Vec2 offset = Vec2::Zero(); // from the vertex, in the rule's frame
    HighwayClass highway = HighwayClass::residential; // class of the connecting edge
    bool operator==(const EmbeddingPoint&) const = default;
};

struct RuleVertex {
    Vec2 position = Vec2::Zero();
    Symbol symbol = 0;
    Frame transform; // T_i: the frame of this vertex relative to the rule's frame
    std::vector<EmbeddingPoint> embedding;
    bool operator==(const RuleVertex&) const = default;
};

struct GrammarEdge {
    std::int32_t a = 0;
    std::int32_t b = 0;
    HighwayClass highway = HighwayClass::residential;
    bool operator==(const GrammarEdge&) const = default;
};

struct Rule {
    Symbol symbol = 0; // the left side q (> 0)
    std::vector<RuleVertex> vertices;
    std::vector<GrammarEdge> edges;
    std::uint64_t uses = 0; // how often the rule occurs (learned grammars); 0 = unknown
    // Metres per unit of the rule's coordinates in its instances (their median; learned
    // grammars), the size at which to place it by hand or in growth; 0 = unknown.
    double size_m = 0.0;
    bool operator==(const Rule&) const = default;
};

struct AxiomVertex {
    Vec2 position = Vec2::Zero();
    Symbol symbol = 0;
    Frame frame;
    bool operator==(const AxiomVertex&) const = default;
};

// One use of a rule in a learned grammar: an occurrence the encoder replaced by a
// nonterminal (paper 6). The rule holds what its occurrences share; an instance holds what
// is its own, so that the derivation puts its streets back where they were: how its frame
// differs from the one its parent hands down, its own embedding (which streets around it
// it joins), and in lossless mode the residual of every vertex.
struct RuleInstance {
    struct Link {
        std::int32_t vertex = 0; // rule vertex the embedding edge starts from
        EmbeddingPoint point;    // offset from that vertex, in the instance's frame
        bool operator==(const Link&) const = default;
    };

    Symbol symbol = 0;
    // Rotation and scale on top of the frame the nonterminal vertex carries (its parent's
    // frame and the rule's transform T_i), then a shift of the frame's origin in metres:
    // together they put the rule where this occurrence was, whatever its parent's shape did.
    Frame correction;
    Vec2 shift = Vec2::Zero();
    // Per rule vertex, metres added to its placed position (lossless mode); empty = none.
    std::vector<Vec2> residuals;
    // Per rule vertex, the instance rewriting the nonterminal placed there (-1: the rule
    // alone); empty = none.
    std::vector<std::int32_t> children;
    // This instance's embedding, which replaces the rule's: the rule's points it uses as
    // they are (indices into the rule's points, counted vertex by vertex), and its own.
    std::vector<std::int32_t> rule_points;
    std::vector<Link> embedding;
    // Links named by their partner instead of aimed at it: the edge from rule vertex `vertex`
    // goes to the `rank`-th nearest vertex to it (from 0) among those present when the
    // instance's embedding is resolved, its own vertices left out. Decoding is deterministic,
    // so the learner knows that rank; a small integer costs less than an offset, and needs
    // no tolerance.
    static constexpr std::int32_t max_rank = 255; // beyond it an offset is as short, and a decoder's search stays small
    struct Neighbour {
        std::int32_t vertex = 0;
        std::int32_t rank = 0;
        HighwayClass highway = HighwayClass::residential;
        bool operator==(const Neighbour&) const = default;
    };
    std::vector<Neighbour> neighbours;
    // Tolerance of this instance's embedding and merging in metres; 0 = the grammar's.
    // An instance among streets far apart can afford a wide one, which lets it reuse the
    // rule's embedding points instead of storing its own.
    double tolerance_m = 0.0;
    // Rule edges whose road class differs in this instance: (edge index, class).
    std::vector<std::pair<std::int32_t, HighwayClass>> edge_classes;
    bool operator==(const RuleInstance&) const = default;
};

// What a learned grammar keeps besides its rules and axiom: the instances and how to
// decode them. Empty (mode "") for a hand-written grammar.
struct Encoding {
    std::string mode;         // "paper" (rule geometry only) or "lossless" (with residuals)
    int levels = 0;           // derivation steps that decode the axiom completely
    double tolerance_m = 0.0; // decoding tolerance (absolute metres)
    double quantum_m = 0.0;   // residuals are multiples of this (lossless mode)
    std::vector<RuleInstance> instances;
    std::vector<std::int32_t> axiom_instances; // per axiom vertex, -1 = none; empty = none
    // What the grammar decodes to, recorded by the learner and checked by every decoding, so
    // that a damaged grammar is an error rather than streets with pieces missing. -1 = not
    // recorded (grammars written before it was).
    std::int64_t decoded_vertices = -1;
    std::int64_t decoded_edges = -1;
    // The length of all its streets (straight between their ends) in whole metres: a damaged
    // grammar whose links still find as many partners (links by rank always find one) joins
    // other streets, of another length. -1 = not recorded.
    std::int64_t decoded_length_m = -1;
    bool empty() const { return mode.empty(); }
    bool operator==(const Encoding&) const = default;
};

struct Grammar {
    std::string name;
    std::vector<std::string> symbol_names; // symbol k is symbol_names[k - 1]
    std::vector<Rule> rules;               // at most one rule per symbol
    GeoOrigin origin;                      // where the axiom sits on the earth (0, 0 = abstract)
    std::vector<AxiomVertex> axiom_vertices;
    std::vector<GrammarEdge> axiom_edges;
    Encoding encoding; // learned grammars only

    // The rule rewriting `symbol`, or nullptr when the symbol has none.
    const Rule* rule_for(Symbol symbol) const;
    // Name of a symbol ("terminal" for 0).
    std::string symbol_name(Symbol symbol) const;
    // The axiom as a graph: nonterminal vertices carry their frames (and, for a learned
    // grammar, their instances).
    GeometricGraph axiom_graph() const;

    bool operator==(const Grammar& other) const;
};

// Checks everything a derivation relies on; throws GrammarError naming the place
// ("rules[1].vertices[2].symbol: unknown symbol 7").
void validate(const Grammar& grammar);

} // namespace ggg
