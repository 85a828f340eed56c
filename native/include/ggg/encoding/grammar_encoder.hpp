#pragma once
// The graph grammar encoder (paper 6): a road graph becomes a hierarchy of rules and an axiom.
//
// Level by level, the analyzer finds the patterns that repeat in the current graph; the
// encoder takes them in order of description-length gain and, as long as a pattern still
// pays for its rule, replaces each of its chosen (non-overlapping) occurrences by one
// nonterminal vertex. The vertex sits on the occurrence's vertex nearest the most important
// roads (Fig. 10c), carries the occurrence's frame, and is joined to everything the
// occurrence was joined to. The next level analyses that graph, where a nonterminal only
// matches the same nonterminal; what is left when nothing repeats is the axiom.
//
// Each replaced occurrence is an instance of its rule (grammar.hpp, RuleInstance): the
// rule keeps the shape its occurrences share, the instance its own frame correction and
// embedding, which outside streets each of its vertices joins (Fig. 10d). Paper mode stops
// there: decoding puts every vertex where the rule's shape says, so positions carry the
// error of that shape (Fig. 11). Lossless mode also stores each vertex's residual, a
// multiple of `quantum_m`, so decoding gives back exactly the input's edges and every vertex
// within quantum_m of where it was.
//
// Decoding (decoding.hpp) is forward derivation (rewriting.hpp) of the axiom; the encoder
// runs it itself to compute residuals and embedding against the positions the derivation
// will really produce, so nothing it stores depends on a second, private decoder.
#include <cstddef>
#include <string>
#include <vector>

#include "ggg/analysis/analyzer.hpp"
#include "ggg/graph/geometric_graph.hpp"
#include "ggg/grammar/grammar.hpp"
#include "ggg/progress.hpp"

namespace ggg {

struct LearnOptions {
    // The analysis run at every level (grid, cut, max order, scale mode, constraints...).
    AnalyzeOptions analysis = default_analysis();
    bool lossless = false;
    // A piece of the input the user picked (vertex ids, a connected induced subgraph, paper
    // Fig. 18a "user selected"): its pattern becomes the first rule, with every copy the
    // analyzer's seeded search finds (that do not overlap), whatever its gain, before the
    // automatic passes. Empty = none.
    std::vector<VertexId> seed;
    // Most passes of the encoder (each adds at most one level of hierarchy); 0 = until
    // nothing repeats.
    int max_levels = 64;
    // Complete encoding (paper Fig. 13): when nothing pays for a rule any more, every pattern
    // that still repeats (down to two vertices) is encoded level after level, and what never
    // repeats becomes one last rule used once, so that the axiom is a single vertex. The
    // grammar is larger than the default one; it shows the whole hierarchy.
    bool complete = false;
    // Positions, shifts and lossless residuals are multiples of this; a power of ten between
    // 1e-9 and 1e-2 m. Rounding each coordinate to it moves a vertex by at most 0.71 quantum.
    // The default is OpenStreetMap's own precision (1e-7 degrees, about 1 cm): lossless to
    // what the map holds.
    double quantum_m = 1e-2;
    // A nonterminal of an occurrence must lie in the same frame, relative to the occurrence,
    // as in the pattern's other occurrences: rotation within this many degrees, scale within
    // this factor (paper 6: "a nonterminal only matches the same nonterminal with a
    // consistent frame"). Occurrences that do not are left for a later level.
    double frame_tolerance_deg = 30.0;
    double frame_scale_tolerance = 1.5;
    // Occurrences whose vertices lie farther from the pattern's shape than this (RMS,
    // relative to the pattern's RMS radius) are not encoded with it: the analyzer's polar
    // grid groups loosely, and a rule is only as good as the shape its instances share.
    // 0 = keep every occurrence.
    double max_shape_error = 0.15;
    // No street vertex of an occurrence may lie farther than this (metres) from where the
    // rule's shape, fitted to the occurrence, puts it: in paper mode that misfit is how far
    // decoding moves the vertex (Fig. 11), so this bounds the paper-mode error of every
    // vertex. A large copy can pass the relative test above and still bend one street by
    // tens of metres. 0 = no bound.
    double max_vertex_error_m = 7.0;

    static AnalyzeOptions default_analysis() {
        AnalyzeOptions a;
        a.detection.max_order = 6;
        return a;
    }
};

// Throws UsageError naming the first bad option.
void check_options(const LearnOptions& options);

// One pass of the encoder: an analysis of the current graph and the rules it yields. The
// rules of pass n place nonterminals of earlier passes, so the grammar's levels of
// hierarchy (Encoding::levels, how deep instances nest) are at most the number of passes.
struct LevelReport {
    int level = 0;                // pass, 1 = the first encoding of the input
    std::size_t vertices = 0;     // of the graph analysed at this level
    std::size_t edges = 0;
    std::size_t rules = 0;        // rules emitted at this level
    std::size_t instances = 0;    // occurrences replaced by nonterminals
    std::size_t frame_rejected = 0; // occurrences left out for an inconsistent frame
    std::size_t shape_rejected = 0; // ... for a shape too far from the pattern's
    std::size_t error_rejected = 0; // ... for a street vertex farther than max_vertex_error_m
    // Bytes of the packed CBOR file this level's rules save, as learning counts them to
    // choose what pays (Encoder::packed_gain): the graph's bytes less these, level after
    // level, is about what the grammar weighs. Negative where a rule was taken that does not
    // pay (the first rule of a small town, complete encoding).
    double bytes_saved = 0.0;
    double seconds = 0.0;
};

struct RoundTrip {
    bool edges_equal = false;          // the decoded graph has exactly the input's edges
    bool classes_equal = false;        // ... and each with its road class
    std::size_t missing_edges = 0;     // input edges the decoded graph lacks
    std::size_t extra_edges = 0;       // decoded edges the input lacks
    std::size_t unplaced_vertices = 0; // input vertices the decoding merged into another
    double max_displacement_m = 0.0;   // over the input vertices
    double mean_displacement_m = 0.0;
};

struct LearnResult {
    Grammar grammar;
    std::vector<LevelReport> levels;
    double analysis_seconds = 0.0;
    double encoding_seconds = 0.0; // building rules, the graphs of each level, residuals, embedding
    RoundTrip roundtrip; // decode(grammar) against the input
    std::size_t axiom_edges = 0; // of the last level's graph (the axiom with its nonterminals' edges)
    // A level's analysis ran out of the time or memory budget (DetectionOptions::max_seconds,
    // max_memory_mb; the time budget is the whole learning's): the levels found so far are
    // the grammar, complete and decodable, and no further level was tried.
    bool stopped_by_budget = false;
};

// Learns a grammar of `graph` (its vertices, edges and road classes; edge shapes, names and
// OSM ids are not part of a grammar). Deterministic: the same graph and options give the
// same grammar, whatever the number of threads. Progress is reported per level; a cancel
// throws ggg::Cancelled. Throws UsageError for bad options and InputError for a graph
// without edges.
LearnResult learn_grammar(const GeometricGraph& graph, const LearnOptions& options = {},
                          const ProgressCallback& progress = {});

} // namespace ggg
