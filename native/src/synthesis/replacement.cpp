// Terminal replacement by one derivation step; see replacement.hpp.
#include "ggg/synthesis/replacement.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <unordered_map>

#include "ggg/error.hpp"
#include "ggg/grammar/grammar.hpp"
#include "ggg/grammar/rewriting.hpp"

namespace ggg {

ReplacementGraph fit_replacement(const ReplacementGraph& drawn, const Pattern& pattern) {
    if (drawn.positions.empty()) throw UsageError("the replacement has no vertices");
    const Spread s = spread_of(drawn.positions);
    const Spread p = spread_of(pattern.positions);
    ReplacementGraph out = drawn;
    const double scale = s.degenerate || p.degenerate ? 1.0 : p.rms / s.rms;
    for (Vec2& v : out.positions) v = p.centroid + scale * (v - s.centroid);
    return out;
}

GeometricGraph replace_occurrences(const GeometricGraph& g, const Isogroup& group, std::span<const std::uint32_t> chosen,
                                   const ReplacementGraph& r, ReplaceReport* report_out) {
    const std::size_t k = group.order();
    if (r.positions.empty()) throw UsageError("the replacement has no vertices");
    if (!r.edge_highway.empty() && r.edge_highway.size() != r.edges.size()) throw UsageError("the replacement needs one road class per edge");
    for (const auto& [a, b] : r.edges) {
        if (a < 0 || b < 0 || static_cast<std::size_t>(a) >= r.positions.size() || static_cast<std::size_t>(b) >= r.positions.size() || a == b) {
            throw UsageError("a replacement edge joins vertices out of range");
        }
    }
    // Which occurrence each vertex belongs to.
    std::vector<std::int32_t> owner(g.vertex_count(), -1);
    for (std::size_t c = 0; c < chosen.size(); ++c) {
        if (chosen[c] >= group.frequency()) throw UsageError("occurrence " + std::to_string(chosen[c]) + " out of range");
        for (VertexId v : group.occurrence(chosen[c])) {
            if (v < 0 || static_cast<std::size_t>(v) >= g.vertex_count()) throw UsageError("an occurrence vertex is out of range");
            if (owner[static_cast<std::size_t>(v)] >= 0) throw UsageError("the occurrences to replace share vertices");
            owner[static_cast<std::size_t>(v)] = static_cast<std::int32_t>(c);
        }
    }

    // The grammar: one rule, the replacement; one instance per occurrence.
    Grammar grammar;
    grammar.name = "replacement";
    grammar.symbol_names = {"replacement"};
    Rule rule;
    rule.symbol = 1;
    for (const Vec2& p : r.positions) rule.vertices.push_back({p, 0, Frame{}, {}});
    for (std::size_t e = 0; e < r.edges.size(); ++e) {
        rule.edges.push_back({r.edges[e][0], r.edges[e][1], r.edge_highway.empty() ? HighwayClass::residential : r.edge_highway[e]});
    }
    grammar.rules.push_back(rule);
    grammar.axiom_vertices.push_back({}); // unused: the host graph is given
    grammar.encoding.mode = "paper";
    grammar.encoding.levels = 1;

    // Where each replaced vertex's streets now end: the replacement vertex nearest to it.
    std::vector<std::int32_t> stand_in(g.vertex_count(), -1);
    std::vector<std::vector<Vec2>> placed(chosen.size());
    for (std::size_t c = 0; c < chosen.size(); ++c) {
        const Similarity2& t = group.transforms[chosen[c]];
        for (const Vec2& p : r.positions) placed[c].push_back(t.apply(p));
        for (VertexId v : group.occurrence(chosen[c])) {
            const Vec2& at = g.positions[static_cast<std::size_t>(v)];
            std::size_t best = 0;
            for (std::size_t i = 1; i < placed[c].size(); ++i) {
                if ((placed[c][i] - at).squaredNorm() < (placed[c][best] - at).squaredNorm()) best = i;
            }
            stand_in[static_cast<std::size_t>(v)] = static_cast<std::int32_t>(best);
        }
    }
    // The host: the graph without the occurrences, plus one nonterminal per occurrence.
    GeometricGraph host;
    host.origin = g.origin;
    std::vector<VertexId> new_id(g.vertex_count(), -1);
    for (std::size_t v = 0; v < g.vertex_count(); ++v) {
        if (owner[v] >= 0) continue;
        new_id[v] = host.add_vertex(g.positions[v], g.vertex_osm_ids[v]);
        host.symbols.back() = g.symbols.empty() ? 0 : g.symbols[v];
        host.frames.back() = g.frames.empty() ? Similarity2::from(1, 0, g.positions[v]) : g.frames[v];
    }
    host.instances.assign(host.vertex_count(), -1);
    double smallest = std::numeric_limits<double>::infinity();
    for (std::size_t c = 0; c < chosen.size(); ++c) {
        const Similarity2& t = group.transforms[chosen[c]];
        const VertexId q = host.add_vertex(t.t);
        host.symbols.back() = 1;
        host.frames.back() = t;
        host.instances.push_back(static_cast<std::int32_t>(c));
        smallest = std::min(smallest, t.scale());
        RuleInstance inst;
        inst.symbol = 1;
        grammar.encoding.instances.push_back(inst);
        (void)q;
    }
    std::size_t reconnected = 0;
    for (std::size_t e = 0; e < g.edge_count(); ++e) {
        const auto [a, b] = g.edges[e];
        const std::int32_t oa = owner[static_cast<std::size_t>(a)], ob = owner[static_cast<std::size_t>(b)];
        if (oa < 0 && ob < 0) {
            const auto id = static_cast<EdgeId>(e);
            std::vector<Vec2> line(g.geometry_begin(id), g.geometry_begin(id) + g.geometry_size(id));
            host.add_edge(new_id[static_cast<std::size_t>(a)], new_id[static_cast<std::size_t>(b)], g.edge_attributes(id), line);
            continue;
        }
        if (oa == ob) continue; // inside one occurrence: the replacement's own edges stand for it
        // A street leaving an occurrence: an embedding point of that occurrence's instance,
        // aimed at the other end (a street vertex, or the stand-in of another replacement).
        const auto [x, y] = oa >= 0 ? std::pair{a, b} : std::pair{b, a};
        const std::size_t c = static_cast<std::size_t>(owner[static_cast<std::size_t>(x)]);
        const std::int32_t i = stand_in[static_cast<std::size_t>(x)];
        const std::int32_t oy = owner[static_cast<std::size_t>(y)];
        const Vec2 target = oy >= 0 ? placed[static_cast<std::size_t>(oy)][static_cast<std::size_t>(stand_in[static_cast<std::size_t>(y)])]
                                    : g.positions[static_cast<std::size_t>(y)];
        RuleInstance::Link link;
        link.vertex = i;
        link.point.offset = group.transforms[chosen[c]].inverse().apply_linear(target - placed[c][static_cast<std::size_t>(i)]);
        link.point.highway = g.edge_highway[e];
        grammar.encoding.instances[c].embedding.push_back(link);
        ++reconnected;
    }
    const std::size_t kept = host.vertex_count() - chosen.size();
    DeriveOptions o;
    o.max_steps = 1;
    o.tolerance = std::isfinite(smallest) ? 1e-6 * std::max(1.0, smallest) : 1e-6;
    o.tolerance_relative = false;
    o.max_vertices = host.vertex_count() + chosen.size() * r.positions.size() + 1;
    if (!chosen.empty()) derive(host, grammar, o);
    host.instances.clear();
    if (report_out) {
        report_out->replaced = chosen.size();
        report_out->removed_vertices = chosen.size() * k;
        report_out->added_vertices = host.vertex_count() - kept;
        report_out->reconnected_streets = reconnected;
    }
    return host;
}

} // namespace ggg
