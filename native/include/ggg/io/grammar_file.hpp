#pragma once
// Grammar files: JSON, versioned ("format": "ggg-grammar", "version": 1), described with a
// schema in docs/grammar-format.md. Symbols are written by name; numbers are written as the
// shortest decimal that reads back to the same double, so write -> read is the identity.
#include <string>

#include <nlohmann/json_fwd.hpp>

#include "ggg/grammar/grammar.hpp"

namespace ggg {

// Version 1: the readable form (rules and axiom as objects; a learned grammar's instances as
// columns of decimals). Version 6: the packed form of a learned grammar (integers in fixed
// units, in columns placed in arrays, docs/grammar-format.md), written as JSON text or, for a
// path ending in ".cbor", as CBOR. The reader takes every version in either encoding, the
// older packed forms 2 to 5 too.
inline constexpr int grammar_file_version = 6;

nlohmann::json grammar_to_json(const Grammar& grammar);
// Throws GrammarError naming the place of the problem ("rules[0].vertices[2].symbol: unknown symbol 'Q'").
Grammar grammar_from_json(const nlohmann::json& document, const std::string& name);

void write_grammar(const Grammar& grammar, const std::string& path);
// True for a path ending in ".cbor": write_grammar writes CBOR there.
bool is_cbor_path(const std::string& path);
// The bytes write_grammar would write: JSON text (with its newline) or CBOR.
std::string grammar_bytes_text(const Grammar& grammar, bool cbor);
Grammar read_grammar(const std::string& path);
Grammar parse_grammar(const std::string& text, const std::string& name);

} // namespace ggg
