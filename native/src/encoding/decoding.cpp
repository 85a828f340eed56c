// Decoding a learned grammar and the graphs of its levels; see decoding.hpp.
#include "ggg/encoding/decoding.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <unordered_map>

#include "ggg/error.hpp"

namespace ggg {

std::int64_t street_length_m(const GeometricGraph& g) {
    double length = 0.0;
    for (const auto& [a, b] : g.edges) length += (g.positions[static_cast<std::size_t>(a)] - g.positions[static_cast<std::size_t>(b)]).norm();
    return std::isfinite(length) && length < 1e15 ? std::llround(length) : -1;
}

DeriveOptions decode_options(const Grammar& grammar) {
    DeriveOptions o;
    o.max_steps = grammar.encoding.levels;
    o.tolerance = grammar.encoding.tolerance_m;
    o.tolerance_relative = false;
    o.strict = false;
    std::size_t placed = grammar.axiom_vertices.size();
    for (const RuleInstance& inst : grammar.encoding.instances) {
        const Rule* rule = grammar.rule_for(inst.symbol);
        placed += rule ? rule->vertices.size() : 0;
    }
    o.max_vertices = placed + 1;
    return o;
}

std::vector<int> rule_levels(const Grammar& grammar) {
    std::vector<int> level(grammar.rules.size(), 0);
    // Rules of a learned grammar only place nonterminals of lower levels; a hand-written
    // recursive rule (P -> P) gets the level it has after as many passes as there are rules.
    for (std::size_t pass = 0; pass < grammar.rules.size(); ++pass) {
        bool changed = false;
        for (std::size_t r = 0; r < grammar.rules.size(); ++r) {
            int l = 1;
            for (const RuleVertex& v : grammar.rules[r].vertices) {
                if (v.symbol == 0) continue;
                for (std::size_t c = 0; c < grammar.rules.size(); ++c) {
                    if (grammar.rules[c].symbol == v.symbol && c != r) l = std::max(l, level[c] + 1);
                }
            }
            changed |= l != level[r];
            level[r] = l;
        }
        if (!changed) break;
    }
    return level;
}

namespace {

void require_learned(const Grammar& grammar) {
    if (grammar.encoding.empty()) {
        throw GrammarError("the grammar '" + grammar.name + "' was not learned from a graph (it has no \"encoding\"): derive it instead");
    }
}

} // namespace

GeometricGraph decode_grammar(const Grammar& grammar, DeriveReport* report_out, const ProgressCallback& progress) {
    require_learned(grammar);
    GeometricGraph g = grammar.axiom_graph();
    DeriveReport report = derive(g, grammar, decode_options(grammar), progress);
    if (std::any_of(g.symbols.begin(), g.symbols.end(), [](Symbol s) { return s != 0; })) {
        throw GrammarError("the grammar '" + grammar.name + "' does not decode completely in its " +
                           std::to_string(grammar.encoding.levels) + " levels (nonterminals are left)");
    }
    // A grammar that decodes to other streets than it was learned from is damaged (an edited
    // position, instance or rule): an error, not a street network with pieces missing.
    const Encoding& enc = grammar.encoding;
    if (enc.decoded_vertices >= 0 &&
        (static_cast<std::int64_t>(g.vertex_count()) != enc.decoded_vertices || static_cast<std::int64_t>(g.edge_count()) != enc.decoded_edges)) {
        throw GrammarError("the grammar '" + grammar.name + "' does not decode to what it encodes: " + std::to_string(g.vertex_count()) +
                           " vertices and " + std::to_string(g.edge_count()) + " edges instead of " + std::to_string(enc.decoded_vertices) +
                           " and " + std::to_string(enc.decoded_edges) + " (" + std::to_string(report.totals.missed_embeddings) +
                           " streets found no vertex to join; is the file damaged?)");
    }
    if (enc.decoded_length_m >= 0 && std::llabs(street_length_m(g) - enc.decoded_length_m) > 1) {
        throw GrammarError("the grammar '" + grammar.name + "' does not decode to what it encodes: its streets are " +
                           std::to_string(street_length_m(g)) + " m long instead of " + std::to_string(enc.decoded_length_m) +
                           " m (is the file damaged?)");
    }
    g.instances.clear();
    if (report_out) *report_out = std::move(report);
    return g;
}

GeometricGraph encoded_graph(const Grammar& grammar, int level, const ProgressCallback& progress, std::vector<VertexId>* image_out) {
    require_learned(grammar);
    const int levels = grammar.encoding.levels;
    if (level < 0 || level > levels) {
        throw UsageError("level " + std::to_string(level) + " is out of range (0 to " + std::to_string(levels) + ")");
    }
    DeriveReport full;
    const GeometricGraph streets = decode_grammar(grammar, &full, progress);
    if (level == 0) {
        if (image_out) {
            image_out->resize(streets.vertex_count());
            for (std::size_t v = 0; v < streets.vertex_count(); ++v) (*image_out)[v] = static_cast<VertexId>(v);
        }
        return streets;
    }

    // The derivation stopped `levels - level` steps in: its vertices are this level's graph.
    GeometricGraph partial = grammar.axiom_graph();
    DeriveOptions options = decode_options(grammar);
    options.max_steps = levels - level;
    const DeriveReport steps = derive(partial, grammar, options);

    // Instances by parent, to find each street vertex's ancestor pending at this level.
    const auto& instances = grammar.encoding.instances;
    std::vector<std::int32_t> parent(instances.size(), -1);
    for (std::size_t i = 0; i < instances.size(); ++i) {
        for (std::int32_t c : instances[i].children) {
            if (c >= 0) parent[static_cast<std::size_t>(c)] = static_cast<std::int32_t>(i);
        }
    }
    std::unordered_map<std::int32_t, VertexId> pending;          // instance -> vertex of `partial`
    std::map<std::pair<std::int32_t, std::int32_t>, VertexId> placed; // (instance, rule vertex) -> vertex
    std::unordered_map<VertexId, VertexId> axiom;                 // axiom vertex -> vertex
    for (std::size_t v = 0; v < partial.vertex_count(); ++v) {
        const auto id = static_cast<VertexId>(v);
        if (partial.instance_of(id) >= 0) pending[partial.instance_of(id)] = id;
        const Placement& p = steps.placed_by[v];
        if (p.instance >= 0) placed[{p.instance, p.rule_vertex}] = id;
        else if (steps.source_vertex[v] >= 0) axiom[steps.source_vertex[v]] = id;
    }
    std::vector<VertexId> image(streets.vertex_count(), -1);
    for (std::size_t v = 0; v < streets.vertex_count(); ++v) {
        const Placement& p = full.placed_by[v];
        if (p.instance < 0) {
            const auto it = axiom.find(full.source_vertex[v]);
            if (it != axiom.end()) image[v] = it->second;
            continue;
        }
        const auto it = placed.find({p.instance, p.rule_vertex});
        if (it != placed.end()) {
            image[v] = it->second;
            continue;
        }
        for (std::int32_t a = p.instance; a >= 0; a = parent[static_cast<std::size_t>(a)]) {
            const auto found = pending.find(a);
            if (found != pending.end()) {
                image[v] = found->second;
                break;
            }
        }
    }
    // Edges: the streets' edges between the vertices they map to, the most important class
    // where several fold into one; the derivation's own (transient) edges are dropped.
    GeometricGraph out;
    out.origin = partial.origin;
    for (std::size_t v = 0; v < partial.vertex_count(); ++v) {
        out.add_vertex(partial.positions[v]);
        out.symbols.back() = partial.symbols[v];
        out.frames.back() = partial.frames[v];
    }
    out.instances = partial.instances;
    out.more_rewrites = partial.more_rewrites;
    std::map<std::pair<VertexId, VertexId>, EdgeId> seen;
    for (std::size_t e = 0; e < streets.edge_count(); ++e) {
        VertexId a = image[static_cast<std::size_t>(streets.edges[e][0])];
        VertexId b = image[static_cast<std::size_t>(streets.edges[e][1])];
        if (a < 0 || b < 0 || a == b) continue;
        if (a > b) std::swap(a, b);
        const auto [it, inserted] = seen.emplace(std::make_pair(a, b), static_cast<EdgeId>(out.edge_count()));
        if (inserted) {
            EdgeAttributes attributes;
            attributes.highway = streets.edge_highway[e];
            out.add_edge(a, b, attributes);
        } else if (highway_rank(streets.edge_highway[e]) < highway_rank(out.edge_highway[static_cast<std::size_t>(it->second)])) {
            out.edge_highway[static_cast<std::size_t>(it->second)] = streets.edge_highway[e];
        }
    }
    if (image_out) *image_out = std::move(image);
    return out;
}

} // namespace ggg
