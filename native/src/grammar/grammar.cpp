#include "ggg/grammar/grammar.hpp"

#include <cmath>
#include <set>

#include "ggg/error.hpp"

namespace ggg {

Similarity2 Frame::at(const Vec2& origin) const {
    return Similarity2::from(scale, rotation_deg * M_PI / 180.0, origin);
}

const Rule* Grammar::rule_for(Symbol symbol) const {
    for (const Rule& r : rules) {
        if (r.symbol == symbol) return &r;
    }
    return nullptr;
}

std::string Grammar::symbol_name(Symbol symbol) const {
    if (symbol == 0) return "terminal";
    if (symbol <= symbol_names.size()) return symbol_names[symbol - 1];
    return "#" + std::to_string(symbol);
}

GeometricGraph Grammar::axiom_graph() const {
    GeometricGraph g;
    g.origin = origin;
    for (const AxiomVertex& v : axiom_vertices) {
        const VertexId id = g.add_vertex(v.position);
        g.symbols[static_cast<std::size_t>(id)] = v.symbol;
        g.frames[static_cast<std::size_t>(id)] = v.frame.at(v.position);
    }
    if (!encoding.axiom_instances.empty()) g.instances = encoding.axiom_instances;
    for (const GrammarEdge& e : axiom_edges) {
        EdgeAttributes a;
        a.highway = e.highway;
        g.add_edge(e.a, e.b, a);
    }
    return g;
}

bool Grammar::operator==(const Grammar& o) const {
    return name == o.name && symbol_names == o.symbol_names && rules == o.rules && origin.lat == o.origin.lat &&
           origin.lon == o.origin.lon && axiom_vertices == o.axiom_vertices && axiom_edges == o.axiom_edges && encoding == o.encoding;
}

namespace {

[[noreturn]] void fail(const std::string& where, const std::string& what) { throw GrammarError(where + ": " + what); }

void check_finite(const Vec2& p, const std::string& where) {
    if (!std::isfinite(p.x()) || !std::isfinite(p.y())) fail(where, "coordinates must be finite numbers");
}

void check_frame(const Frame& f, const std::string& where) {
    if (!std::isfinite(f.scale) || !std::isfinite(f.rotation_deg)) fail(where, "scale and rotation must be finite numbers");
    if (f.scale <= 0) fail(where + ".scale", "must be > 0");
}

void check_symbol(const Grammar& g, Symbol s, const std::string& where) {
    if (s > g.symbol_names.size()) fail(where, "unknown symbol " + std::to_string(s));
}

void check_edges(const std::vector<GrammarEdge>& edges, std::size_t vertex_count, const std::string& where) {
    std::set<std::pair<int, int>> seen;
    for (std::size_t i = 0; i < edges.size(); ++i) {
        const std::string at = where + "[" + std::to_string(i) + "]";
        const auto& e = edges[i];
        if (e.a < 0 || e.b < 0 || static_cast<std::size_t>(e.a) >= vertex_count || static_cast<std::size_t>(e.b) >= vertex_count) {
            fail(at, "vertex index out of range (there are " + std::to_string(vertex_count) + " vertices)");
        }
        if (e.a == e.b) fail(at, "an edge must join two different vertices");
        if (!seen.emplace(std::min(e.a, e.b), std::max(e.a, e.b)).second) fail(at, "duplicate edge");
    }
}

// An instance must fit its rule, and its children must be instances of the rules of the
// nonterminals they rewrite, each used once: then the instances form a forest and a
// derivation consumes every one of them at most once.
void validate_encoding(const Grammar& g) {
    const Encoding& enc = g.encoding;
    if (enc.empty()) {
        if (!enc.instances.empty() || !enc.axiom_instances.empty()) fail("encoding.mode", "missing (\"paper\" or \"lossless\")");
        return;
    }
    if (enc.mode != "paper" && enc.mode != "lossless") fail("encoding.mode", "must be \"paper\" or \"lossless\"");
    if (enc.levels < 0) fail("encoding.levels", "must be >= 0");
    if (!std::isfinite(enc.tolerance_m) || enc.tolerance_m < 0) fail("encoding.tolerance_m", "must be a finite number >= 0");
    if (!std::isfinite(enc.quantum_m) || enc.quantum_m < 0) fail("encoding.quantum_m", "must be a finite number >= 0");
    const std::size_t n = enc.instances.size();
    std::vector<char> used(n, 0);
    auto claim = [&](std::int32_t instance, Symbol symbol, const std::string& where) {
        if (instance < 0) return;
        if (static_cast<std::size_t>(instance) >= n) fail(where, "instance " + std::to_string(instance) + " out of range");
        if (used[static_cast<std::size_t>(instance)]++) fail(where, "instance " + std::to_string(instance) + " is used twice");
        if (enc.instances[static_cast<std::size_t>(instance)].symbol != symbol) {
            fail(where, "instance " + std::to_string(instance) + " belongs to another symbol");
        }
    };
    if (!enc.axiom_instances.empty()) {
        if (enc.axiom_instances.size() != g.axiom_vertices.size()) fail("encoding.axiom_instances", "needs one entry per axiom vertex");
        for (std::size_t i = 0; i < enc.axiom_instances.size(); ++i) {
            claim(enc.axiom_instances[i], g.axiom_vertices[i].symbol, "encoding.axiom_instances[" + std::to_string(i) + "]");
        }
    }
    for (std::size_t k = 0; k < n; ++k) {
        const RuleInstance& inst = enc.instances[k];
        const std::string where = "encoding.instances[" + std::to_string(k) + "]";
        const Rule* rule = g.rule_for(inst.symbol);
        if (!rule) fail(where + ".symbol", "no rule for symbol " + std::to_string(inst.symbol));
        const std::size_t size = rule->vertices.size();
        check_frame(inst.correction, where + ".correction");
        check_finite(inst.shift, where + ".shift");
        if (!inst.residuals.empty() && inst.residuals.size() != size) fail(where + ".residuals", "needs one entry per rule vertex");
        for (const Vec2& r : inst.residuals) check_finite(r, where + ".residuals");
        if (!inst.children.empty() && inst.children.size() != size) fail(where + ".children", "needs one entry per rule vertex");
        for (std::size_t i = 0; i < inst.children.size(); ++i) {
            claim(inst.children[i], rule->vertices[i].symbol, where + ".children[" + std::to_string(i) + "]");
        }
        std::size_t points = 0;
        for (const RuleVertex& v : rule->vertices) points += v.embedding.size();
        for (std::int32_t p : inst.rule_points) {
            if (p < 0 || static_cast<std::size_t>(p) >= points) fail(where + ".rule_points", "rule embedding point out of range");
        }
        if (!std::isfinite(inst.tolerance_m) || inst.tolerance_m < 0) fail(where + ".tolerance_m", "must be a finite number >= 0");
        for (const RuleInstance::Link& link : inst.embedding) {
            if (link.vertex < 0 || static_cast<std::size_t>(link.vertex) >= size) fail(where + ".embedding", "rule vertex out of range");
            check_finite(link.point.offset, where + ".embedding");
        }
        for (const RuleInstance::Neighbour& link : inst.neighbours) {
            if (link.vertex < 0 || static_cast<std::size_t>(link.vertex) >= size) fail(where + ".neighbours", "rule vertex out of range");
            if (link.rank < 0 || link.rank > RuleInstance::max_rank) fail(where + ".neighbours", "a rank is from 0 to " + std::to_string(RuleInstance::max_rank));
        }
        for (const auto& [edge, highway] : inst.edge_classes) {
            if (edge < 0 || static_cast<std::size_t>(edge) >= rule->edges.size()) fail(where + ".edge_classes", "rule edge out of range");
        }
    }
}

} // namespace

void validate(const Grammar& g) {
    std::set<Symbol> defined;
    for (std::size_t r = 0; r < g.rules.size(); ++r) {
        const Rule& rule = g.rules[r];
        const std::string where = "rules[" + std::to_string(r) + "]";
        if (rule.symbol == 0) fail(where + ".symbol", "the left side of a rule must be a nonterminal");
        check_symbol(g, rule.symbol, where + ".symbol");
        if (!defined.insert(rule.symbol).second) fail(where + ".symbol", "a second rule for symbol '" + g.symbol_name(rule.symbol) + "'");
        if (rule.vertices.empty()) fail(where + ".vertices", "a rule needs at least one vertex");
        for (std::size_t i = 0; i < rule.vertices.size(); ++i) {
            const RuleVertex& v = rule.vertices[i];
            const std::string at = where + ".vertices[" + std::to_string(i) + "]";
            check_finite(v.position, at + ".position");
            check_symbol(g, v.symbol, at + ".symbol");
            check_frame(v.transform, at + ".transform");
            for (std::size_t j = 0; j < v.embedding.size(); ++j) check_finite(v.embedding[j].offset, at + ".embedding[" + std::to_string(j) + "]");
        }
        check_edges(rule.edges, rule.vertices.size(), where + ".edges");
    }
    if (g.axiom_vertices.empty()) fail("axiom", "missing axiom (a grammar needs at least one axiom vertex)");
    for (std::size_t i = 0; i < g.axiom_vertices.size(); ++i) {
        const AxiomVertex& v = g.axiom_vertices[i];
        const std::string at = "axiom.vertices[" + std::to_string(i) + "]";
        check_finite(v.position, at + ".position");
        check_symbol(g, v.symbol, at + ".symbol");
        check_frame(v.frame, at + ".frame");
    }
    check_edges(g.axiom_edges, g.axiom_vertices.size(), "axiom.edges");
    validate_encoding(g);
    if (!std::isfinite(g.origin.lat) || !std::isfinite(g.origin.lon) || std::abs(g.origin.lat) > 90 || std::abs(g.origin.lon) > 180) {
        fail("origin_latlon", "out of range");
    }
}

} // namespace ggg
