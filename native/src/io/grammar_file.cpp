#include "ggg/io/grammar_file.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <nlohmann/json.hpp>

#include "ggg/error.hpp"
#include "json_util.hpp"

namespace ggg {

using nlohmann::json;

namespace {

json point(const Vec2& p) { return json::array({p.x(), p.y()}); }
json frame(const Frame& f) { return {{"scale", f.scale}, {"rotation_deg", f.rotation_deg}}; }

json edges_json(const std::vector<GrammarEdge>& edges) {
    json out = json::array();
    for (const auto& e : edges) out.push_back(json::array({e.a, e.b, std::string(highway_name(e.highway))}));
    return out;
}

} // namespace

json grammar_to_json(const Grammar& g) {
    json rules = json::array();
    for (const Rule& r : g.rules) {
        json vertices = json::array();
        for (const RuleVertex& v : r.vertices) {
            json embedding = json::array();
            for (const auto& ep : v.embedding) embedding.push_back({{"offset", point(ep.offset)}, {"highway", std::string(highway_name(ep.highway))}});
            vertices.push_back({{"position", point(v.position)},
                                {"symbol", v.symbol ? g.symbol_name(v.symbol) : ""},
                                {"transform", frame(v.transform)},
                                {"embedding", std::move(embedding)}});
        }
        rules.push_back({{"symbol", g.symbol_name(r.symbol)}, {"uses", r.uses}, {"vertices", std::move(vertices)}, {"edges", edges_json(r.edges)}});
    }
    json axiom_vertices = json::array();
    for (const AxiomVertex& v : g.axiom_vertices) {
        axiom_vertices.push_back({{"position", point(v.position)}, {"symbol", v.symbol ? g.symbol_name(v.symbol) : ""}, {"frame", frame(v.frame)}});
    }
    return {
        {"format", "ggg-grammar"},
        {"version", grammar_file_version},
        {"name", g.name},
        {"origin_latlon", {g.origin.lat, g.origin.lon}},
        {"symbols", g.symbol_names},
        {"rules", std::move(rules)},
        {"axiom", {{"vertices", std::move(axiom_vertices)}, {"edges", edges_json(g.axiom_edges)}}},
    };
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
    Grammar g;
    if (const json* n = r.optional(doc, "name")) {
        if (!n->is_string()) r.fail("name", "must be a string");
        g.name = n->get<std::string>();
    }
    if (const json* o = r.optional(doc, "origin_latlon")) {
        if (!o->is_array() || o->size() != 2) r.fail("origin_latlon", "must be [latitude, longitude]");
        g.origin = {r.number((*o)[0], "origin_latlon[0]"), r.number((*o)[1], "origin_latlon[1]")};
    }
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
                    if ((*emb)[j].is_array()) {
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
    const json& vertices = r.array(r.member(axiom, "vertices", "axiom"), "axiom.vertices");
    for (std::size_t k = 0; k < vertices.size(); ++k) {
        const std::string at = "axiom.vertices[" + std::to_string(k) + "]";
        AxiomVertex v;
        v.position = r.point(r.member(vertices[k], "position", at), at + ".position");
        v.symbol = symbol(r.optional(vertices[k], "symbol"), at + ".symbol");
        v.frame = r.frame(r.optional(vertices[k], "frame"), at + ".frame");
        g.axiom_vertices.push_back(v);
    }
    const json* axiom_edges = r.optional(axiom, "edges");
    if (axiom_edges) g.axiom_edges = r.edges(*axiom_edges, g.axiom_vertices.size(), "axiom.edges");
    try {
        validate(g);
    } catch (const GrammarError& e) {
        throw GrammarError(name + ": " + e.what());
    }
    return g;
}

Grammar parse_grammar(const std::string& text, const std::string& name) {
    return grammar_from_json(io_detail::parse<GrammarError>(text, name), name);
}

Grammar read_grammar(const std::string& path) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) throw GrammarError(path + ": no such file");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw GrammarError(path + ": cannot open");
    std::ostringstream s;
    s << in.rdbuf();
    if (s.str().find_first_not_of(" \t\r\n") == std::string::npos) throw GrammarError(path + ": the file is empty");
    return parse_grammar(s.str(), path);
}

void write_grammar(const Grammar& grammar, const std::string& path) {
    const std::string text = io_detail::dump(grammar_to_json(grammar), 1);
    io_detail::write_file(path, [&](std::ostream& out) { out << text << '\n'; });
}

} // namespace ggg
