#pragma once
// Grammar files: JSON, versioned ("format": "ggg-grammar", "version": 1), described with a
// schema in docs/grammar-format.md. Symbols are written by name; numbers are written as the
// shortest decimal that reads back to the same double, so write -> read is the identity.
#include <string>

#include <nlohmann/json_fwd.hpp>

#include "ggg/grammar/grammar.hpp"

namespace ggg {

inline constexpr int grammar_file_version = 1;

nlohmann::json grammar_to_json(const Grammar& grammar);
// Throws GrammarError naming the place of the problem ("rules[0].vertices[2].symbol: unknown symbol 'Q'").
Grammar grammar_from_json(const nlohmann::json& document, const std::string& name);

void write_grammar(const Grammar& grammar, const std::string& path);
Grammar read_grammar(const std::string& path);
Grammar parse_grammar(const std::string& text, const std::string& name);

} // namespace ggg
