#include "ggg/io/grammar_file.hpp"

#include <climits>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <nlohmann/json.hpp>

#include "ggg/error.hpp"
#include "grammar_packing.hpp"
#include "json_util.hpp"

namespace ggg {

using nlohmann::json;

namespace {

json point(const Vec2& p) { return json::array({p.x(), p.y()}); }
json frame(const Frame& f) { return {{"scale", f.scale}, {"rotation_deg", f.rotation_deg}}; }

// Members at their default value (a terminal, the identity frame, no embedding, a
// residential street) are left out: the reader supplies them, and a learned grammar has
// thousands of vertices where they would only repeat the default.
json edges_json(const std::vector<GrammarEdge>& edges) {
    json out = json::array();
    for (const auto& e : edges) {
        if (e.highway == GrammarEdge{}.highway) out.push_back(json::array({e.a, e.b}));
        else out.push_back(json::array({e.a, e.b, std::string(highway_name(e.highway))}));
    }
    return out;
}

json encoding_json(const Encoding& enc) {
    json symbol = json::array(), scale = json::array(), rotation = json::array(), shift = json::array(), residuals = json::array(),
         children = json::array(), embedding = json::array(), classes = json::array(), rule_points = json::array(),
         tolerance = json::array(), neighbours = json::array();
    bool any_neighbour = false;
    for (const RuleInstance& inst : enc.instances) {
        symbol.push_back(inst.symbol);
        scale.push_back(inst.correction.scale);
        rotation.push_back(inst.correction.rotation_deg);
        shift.push_back(inst.shift.x());
        shift.push_back(inst.shift.y());
        json r = json::array();
        for (const Vec2& v : inst.residuals) {
            r.push_back(v.x());
            r.push_back(v.y());
        }
        residuals.push_back(std::move(r));
        children.push_back(inst.children);
        rule_points.push_back(inst.rule_points);
        tolerance.push_back(inst.tolerance_m);
        json links = json::array();
        for (const RuleInstance::Link& l : inst.embedding) {
            links.push_back(l.vertex);
            links.push_back(l.point.offset.x());
            links.push_back(l.point.offset.y());
            links.push_back(static_cast<int>(l.point.highway));
        }
        embedding.push_back(std::move(links));
        json ranked = json::array();
        for (const RuleInstance::Neighbour& l : inst.neighbours) ranked.insert(ranked.end(), {l.vertex, l.rank, static_cast<int>(l.highway)});
        any_neighbour |= !inst.neighbours.empty();
        neighbours.push_back(std::move(ranked));
        json ec = json::array();
        for (const auto& [edge, highway] : inst.edge_classes) {
            ec.push_back(edge);
            ec.push_back(static_cast<int>(highway));
        }
        classes.push_back(std::move(ec));
    }
    json class_names = json::array();
    for (int c = 0; c < highway_class_count; ++c) class_names.push_back(highway_name(static_cast<HighwayClass>(c)));
    json out{{"mode", enc.mode},
            {"levels", enc.levels},
            {"tolerance_m", enc.tolerance_m},
            {"quantum_m", enc.quantum_m},
            {"highway_classes", std::move(class_names)},
            {"axiom_instances", enc.axiom_instances},
            {"instances",
             {{"symbol", std::move(symbol)},
              {"scale", std::move(scale)},
              {"rotation_deg", std::move(rotation)},
              {"shift", std::move(shift)},
              {"residuals", std::move(residuals)},
              {"children", std::move(children)},
              {"tolerance_m", std::move(tolerance)},
              {"rule_points", std::move(rule_points)},
              {"embedding", std::move(embedding)},
              {"edge_classes", std::move(classes)}}}};
    if (any_neighbour) out["instances"]["neighbours"] = std::move(neighbours);
    if (enc.decoded_vertices >= 0) out["decodes_to"] = {{"vertices", enc.decoded_vertices}, {"edges", enc.decoded_edges}};
    if (enc.decoded_vertices >= 0 && enc.decoded_length_m >= 0) out["decodes_to"]["length_m"] = enc.decoded_length_m;
    return out;
}

} // namespace

json grammar_to_json(const Grammar& g) {
    // A learned grammar is data: packed (version 6) wherever its values fit the packed units.
    if (!g.encoding.empty()) {
        if (auto packed = io_detail::pack_grammar(g)) return std::move(*packed);
    }
    json rules = json::array();
    for (const Rule& r : g.rules) {
        json vertices = json::array();
        for (const RuleVertex& v : r.vertices) {
            json embedding = json::array();
            for (const auto& ep : v.embedding) embedding.push_back({ep.offset.x(), ep.offset.y(), std::string(highway_name(ep.highway))});
            json vertex = {{"position", point(v.position)}};
            if (v.symbol) vertex["symbol"] = g.symbol_name(v.symbol);
            if (v.transform != Frame{}) vertex["transform"] = frame(v.transform);
            if (!embedding.empty()) vertex["embedding"] = std::move(embedding);
            vertices.push_back(std::move(vertex));
        }
        json rule = {{"symbol", g.symbol_name(r.symbol)}, {"uses", r.uses}, {"vertices", std::move(vertices)}, {"edges", edges_json(r.edges)}};
        if (r.size_m > 0) rule["size_m"] = r.size_m;
        rules.push_back(std::move(rule));
    }
    // A learned grammar's axiom can hold most of a city: columns, as in a .ggraph file.
    json axiom;
    if (g.encoding.empty()) {
        json axiom_vertices = json::array();
        for (const AxiomVertex& v : g.axiom_vertices) {
            json vertex = {{"position", point(v.position)}};
            if (v.symbol) vertex["symbol"] = g.symbol_name(v.symbol);
            if (v.frame != Frame{}) vertex["frame"] = frame(v.frame);
            axiom_vertices.push_back(std::move(vertex));
        }
        axiom = {{"vertices", std::move(axiom_vertices)}, {"edges", edges_json(g.axiom_edges)}};
    } else {
        json x = json::array(), y = json::array(), symbol = json::array(), frames = json::array();
        for (const AxiomVertex& v : g.axiom_vertices) {
            x.push_back(v.position.x());
            y.push_back(v.position.y());
            symbol.push_back(v.symbol);
            if (v.symbol) {
                frames.push_back(v.frame.scale);
                frames.push_back(v.frame.rotation_deg);
            }
        }
        axiom = {{"x", std::move(x)}, {"y", std::move(y)}, {"symbol", std::move(symbol)}, {"frames", std::move(frames)},
                 {"edges", edges_json(g.axiom_edges)}};
    }
    json doc = {
        {"format", "ggg-grammar"},
        {"version", 1},
        {"name", g.name},
        {"origin_latlon", {g.origin.lat, g.origin.lon}},
        {"symbols", g.symbol_names},
        {"rules", std::move(rules)},
        {"axiom", std::move(axiom)},
    };
    if (!g.encoding.empty()) doc["encoding"] = encoding_json(g.encoding);
    return doc;
}

namespace {

// Grammar members on top of the shared reader: points, frames, classes, edge lists.
class Reader : public io_detail::JsonReader<GrammarError> {
public:
    using JsonReader::JsonReader;

    Vec2 point(const json& v, const std::string& where) const {
        if (!v.is_array() || v.size() != 2) fail(where, "must be [x, y]");
        return {number(v[0], where + "[0]"), number(v[1], where + "[1]")};
    }
    Frame frame(const json* v, const std::string& where) const {
        Frame f;
        if (!v) return f;
        if (!v->is_object()) fail(where, "must be {\"scale\": s, \"rotation_deg\": r}");
        if (const json* s = optional(*v, "scale")) f.scale = number(*s, where + ".scale");
        if (const json* r = optional(*v, "rotation_deg")) f.rotation_deg = number(*r, where + ".rotation_deg");
        if (f.scale <= 0) fail(where + ".scale", "must be > 0");
        return f;
    }
    HighwayClass highway(const json& v, const std::string& where) const {
        if (!v.is_string()) fail(where, "must be a highway class name");
        const auto c = highway_from_known_name(v.get<std::string>());
        if (!c) fail(where, "unknown highway class '" + v.get<std::string>() + "'");
        return *c;
    }
    std::vector<GrammarEdge> edges(const json& v, std::size_t vertex_count, const std::string& where) const {
        std::vector<GrammarEdge> out;
        for (std::size_t i = 0; i < array(v, where).size(); ++i) {
            const std::string at = where + "[" + std::to_string(i) + "]";
            const json& e = v[i];
            if (!e.is_array() || e.size() < 2 || e.size() > 3 || !e[0].is_number_integer() || !e[1].is_number_integer()) {
                fail(at, "an edge is [a, b] or [a, b, \"highway class\"] with vertex indices a, b");
            }
            GrammarEdge edge;
            const auto a = e[0].get<std::int64_t>(), b = e[1].get<std::int64_t>();
            if (a < 0 || b < 0 || a >= static_cast<std::int64_t>(vertex_count) || b >= static_cast<std::int64_t>(vertex_count)) {
                fail(at, "vertex index out of range (there are " + std::to_string(vertex_count) + " vertices)");
            }
            edge.a = static_cast<std::int32_t>(a);
            edge.b = static_cast<std::int32_t>(b);
            if (e.size() == 3) edge.highway = highway(e[2], at + "[2]");
            out.push_back(edge);
        }
        return out;
    }
};

// The instances are columns of equal length (see encoding_json); what they refer to (rules,
// rule vertices, children) is checked afterwards by validate().
Encoding read_encoding(const Reader& r, const json& doc, std::size_t symbol_count) {
    Encoding enc;
    const json& mode = r.member(doc, "mode", "encoding");
    if (!mode.is_string()) r.fail("encoding.mode", "must be \"paper\" or \"lossless\"");
    enc.mode = mode.get<std::string>();
    enc.levels = static_cast<int>(r.integer(r.member(doc, "levels", "encoding"), "encoding.levels", 0, 1'000'000));
    enc.tolerance_m = r.number(r.member(doc, "tolerance_m", "encoding"), "encoding.tolerance_m");
    enc.quantum_m = r.number(r.member(doc, "quantum_m", "encoding"), "encoding.quantum_m");
    if (const json* d = r.optional(doc, "decodes_to")) {
        enc.decoded_vertices = r.integer(r.member(*d, "vertices", "encoding.decodes_to"), "encoding.decodes_to.vertices", 0, INT32_MAX);
        enc.decoded_edges = r.integer(r.member(*d, "edges", "encoding.decodes_to"), "encoding.decodes_to.edges", 0, INT32_MAX);
        if (const json* m = r.optional(*d, "length_m")) enc.decoded_length_m = r.integer(*m, "encoding.decodes_to.length_m", 0, INT64_MAX / 8);
    }
    const int class_max = highway_class_count - 1;
    auto integers = [&](const json& v, const std::string& where, std::int64_t lo, std::int64_t hi) {
        std::vector<std::int32_t> out;
        for (std::size_t i = 0; i < r.array(v, where).size(); ++i) {
            out.push_back(static_cast<std::int32_t>(r.integer(v[i], where + "[" + std::to_string(i) + "]", lo, hi)));
        }
        return out;
    };
    if (const json* a = r.optional(doc, "axiom_instances")) enc.axiom_instances = integers(*a, "encoding.axiom_instances", -1, INT32_MAX);
    const json& inst = r.member(doc, "instances", "encoding");
    const json& symbol = r.array(r.member(inst, "symbol", "encoding.instances"), "encoding.instances.symbol");
    const std::size_t n = symbol.size();
    auto column = [&](const char* key) -> const json& {
        return r.array(r.member(inst, key, "encoding.instances"), std::string("encoding.instances.") + key, n);
    };
    const json& scale = column("scale");
    const json& rotation = column("rotation_deg");
    const json& shift = r.array(r.member(inst, "shift", "encoding.instances"), "encoding.instances.shift", 2 * n);
    const json& residuals = column("residuals");
    const json& children = column("children");
    const json& embedding = column("embedding");
    const json& rule_points = column("rule_points");
    const json& tolerance = column("tolerance_m");
    const json& classes = column("edge_classes");
    const json* neighbours = inst.contains("neighbours") ? &column("neighbours") : nullptr; // absent: none
    enc.instances.resize(n);
    for (std::size_t k = 0; k < n; ++k) {
        const std::string at = "[" + std::to_string(k) + "]";
        RuleInstance& ri = enc.instances[k];
        ri.symbol = static_cast<Symbol>(r.integer(symbol[k], "encoding.instances.symbol" + at, 1, static_cast<std::int64_t>(symbol_count)));
        ri.correction.scale = r.number(scale[k], "encoding.instances.scale" + at);
        ri.correction.rotation_deg = r.number(rotation[k], "encoding.instances.rotation_deg" + at);
        ri.shift = {r.number(shift[2 * k], "encoding.instances.shift[" + std::to_string(2 * k) + "]"),
                    r.number(shift[2 * k + 1], "encoding.instances.shift[" + std::to_string(2 * k + 1) + "]")};
        const json& res = r.array(residuals[k], "encoding.instances.residuals" + at);
        if (res.size() % 2) r.fail("encoding.instances.residuals" + at, "must hold x, y pairs");
        for (std::size_t i = 0; i + 1 < res.size(); i += 2) {
            ri.residuals.emplace_back(r.number(res[i], "encoding.instances.residuals" + at), r.number(res[i + 1], "encoding.instances.residuals" + at));
        }
        ri.children = integers(children[k], "encoding.instances.children" + at, -1, INT32_MAX);
        ri.rule_points = integers(rule_points[k], "encoding.instances.rule_points" + at, 0, INT32_MAX);
        ri.tolerance_m = r.number(tolerance[k], "encoding.instances.tolerance_m" + at);
        const json& links = r.array(embedding[k], "encoding.instances.embedding" + at);
        if (links.size() % 4) r.fail("encoding.instances.embedding" + at, "must hold (vertex, x, y, class) quadruples");
        for (std::size_t i = 0; i < links.size(); i += 4) {
            const std::string where = "encoding.instances.embedding" + at;
            RuleInstance::Link link;
            link.vertex = static_cast<std::int32_t>(r.integer(links[i], where, 0, INT32_MAX));
            link.point.offset = {r.number(links[i + 1], where), r.number(links[i + 2], where)};
            link.point.highway = static_cast<HighwayClass>(r.integer(links[i + 3], where, 0, class_max));
            ri.embedding.push_back(link);
        }
        if (neighbours) {
            const std::string where = "encoding.instances.neighbours" + at;
            const json& ranked = r.array((*neighbours)[k], where);
            if (ranked.size() % 3) r.fail(where, "must hold (vertex, rank, class) triples");
            for (std::size_t i = 0; i < ranked.size(); i += 3) {
                RuleInstance::Neighbour link;
                link.vertex = static_cast<std::int32_t>(r.integer(ranked[i], where, 0, INT32_MAX));
                link.rank = static_cast<std::int32_t>(r.integer(ranked[i + 1], where, 0, RuleInstance::max_rank));
                link.highway = static_cast<HighwayClass>(r.integer(ranked[i + 2], where, 0, class_max));
                ri.neighbours.push_back(link);
            }
        }
        const json& ec = r.array(classes[k], "encoding.instances.edge_classes" + at);
        if (ec.size() % 2) r.fail("encoding.instances.edge_classes" + at, "must hold (edge, class) pairs");
        for (std::size_t i = 0; i < ec.size(); i += 2) {
            const std::string where = "encoding.instances.edge_classes" + at;
            ri.edge_classes.emplace_back(static_cast<std::int32_t>(r.integer(ec[i], where, 0, INT32_MAX)),
                                         static_cast<HighwayClass>(r.integer(ec[i + 1], where, 0, class_max)));
        }
    }
    return enc;
}

} // namespace

Grammar grammar_from_json(const json& doc, const std::string& name) {
    Reader r(name);
    if (!io_detail::has_format(doc, "ggg-grammar")) {
        throw GrammarError(name + ": not a grammar file (\"format\": \"ggg-grammar\" missing)");
    }
    const json& version = r.member(doc, "version", "file");
    if (!version.is_number_integer() || version.get<std::int64_t>() < 1) r.fail("version", "must be a positive integer");
    if (version.get<std::int64_t>() > grammar_file_version) {
        r.fail("version", std::to_string(version.get<std::int64_t>()) + " is newer than this program reads (" +
                              std::to_string(grammar_file_version) + "); update ggg");
    }
    // Versions 2 and 3 are packed (3 stores rare columns sparsely); 1 is the column form.
    if (version.get<std::int64_t>() >= 2) return io_detail::unpack_grammar(doc, name);
    Grammar g;
    io_detail::read_grammar_header(r, doc, g);
    // Symbols: those declared, then the left sides of the rules.
    std::map<std::string, Symbol> symbol_of;
    auto declare = [&](const std::string& s, const std::string& where) {
        if (s.empty() || s == "terminal") r.fail(where, "a nonterminal needs a name other than \"\" and \"terminal\"");
        if (!symbol_of.count(s)) {
            g.symbol_names.push_back(s);
            symbol_of[s] = static_cast<Symbol>(g.symbol_names.size());
        }
        return symbol_of[s];
    };
    if (const json* symbols = r.optional(doc, "symbols")) {
        for (std::size_t i = 0; i < r.array(*symbols, "symbols").size(); ++i) {
            if (!(*symbols)[i].is_string()) r.fail("symbols[" + std::to_string(i) + "]", "must be a string");
            declare((*symbols)[i].get<std::string>(), "symbols[" + std::to_string(i) + "]");
        }
    }
    const json& rules = r.array(r.member(doc, "rules", "file"), "rules");
    for (std::size_t i = 0; i < rules.size(); ++i) {
        const std::string where = "rules[" + std::to_string(i) + "]";
        const json& s = r.member(rules[i], "symbol", where);
        if (!s.is_string()) r.fail(where + ".symbol", "must be the name of a nonterminal");
        declare(s.get<std::string>(), where + ".symbol");
    }
    auto symbol = [&](const json* v, const std::string& where) -> Symbol {
        if (!v || v->is_null()) return 0;
        if (!v->is_string()) r.fail(where, "must be a symbol name (\"\" for a terminal)");
        const std::string s = v->get<std::string>();
        if (s.empty() || s == "terminal") return 0;
        const auto it = symbol_of.find(s);
        if (it == symbol_of.end()) r.fail(where, "unknown symbol '" + s + "' (no rule and not in \"symbols\")");
        return it->second;
    };
    for (std::size_t i = 0; i < rules.size(); ++i) {
        const std::string where = "rules[" + std::to_string(i) + "]";
        Rule rule;
        rule.symbol = symbol_of.at(rules[i]["symbol"].get<std::string>());
        if (const json* uses = r.optional(rules[i], "uses")) {
            if (!uses->is_number_unsigned() && !(uses->is_number_integer() && uses->get<std::int64_t>() >= 0)) r.fail(where + ".uses", "must be a count >= 0");
            rule.uses = uses->get<std::uint64_t>();
        }
        if (const json* size = r.optional(rules[i], "size_m")) {
            rule.size_m = r.number(*size, where + ".size_m");
            if (rule.size_m < 0) r.fail(where + ".size_m", "must be >= 0");
        }
        const json& vertices = r.array(r.member(rules[i], "vertices", where), where + ".vertices");
        for (std::size_t k = 0; k < vertices.size(); ++k) {
            const std::string at = where + ".vertices[" + std::to_string(k) + "]";
            RuleVertex v;
            v.position = r.point(r.member(vertices[k], "position", at), at + ".position");
            v.symbol = symbol(r.optional(vertices[k], "symbol"), at + ".symbol");
            v.transform = r.frame(r.optional(vertices[k], "transform"), at + ".transform");
            if (const json* emb = r.optional(vertices[k], "embedding")) {
                for (std::size_t j = 0; j < r.array(*emb, at + ".embedding").size(); ++j) {
                    const std::string ej = at + ".embedding[" + std::to_string(j) + "]";
                    EmbeddingPoint ep;
                    if ((*emb)[j].is_array() && (*emb)[j].size() == 3) { // [x, y, "class"]
                        ep.offset = {r.number((*emb)[j][0], ej + "[0]"), r.number((*emb)[j][1], ej + "[1]")};
                        ep.highway = r.highway((*emb)[j][2], ej + "[2]");
                    } else if ((*emb)[j].is_array()) {
                        ep.offset = r.point((*emb)[j], ej);
                    } else {
                        ep.offset = r.point(r.member((*emb)[j], "offset", ej), ej + ".offset");
                        if (const json* h = r.optional((*emb)[j], "highway")) ep.highway = r.highway(*h, ej + ".highway");
                    }
                    v.embedding.push_back(ep);
                }
            }
            rule.vertices.push_back(std::move(v));
        }
        rule.edges = r.edges(r.member(rules[i], "edges", where), rule.vertices.size(), where + ".edges");
        g.rules.push_back(std::move(rule));
    }
    const json& axiom = r.member(doc, "axiom", "file");
    if (r.optional(axiom, "x")) {
        // Columns: x, y, symbol (0 = terminal, k = the k-th of "symbols"), frames (scale and
        // rotation of each nonterminal, in order).
        const json& x = r.array(r.member(axiom, "x", "axiom"), "axiom.x");
        const json& y = r.array(r.member(axiom, "y", "axiom"), "axiom.y", x.size());
        const json& symbols = r.array(r.member(axiom, "symbol", "axiom"), "axiom.symbol", x.size());
        const json& frames = r.array(r.member(axiom, "frames", "axiom"), "axiom.frames");
        std::size_t next_frame = 0;
        for (std::size_t k = 0; k < x.size(); ++k) {
            const std::string at = "[" + std::to_string(k) + "]";
            AxiomVertex v;
            v.position = {r.number(x[k], "axiom.x" + at), r.number(y[k], "axiom.y" + at)};
            v.symbol = static_cast<Symbol>(r.integer(symbols[k], "axiom.symbol" + at, 0, static_cast<std::int64_t>(g.symbol_names.size())));
            if (v.symbol) {
                if (next_frame + 2 > frames.size()) r.fail("axiom.frames", "needs a scale and a rotation for every nonterminal");
                v.frame.scale = r.number(frames[next_frame], "axiom.frames[" + std::to_string(next_frame) + "]");
                v.frame.rotation_deg = r.number(frames[next_frame + 1], "axiom.frames[" + std::to_string(next_frame + 1) + "]");
                next_frame += 2;
            }
            g.axiom_vertices.push_back(v);
        }
        if (next_frame != frames.size()) r.fail("axiom.frames", "has more entries than the axiom has nonterminals");
    } else {
        const json& vertices = r.array(r.member(axiom, "vertices", "axiom"), "axiom.vertices");
        for (std::size_t k = 0; k < vertices.size(); ++k) {
            const std::string at = "axiom.vertices[" + std::to_string(k) + "]";
            AxiomVertex v;
            v.position = r.point(r.member(vertices[k], "position", at), at + ".position");
            v.symbol = symbol(r.optional(vertices[k], "symbol"), at + ".symbol");
            v.frame = r.frame(r.optional(vertices[k], "frame"), at + ".frame");
            g.axiom_vertices.push_back(v);
        }
    }
    const json* axiom_edges = r.optional(axiom, "edges");
    if (axiom_edges) g.axiom_edges = r.edges(*axiom_edges, g.axiom_vertices.size(), "axiom.edges");
    if (const json* enc = r.optional(doc, "encoding")) g.encoding = read_encoding(r, *enc, g.symbol_names.size());
    try {
        validate(g);
    } catch (const GrammarError& e) {
        throw GrammarError(name + ": " + e.what());
    }
    return g;
}

Grammar parse_grammar(const std::string& text, const std::string& name) {
    if (io_detail::looks_like_cbor(text)) return grammar_from_json(io_detail::parse_cbor(text, name), name);
    return grammar_from_json(io_detail::parse<GrammarError>(text, name), name);
}

Grammar read_grammar(const std::string& path) {
    return parse_grammar(io_detail::read_json_text<GrammarError>(path), path);
}

bool is_cbor_path(const std::string& path) {
    const std::string ext = std::filesystem::path(path).extension().string();
    return ext == ".cbor" || ext == ".CBOR";
}

std::string grammar_bytes_text(const Grammar& grammar, bool cbor) {
    const json doc = grammar_to_json(grammar);
    if (cbor) {
        const std::vector<std::uint8_t> bytes = json::to_cbor(doc);
        return std::string(bytes.begin(), bytes.end());
    }
    // A hand-written grammar is for reading; a learned one is data, written compactly.
    return io_detail::dump(doc, grammar.encoding.empty() ? 1 : -1) + '\n';
}

void write_grammar(const Grammar& grammar, const std::string& path) {
    const std::string bytes = grammar_bytes_text(grammar, is_cbor_path(path));
    io_detail::write_file(path, [&](std::ostream& out) { out << bytes; });
}

} // namespace ggg
