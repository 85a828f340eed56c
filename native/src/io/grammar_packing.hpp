#pragma once
// The packed form of a learned grammar (grammar file version 4, docs/grammar-format.md; the
// reader takes versions 2 and 3 too: version 3 stores the axiom's nonterminals one by one with
// their symbols, version 2 also the rule points, class changes and links densely):
// every number an integer in a fixed unit, columns instead of objects, and nothing stored
// that the derivation already knows (an instance's symbol, which instance rewrites which
// nonterminal). The same document is written as JSON text or as CBOR, so that a grammar's
// size can be set fairly beside the graph it encodes in either encoding.
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "ggg/grammar/grammar.hpp"
#include "ggg/graph/geometric_graph.hpp"
#include "json_util.hpp"

namespace ggg::io_detail {

inline constexpr int packed_grammar_version = 5;

// The packed document of a learned grammar, or nothing when the grammar holds something the
// packed form has no place for (a value off its unit, a nonterminal without its instance):
// the writer then keeps the column form of version 1.
std::optional<nlohmann::json> pack_grammar(const Grammar& grammar);
// Throws GrammarError naming the place ("encoding.embedding[40]: ...").
Grammar unpack_grammar(const nlohmann::json& document, const std::string& name);

// The graph in the same kind of columns: positions in quanta and delta-coded, edges as
// the first end's step from the previous edge's and the second end's from the first.
nlohmann::json pack_graph(const GeometricGraph& graph, double quantum_m);

// The fixed-unit integers of the packed form: `k` steps of 1 / inverse (a power of ten).
double from_steps(std::int64_t k, double inverse);
// The one-digit decimal m × 10^e (the tolerances), computed as the reader computes it.
double one_digit_decimal(double mantissa, int exponent);
// Bytes of an integer in CBOR.
int cbor_bytes(std::int64_t k);

// The name and origin of a grammar file, read the same way in either version.
void read_grammar_header(const JsonReader<GrammarError>& reader, const nlohmann::json& document, Grammar& grammar);
// Edges as (step of the first end from the previous edge's, second end minus first, class).
nlohmann::json edge_steps(const std::vector<GrammarEdge>& edges);

// A grammar file in CBOR starts with a map; JSON text with '{' or blanks.
bool looks_like_cbor(const std::string& bytes);
// Parses CBOR with the bounds of the JSON parser (json_util.hpp); any failure is a
// GrammarError naming the file.
nlohmann::json parse_cbor(const std::string& bytes, const std::string& name);

} // namespace ggg::io_detail
