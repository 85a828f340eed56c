#pragma once
// The packed form of a learned grammar (grammar file version 6, docs/grammar-format.md; the
// reader takes versions 2 to 5 too, whose columns are named instead of placed, see
// grammar-format.md#versions):
// every number an integer in a fixed unit, columns instead of objects, and nothing stored
// that the derivation already knows (an instance's symbol, which instance rewrites which
// nonterminal). The same document is written as JSON text or as CBOR, so that a grammar's
// size can be set fairly beside the graph it encodes in either encoding.
#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "ggg/grammar/grammar.hpp"
#include "ggg/graph/geometric_graph.hpp"
#include "json_util.hpp"

namespace ggg::io_detail {

inline constexpr int packed_grammar_version = 6;

// Version 6 places each section's columns in an array instead of naming them: a small town's
// grammar is a few kilobytes, and the names took a tenth of it. The names, in place order,
// are written once here (the reader names a damaged column by them; the size report sums
// them by part). The encoding's array starts with its settings.
inline constexpr std::array<const char*, 11> rule_columns = {"uses", "size_cm", "vertices", "edges", "x", "y", "symbol", "transform", "embedding", "points", "edge_list"};
inline constexpr std::array<const char*, 7> axiom_columns = {"x", "y", "nonterminals", "symbol_order", "symbol", "frames", "edges"};
inline constexpr std::array<const char*, 5> encoding_settings = {"mode", "levels", "tolerance_m", "quantum_m", "decodes_to"};
inline constexpr std::array<const char*, 9> instance_columns = {"correction", "shift", "residuals", "tolerance", "rule_points", "embedding", "link_classes", "edge_classes", "neighbours"};
// The packed graph (what a grammar's size is set beside) in the same layout.
inline constexpr std::array<const char*, 3> graph_columns = {"x", "y", "edges"};
// The place of column or setting `name` in `section` ("rules", "axiom", "encoding", or
// "graph" of the packed graph), or nothing where the section has no such column.
std::optional<std::size_t> column_place(std::string_view section, std::string_view name);

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
