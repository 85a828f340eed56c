#pragma once
// The encoder of the learning (encoding/grammar_encoder.hpp), private to it. Its stages:
// the levels, each analysed and contracted (grammar_encoder.cpp); a rule made of one
// isogroup's copies (rule_encoding.cpp); the grammar built from the rules and instances,
// each instance's frame correction, residuals and embedding set against a real
// derivation, and the round trip checked (grammar_assembly.cpp).
#include <chrono>
#include <cmath>
#include <complex>
#include <cstdint>
#include <optional>
#include <vector>

#include "ggg/analysis/geometric_isomorphism.hpp"
#include "ggg/analysis/pattern.hpp"
#include "ggg/encoding/grammar_encoder.hpp"
#include "ggg/grammar/grammar.hpp"
#include "ggg/graph/geometric_graph.hpp"
#include "ggg/progress.hpp"

namespace ggg::encoding_detail {

using Clock = std::chrono::steady_clock;
using Complex = std::complex<double>;

// Rounded to a multiple of 1 / inverse_step, where inverse_step is a power of ten: the
// result is the double nearest to a short decimal, which the JSON writer prints as such.
inline double round_to(double x, double inverse_step) {
    double r = 0.0;
    if (inverse_step >= 1.0) {
        r = std::round(x * inverse_step) / inverse_step;
    } else {
        const double step = std::round(1.0 / inverse_step);
        r = std::round(x / step) * step;
    }
    return r == 0.0 ? 0.0 : r; // no "-0.0" in the file
}
inline Vec2 round_to(const Vec2& p, double inverse_step) { return {round_to(p.x(), inverse_step), round_to(p.y(), inverse_step)}; }

// The power of ten 10^k with 10^-k <= step (so rounding to it errs by at most step / 2).
inline double inverse_power_of_ten(double step) { return std::pow(10.0, std::ceil(-std::log10(step))); }

inline double round_significant(double x, int digits) {
    if (x == 0.0 || !std::isfinite(x)) return x;
    const int exponent = static_cast<int>(std::floor(std::log10(std::abs(x))));
    return round_to(x, std::pow(10.0, digits - 1 - exponent));
}

inline Complex linear(const Similarity2& s) { return {s.a, s.b}; }

// Frames the derivation corrects afterwards (the axiom's, the rules' T_i) need few digits;
// an instance's correction is what places it, to about 1e-6 of its size. The steps are the
// fixed units of the packed grammar file (io/grammar_packing.cpp).
inline Frame frame_of(Complex z, double scale_inverse_step = 1e4) {
    return {std::max(round_to(std::abs(z), scale_inverse_step), 1.0 / scale_inverse_step), round_to(std::arg(z) * 180.0 / M_PI, 100)};
}
// An axiom frame's scale is the size of its copy in metres: to the centimetre, the
// positions' own quantum (a copy of 600 m then takes three bytes of CBOR, not five).
inline constexpr double axiom_scale_inverse_step = 1e2;
// A rule's embedding points (where streets around it are expected, for a user placing it
// and for the instances that reuse them) to a hundredth of the rule's size: a street's end
// is not known closer, and a point then takes four or five bytes of CBOR, not seven.
inline constexpr double rule_point_inverse_step = 1e2;
inline Frame correction_of(Complex z) { return {std::max(round_to(std::abs(z), 1e6), 1e-6), round_to(std::arg(z) * 180.0 / M_PI, 1e4)}; }

// 1 / quantum as the exact power of ten (1.0 / 1e-6 is not exactly 1e6).
inline double inverse_of(double quantum) { return std::pow(10.0, std::round(-std::log10(quantum))); }

// The one-digit decimal m × 10^e, computed as the packed grammar file reads it back.
inline double one_digit_decimal(double mantissa, int exponent) {
    return exponent >= 0 ? mantissa * std::pow(10.0, exponent) : mantissa / std::pow(10.0, -exponent);
}

// Bytes of an integer in CBOR.
inline double cbor_bytes(std::int64_t k) {
    const std::uint64_t a = k >= 0 ? static_cast<std::uint64_t>(k) : static_cast<std::uint64_t>(-(k + 1));
    return a < 24 ? 1 : a < 256 ? 2 : a < 65536 ? 3 : a < 4294967296ULL ? 5 : 9;
}

// A vertex of a level's graph: a street vertex of the input, or a nonterminal standing for
// an instance.
struct Node {
    bool nonterminal = false;
    std::int32_t id = 0; // input vertex, or instance
};

struct InstanceDraft {
    Symbol symbol = 0;
    std::vector<Node> members;  // per rule vertex
    Similarity2 fit;            // rule coordinates -> metres, least squares over the occurrence
    Similarity2 frame;          // the same with t = the nonterminal's position
    std::int32_t parent = -1;   // the instance whose rule placed this one's nonterminal
    // Its number in the derivation order before the axiom's nonterminals were walked
    // (order_axiom_nonterminals): which of equally joined instances gives its rule the
    // embedding, whatever the order the file stores them in.
    std::int32_t first_number = -1;
};

struct RuleDraft {
    Rule rule;
    int level = 0;
};

class Encoder {
public:
    // How the copies of a group are taken: only where the rule pays for itself (the default),
    // wherever it repeats (complete encoding, when nothing pays any more), the user's seed
    // (whatever it saves), or once (complete encoding's last rule: what never repeated).
    enum class Take { paying, repeating, seed, once };

    Encoder(const GeometricGraph& input, const LearnOptions& options, const ProgressCallback& progress)
        : input_(input), options_(options), progress_(progress) {}

    LearnResult run();

private:
    void start_level_graph();

    Vec2 node_position(const Node& n) const {
        return n.nonterminal ? instances_[static_cast<std::size_t>(n.id)].frame.t : input_.positions[static_cast<std::size_t>(n.id)];
    }

    // One level: analyse, take the groups that pay, contract their occurrences. False when
    // nothing was encoded.
    bool encode_level(int level, bool seeded, Take take = Take::paying);

    // Complete encoding's last level: the whole graph left becomes the right side of one rule
    // used once, and the axiom its single nonterminal.
    void encode_rest(int level);

    // Makes a rule of `group` from those of its occurrences that are free, fit its shape and
    // sit in consistent frames, and records an instance for each; nothing when too few are
    // left (or, paying, when they no longer pay).
    // With `price_only`, nothing is encoded: returns what the group would save both ways
    // (packed_gain), or nothing where too few of its copies would be kept. Encoding, it
    // returns nothing.
    struct GroupGains {
        double paper;  // its copies against what they replace
        double strict; // also less its rule and its residuals
    };
    std::optional<GroupGains> encode_group(const Isogroup& group, Take take, int level, const Adjacency& adj, std::vector<char>& used,
                                           std::vector<std::int32_t>& level_instances, LevelReport& lr, bool price_only = false);

    // What encoding these occurrences as instances of one rule saves, in bytes of the packed
    // grammar file against the packed graph (docs/learning.md#size): the positions and
    // inside edges they no longer store, less each instance's frame, residuals (lossless)
    // and the extra bytes of its embedding, less the rule itself; not `strict`, the copies
    // only (neither the rule nor the residuals).
    double packed_gain(const Isogroup& group, const std::vector<std::vector<VertexId>>& occs, const std::vector<Similarity2>& fits,
                       const std::vector<Frame>& transforms, const Adjacency& adj, bool strict) const;

    // The largest distance from a street vertex of the occurrence (labelled as the pattern)
    // to where `fit` puts the pattern's vertex: the vertex's paper-mode decoding error.
    // Nonterminals are left out, since their instances correct their own frames.
    double worst_street_misfit(const Pattern& pattern, const Similarity2& fit, const std::vector<VertexId>& occ) const;

    // The occurrences to encode: a largest set that shares no vertex, taken first among the
    // occurrences turned like most of them (modulo the pattern's n-fold symmetry), then among
    // the others. A district tiled by copies that all face one way is regular again one
    // level up, where a tiling of mixed orientations is not.
    void choose_aligned(std::vector<std::vector<VertexId>>& occs, std::vector<Similarity2>& fits, int n) const;

    // Keeps the occurrences whose nonterminals sit in the pattern's usual frame, and sets
    // the rule's transform T_i of each nonterminal vertex to that frame (the mean over the
    // occurrences in the most common 30-degree sector).
    void consistent_frames(const Isogroup& group, std::vector<std::vector<VertexId>>& chosen, std::vector<Similarity2>& fits,
                           std::vector<Frame>& transforms) const;

    // The next level's graph: every occurrence replaced by its nonterminal, joined to what
    // the occurrence was joined to (the most important class where several streets merge).
    void contract(const std::vector<std::int32_t>& level_instances, const std::vector<char>& used);

    // Orders the axiom's nonterminals along a walk through their positions: the packed
    // axiom stores each position as a step from the one before.
    void order_axiom_nonterminals();

    // Numbers the instances in the order the derivation meets them (the axiom's
    // nonterminals, then level by level the nonterminals each instance places), the order
    // the packed grammar file implies, so that a learned grammar reads back as it was made.
    void number_in_derivation_order();

    // Rules, the axiom (the last level's graph) and the instance skeletons.
    Grammar build_grammar();

    // Derives the grammar level by level, as decoding will, and sets each instance's frame
    // correction (and residuals) against the frame the derivation hands it. Records where
    // every input vertex lands.
    void simulate(Grammar& grammar);

    // Every input edge that is neither a rule edge nor an axiom edge becomes an embedding
    // point of one of its ends, aimed at where the derivation puts the other end.
    void embed(Grammar& grammar);

    void check_roundtrip();

    const GeometricGraph& input_;
    Clock::time_point start_;
    const LearnOptions& options_;
    IsomorphismOptions symmetry_options_ = [this] {
        IsomorphismOptions o;
        o.tolerance = options_.analysis.detection.merge_tolerance;
        return o;
    }();
    const ProgressCallback& progress_;
    LearnResult result_;
    double progress_done_ = 0.0;

    // Whether a group must also pay for its rule's own bytes and its residuals (packed_gain).
    // Off only for the first pass of a graph where nothing pays that way: a small town still
    // gets the patterns whose copies would pay for themselves in paper mode.
    bool strict_gain_ = true;
    // Mean bytes of one vertex's position and of one edge in the packed graph of the input.
    double vertex_bytes_ = 6.0;
    double edge_bytes_ = 5.0;

    GeometricGraph graph_;   // the current level's graph
    std::vector<Node> nodes_; // per vertex of graph_
    std::vector<InstanceDraft> instances_;
    std::vector<RuleInstance> encoded_; // per instance: what goes into the grammar
    std::vector<std::vector<VertexId>> occurrence_of_; // this level's instances: vertices of graph_
    std::vector<RuleDraft> rules_;
    std::vector<int> rotations_; // per rule: the rotations that map its pattern onto itself
    std::vector<std::int32_t> placer_;      // per input vertex: the instance placing it, -1 = the axiom
    std::vector<std::int32_t> axiom_index_; // per input vertex: its axiom vertex, -1 = none
    std::vector<Vec2> decoded_;             // per input vertex: where the derivation puts it
    std::vector<char> placed_;
    bool derivation_matches_ = false; // simulate: the derivation gave exactly the input's vertices
    std::vector<Similarity2> effective_;    // per instance: the frame its rule is placed in
    // Per derivation step (0 = the axiom): the nonterminals it places, where, and by which
    // instance (-1: the axiom).
    struct PlacedNonterminal {
        Vec2 position;
        std::int32_t instance;
    };
    std::vector<std::vector<PlacedNonterminal>> step_nonterminals_;
};

} // namespace ggg::encoding_detail
