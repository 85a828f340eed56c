// A fuzzed grammar derived under small budgets (ggg::derive, at most 2000 vertices and 4
// steps; the input's size picks strict or relaxed embedding and a relative or absolute
// tolerance), and decoded (ggg::decode_grammar) when it is a learned grammar. Reading,
// deriving and decoding may fail with a ggg::Error; nothing else may escape.
#include <cstdint>
#include <string>

#include "fuzz_common.hpp"
#include "ggg/encoding/decoding.hpp"
#include "ggg/error.hpp"
#include "ggg/io/grammar_file.hpp"
#include "ggg/grammar/rewriting.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    ggg::Grammar grammar;
    try {
        grammar = ggg::parse_grammar(text, "fuzz.grammar.json");
    } catch (const ggg::Error&) {
        return 0;
    }
    try {
        ggg::DeriveOptions options;
        options.max_steps = 4;
        options.max_vertices = 2000;
        options.strict = size % 2 == 1;
        options.tolerance_relative = size / 2 % 2 == 0;
        if (!options.tolerance_relative) options.tolerance = 1.0;
        ggg::GeometricGraph graph = grammar.axiom_graph();
        const ggg::DeriveReport report = ggg::derive(graph, grammar, options);
        if (graph.vertex_count() > options.max_vertices && graph.vertex_count() > grammar.axiom_vertices.size()) {
            ggg_fuzz::fail("derive passed its vertex budget: " + std::to_string(graph.vertex_count()) + " vertices");
        }
        if (report.source_vertex.size() != graph.vertex_count()) ggg_fuzz::fail("derive: source_vertex has the wrong size");
    } catch (const ggg::Error&) {
    }
    if (!grammar.encoding.empty()) {
        try {
            (void)ggg::decode_grammar(grammar);
        } catch (const ggg::Error&) {
        }
    }
    return 0;
}
