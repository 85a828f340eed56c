// Grammar reader (ggg::parse_grammar from text). What it accepts must validate or fail with
// a GrammarError, and must write and read back to the same grammar (grammar_file.hpp
// promises write -> read is the identity).
#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "fuzz_common.hpp"
#include "ggg/encoding/decoding.hpp"
#include "ggg/error.hpp"
#include "ggg/io/grammar_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    ggg::Grammar grammar;
    try {
        grammar = ggg::parse_grammar(text, "fuzz.grammar.json");
    } catch (const ggg::Error&) {
        return 0;
    }
    ggg::Grammar again;
    try {
        again = ggg::grammar_from_json(ggg::grammar_to_json(grammar), "written");
    } catch (const ggg::Error& e) {
        ggg_fuzz::fail(std::string("a grammar read from a file does not read back after writing: ") + e.what());
    }
    if (!(again == grammar)) ggg_fuzz::fail("a grammar read from a file reads back different after writing");
    try {
        ggg::validate(grammar);
        (void)ggg::rule_levels(grammar);
        (void)grammar.axiom_graph();
    } catch (const ggg::Error&) {
    }
    return 0;
}
