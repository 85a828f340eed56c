// The grammar built from the encoder's rules and instances, set against a real derivation
// and checked by decoding it (encoder.hpp).
#include "encoder.hpp"

#include <algorithm>
#include <limits>
#include <string>
#include <type_traits>
#include <unordered_map>
#include <unordered_set>

#include "ggg/encoding/decoding.hpp"
#include "ggg/grammar/rewriting.hpp"
#include "ggg/graph/spatial_index.hpp"

namespace ggg::encoding_detail {

namespace {

// The distance between the two closest vertices (infinity for fewer than two).
double closest_pair_distance(const std::vector<Vec2>& positions) {
    namespace bgi = spatial::bgi;
    using Entry = std::pair<spatial::Point, std::size_t>;
    std::vector<Entry> entries;
    entries.reserve(positions.size());
    for (std::size_t i = 0; i < positions.size(); ++i) entries.emplace_back(spatial::point(positions[i]), i);
    const spatial::RTree<Entry> tree(entries.begin(), entries.end());
    double closest = std::numeric_limits<double>::infinity();
    for (const Entry& e : entries) {
        for (auto it = tree.qbegin(bgi::nearest(e.first, 2)); it != tree.qend(); ++it) {
            if (it->second != e.second) closest = std::min(closest, (positions[it->second] - positions[e.second]).norm());
        }
    }
    return closest;
}

} // namespace

void Encoder::order_axiom_nonterminals() {
    namespace bgi = spatial::bgi;
    using Entry = std::pair<spatial::Point, std::size_t>;
    std::vector<std::size_t> slots; // where the nonterminals stand in graph_, in order
    std::vector<Entry> entries;
    for (std::size_t v = 0; v < nodes_.size(); ++v) {
        if (!nodes_[v].nonterminal) continue;
        entries.emplace_back(spatial::point(instances_[static_cast<std::size_t>(nodes_[v].id)].fit.t), v);
        slots.push_back(v);
    }
    if (slots.size() < 3) return;
    // A walk from each nonterminal to the nearest one not yet walked, starting beside the
    // vertex before the first: consecutive positions are close, and their deltas short.
    spatial::RTree<Entry> left(entries.begin(), entries.end());
    Vec2 at = slots.front() > 0 ? graph_.positions[slots.front() - 1] : Vec2(entries.front().first.get<0>(), entries.front().first.get<1>());
    std::vector<std::size_t> order; // per slot: the vertex of graph_ that goes there
    order.reserve(slots.size());
    while (!left.empty()) {
        const auto it = left.qbegin(bgi::nearest(spatial::point(at), 1));
        const Entry next = *it;
        left.remove(next);
        order.push_back(next.second);
        at = {next.first.get<0>(), next.first.get<1>()};
    }
    std::vector<std::size_t> source(nodes_.size()); // new position -> old vertex
    for (std::size_t v = 0; v < source.size(); ++v) source[v] = v;
    for (std::size_t k = 0; k < slots.size(); ++k) source[slots[k]] = order[k];
    GeometricGraph next;
    next.origin = graph_.origin;
    std::vector<Node> next_nodes;
    std::vector<VertexId> new_id(graph_.vertex_count(), -1);
    for (const std::size_t v : source) {
        new_id[v] = next.add_vertex(graph_.positions[v]);
        next.symbols.back() = graph_.symbols[v];
        next.frames.back() = graph_.frames[v];
        next_nodes.push_back(nodes_[v]);
    }
    for (std::size_t e = 0; e < graph_.edge_count(); ++e) {
        EdgeAttributes attributes;
        attributes.highway = graph_.edge_highway[e];
        next.add_edge(new_id[static_cast<std::size_t>(graph_.edges[e][0])], new_id[static_cast<std::size_t>(graph_.edges[e][1])], attributes);
    }
    graph_ = std::move(next);
    nodes_ = std::move(next_nodes);
}

void Encoder::number_in_derivation_order() {
    std::vector<std::int32_t> order; // new number -> old
    order.reserve(instances_.size());
    for (const Node& n : nodes_) {
        if (n.nonterminal) order.push_back(n.id);
    }
    for (std::size_t k = 0; k < order.size(); ++k) {
        for (const Node& m : instances_[static_cast<std::size_t>(order[k])].members) {
            if (m.nonterminal) order.push_back(m.id);
        }
    }
    if (order.size() != instances_.size()) return; // not a tree below the axiom: keep the numbers
    std::vector<std::int32_t> renumber(instances_.size());
    for (std::size_t k = 0; k < order.size(); ++k) renumber[static_cast<std::size_t>(order[k])] = static_cast<std::int32_t>(k);
    auto permute = [&](auto& per_instance) {
        std::remove_reference_t<decltype(per_instance)> reordered;
        reordered.reserve(per_instance.size());
        for (const std::int32_t old : order) reordered.push_back(std::move(per_instance[static_cast<std::size_t>(old)]));
        per_instance = std::move(reordered);
    };
    permute(instances_);
    permute(encoded_);
    auto fix = [&](Node& n) {
        if (n.nonterminal) n.id = renumber[static_cast<std::size_t>(n.id)];
    };
    for (Node& n : nodes_) fix(n);
    for (InstanceDraft& d : instances_) {
        for (Node& m : d.members) fix(m);
        if (d.parent >= 0) d.parent = renumber[static_cast<std::size_t>(d.parent)];
    }
}

Grammar Encoder::build_grammar() {
    Grammar g;
    g.name = "learned";
    g.origin = input_.origin;
    for (RuleDraft& r : rules_) {
        g.symbol_names.push_back("R" + std::to_string(r.rule.symbol));
        g.rules.push_back(std::move(r.rule));
    }
    Encoding& enc = g.encoding;
    enc.mode = options_.lossless ? "lossless" : "paper";
    // Levels of hierarchy: how deep instances nest, so the derivation steps that decode
    // the axiom (a pass of the analysis may add rules of street vertices only).
    int depth = 0;
    for (const InstanceDraft& d : instances_) {
        int n = 1;
        for (std::int32_t p = d.parent; p >= 0; p = instances_[static_cast<std::size_t>(p)].parent) ++n;
        depth = std::max(depth, n);
    }
    enc.levels = depth;
    enc.quantum_m = options_.quantum_m;
    // Decoding finds embedding partners and merges vertices within this distance: well
    // below the closest two input vertices, well above the rounding of what is stored.
    const double closest = closest_pair_distance(input_.positions);
    enc.tolerance_m = std::max(round_significant(0.25 * closest, 1), options_.quantum_m);
    // In paper mode vertices decode away from where they were, possibly towards each
    // other: the shared tolerance stays small, and each instance gets the room its
    // decoded surroundings leave (embed).
    if (!options_.lossless) enc.tolerance_m = std::min(enc.tolerance_m, std::max(1e-3, 10 * options_.quantum_m));
    placer_.assign(input_.vertex_count(), -1);
    axiom_index_.assign(input_.vertex_count(), -1);
    for (std::size_t i = 0; i < instances_.size(); ++i) {
        RuleInstance& ri = encoded_[i];
        const InstanceDraft& d = instances_[i];
        bool any_child = false;
        for (const Node& n : d.members) any_child |= n.nonterminal;
        for (std::size_t j = 0; j < d.members.size(); ++j) {
            const Node& n = d.members[j];
            if (any_child) ri.children.push_back(n.nonterminal ? n.id : -1);
            if (!n.nonterminal) placer_[static_cast<std::size_t>(n.id)] = static_cast<std::int32_t>(i);
        }
    }
    bool any_instance = false;
    for (std::size_t v = 0; v < graph_.vertex_count(); ++v) {
        const Node& n = nodes_[v];
        AxiomVertex av;
        av.position = round_to(graph_.positions[v], inverse_of(options_.quantum_m));
        av.symbol = graph_.symbols[v];
        if (n.nonterminal) {
            // The nonterminal stands where its rule's origin fits the copy, in the copy's own
            // frame: its instance needs next to no correction or shift.
            const InstanceDraft& d = instances_[static_cast<std::size_t>(n.id)];
            av.position = round_to(d.fit.t, inverse_of(options_.quantum_m));
            av.frame = frame_of(linear(d.fit), axiom_scale_inverse_step);
        }
        else axiom_index_[static_cast<std::size_t>(n.id)] = static_cast<std::int32_t>(v);
        g.axiom_vertices.push_back(av);
        enc.axiom_instances.push_back(n.nonterminal ? n.id : -1);
        any_instance |= n.nonterminal;
    }
    if (!any_instance) enc.axiom_instances.clear();
    for (std::size_t e = 0; e < input_.edge_count(); ++e) {
        const auto [u, v] = input_.edges[e];
        const std::int32_t a = axiom_index_[static_cast<std::size_t>(u)], b = axiom_index_[static_cast<std::size_t>(v)];
        if (a >= 0 && b >= 0) g.axiom_edges.push_back({a, b, input_.edge_highway[e]});
    }
    enc.instances = std::move(encoded_);
    return g;
}

void Encoder::simulate(Grammar& grammar) {
    Encoding& enc = grammar.encoding;
    const double inverse_quantum = inverse_of(options_.quantum_m);
    decoded_.assign(input_.vertex_count(), Vec2::Zero());
    placed_.assign(input_.vertex_count(), 0);
    effective_.assign(instances_.size(), Similarity2{});
    for (std::size_t v = 0; v < input_.vertex_count(); ++v) {
        if (axiom_index_[v] >= 0) {
            decoded_[v] = grammar.axiom_vertices[static_cast<std::size_t>(axiom_index_[v])].position;
            placed_[v] = 1;
        }
    }
    GeometricGraph g = grammar.axiom_graph();
    const DeriveOptions derive_options = decode_options(grammar);
    step_nonterminals_.assign(1, {});
    for (std::size_t v = 0; v < g.vertex_count(); ++v) {
        if (g.symbols[v]) step_nonterminals_[0].push_back({g.positions[v], -1});
    }
    for (int step = 0; step < enc.levels; ++step) {
        for (std::size_t q = 0; q < g.vertex_count(); ++q) {
            const std::int32_t id = g.instance_of(static_cast<VertexId>(q));
            if (id < 0) continue;
            RuleInstance& ri = enc.instances[static_cast<std::size_t>(id)];
            const InstanceDraft& d = instances_[static_cast<std::size_t>(id)];
            // The axiom's nonterminals carry their copies' frames (build_grammar): no correction.
            if (step > 0) ri.correction = correction_of(linear(d.fit) / linear(g.frames[q]));
            Similarity2 effective = g.frames[q] * ri.correction.at(Vec2::Zero());
            if (step > 0) ri.shift = round_to(d.fit.t - effective.t, inverse_quantum);
            effective.t += ri.shift;
            effective_[static_cast<std::size_t>(id)] = effective;
            if (!options_.lossless) continue;
            const Rule& rule = *grammar.rule_for(ri.symbol);
            ri.residuals.resize(rule.vertices.size());
            for (std::size_t j = 0; j < rule.vertices.size(); ++j) {
                ri.residuals[j] = round_to(node_position(d.members[j]) - effective.apply(rule.vertices[j].position), inverse_quantum);
            }
        }
        std::vector<VertexId> source;
        std::vector<Placement> placed;
        if (!derive_step(g, grammar, derive_options, nullptr, nullptr, &source, &placed)) break;
        step_nonterminals_.emplace_back();
        for (std::size_t v = 0; v < placed.size(); ++v) {
            const Placement& p = placed[v];
            if (p.instance < 0) continue;
            if (g.symbols[v]) step_nonterminals_.back().push_back({g.positions[v], p.instance});
            const Node& n = instances_[static_cast<std::size_t>(p.instance)].members[static_cast<std::size_t>(p.rule_vertex)];
            if (n.nonterminal) continue;
            decoded_[static_cast<std::size_t>(n.id)] = g.positions[v];
            placed_[static_cast<std::size_t>(n.id)] = 1;
        }
    }
    for (std::size_t v = 0; v < input_.vertex_count(); ++v) {
        if (!placed_[v]) decoded_[v] = input_.positions[v]; // merged into another vertex (paper mode)
    }
    // The derivation holds exactly the input's vertices, each where decoded_ says: then the
    // vertices present at each step are known, and links can name their partners by rank.
    derivation_matches_ = g.vertex_count() == input_.vertex_count() &&
                          std::all_of(placed_.begin(), placed_.end(), [](char p) { return p != 0; }) &&
                          std::all_of(g.symbols.begin(), g.symbols.end(), [](Symbol s) { return s == 0; });
}

void Encoder::embed(Grammar& grammar) {
    Encoding& enc = grammar.encoding;
    // The step in which each instance is rewritten: its depth below the axiom.
    std::vector<int> depth(instances_.size(), -1);
    for (std::size_t i = 0; i < instances_.size(); ++i) {
        int d = 0;
        for (std::int32_t p = instances_[i].parent; p >= 0; p = instances_[static_cast<std::size_t>(p)].parent) ++d;
        depth[i] = d;
    }
    auto step_of = [&](VertexId v) { // when the vertex appears: -1 for the axiom's
        const std::int32_t p = placer_[static_cast<std::size_t>(v)];
        return p < 0 ? -1 : depth[static_cast<std::size_t>(p)];
    };
    struct RawLink {
        std::int32_t vertex;
        VertexId x, y;
        HighwayClass highway;
    };
    std::vector<std::vector<RawLink>> raw(instances_.size());
    for (std::size_t e = 0; e < input_.edge_count(); ++e) {
        // The end that appears last carries the point (the other is there by then); on a
        // tie, the first end. An edge between two axiom vertices is an axiom edge.
        VertexId x = input_.edges[e][0];
        VertexId y = input_.edges[e][1];
        if (step_of(y) > step_of(x)) std::swap(x, y);
        const std::int32_t inst = placer_[static_cast<std::size_t>(x)];
        if (inst < 0 || placer_[static_cast<std::size_t>(y)] == inst) continue; // axiom edge, or a rule edge
        const InstanceDraft& d = instances_[static_cast<std::size_t>(inst)];
        std::int32_t j = 0;
        while (d.members[static_cast<std::size_t>(j)].nonterminal || d.members[static_cast<std::size_t>(j)].id != x) ++j;
        raw[static_cast<std::size_t>(inst)].push_back({j, x, y, input_.edge_highway[e]});
    }
    auto offset_of = [&](std::size_t inst, const RawLink& l) {
        return effective_[inst].inverse().apply_linear(decoded_[static_cast<std::size_t>(l.y)] - decoded_[static_cast<std::size_t>(l.x)]);
    };
    // Each rule's own embedding (for placing it by hand, and for its instances to reuse):
    // that of its best-joined instance, the first found of equals.
    std::vector<std::int32_t> best(grammar.rules.size(), -1);
    for (std::size_t i = 0; i < raw.size(); ++i) {
        const std::size_t r = enc.instances[i].symbol - 1;
        const auto b = static_cast<std::size_t>(best[r]);
        if (best[r] < 0 || raw[i].size() > raw[b].size() ||
            (raw[i].size() == raw[b].size() && instances_[i].first_number < instances_[b].first_number)) {
            best[r] = static_cast<std::int32_t>(i);
        }
    }
    std::vector<std::vector<std::pair<std::int32_t, EmbeddingPoint>>> rule_points(grammar.rules.size());
    for (std::size_t r = 0; r < grammar.rules.size(); ++r) {
        if (best[r] < 0) continue;
        std::vector<RawLink> links = raw[static_cast<std::size_t>(best[r])];
        std::stable_sort(links.begin(), links.end(), [](const RawLink& a, const RawLink& b) { return a.vertex < b.vertex; });
        for (const RawLink& l : links) {
            EmbeddingPoint ep{round_to(offset_of(static_cast<std::size_t>(best[r]), l), rule_point_inverse_step), l.highway};
            grammar.rules[r].vertices[static_cast<std::size_t>(l.vertex)].embedding.push_back(ep);
            rule_points[r].emplace_back(l.vertex, ep);
        }
    }
    // What is present around each place when an instance's embedding is resolved, in the
    // step that rewrites it: the streets placed by then and the nonterminals that step places.
    namespace bg = spatial::bg;
    namespace bgi = spatial::bgi;
    using Entry = std::pair<spatial::Point, std::uint32_t>;
    using Tree = spatial::RTree<Entry>;
    std::vector<Entry> street_entries;
    for (std::size_t v = 0; v < decoded_.size(); ++v) street_entries.emplace_back(spatial::point(decoded_[v]), static_cast<std::uint32_t>(v));
    const Tree streets(street_entries.begin(), street_entries.end());
    std::vector<Tree> nonterminals;
    for (const auto& placed : step_nonterminals_) {
        std::vector<Entry> entries;
        for (std::size_t k = 0; k < placed.size(); ++k) entries.emplace_back(spatial::point(placed[k].position), static_cast<std::uint32_t>(k));
        nonterminals.emplace_back(entries.begin(), entries.end());
    }
    // A link names its partner by rank (RuleInstance::neighbours) only where decoding sees
    // the same vertices as this derivation (always so far: the vertices of instances never
    // merge, and a learned grammar places nothing but its instances).
    const bool ranks = derivation_matches_;
    // The rank of y among the vertices nearest to x when instance i's embedding is resolved,
    // its own left out; none where another vertex is about as near as y (ties must not
    // decide) or y is not among the nearest few hundred (an offset is then as short).
    constexpr auto max_rank = static_cast<std::size_t>(RuleInstance::max_rank);
    auto rank_of = [&](std::size_t i, VertexId x, VertexId y) -> std::optional<std::int32_t> {
        const Vec2 p = decoded_[static_cast<std::size_t>(x)];
        const double dy = (decoded_[static_cast<std::size_t>(y)] - p).squaredNorm();
        const double margin = 1e-9 * dy + 1e-18;
        const int step = depth[i];
        const auto inst = static_cast<std::int32_t>(i);
        const unsigned k = static_cast<unsigned>(max_rank + 2);
        std::size_t nearer = 0, alike = 0;
        auto count = [&](const Vec2& q) {
            const double d = (q - p).squaredNorm();
            if (d < dy - margin) ++nearer;
            else if (d <= dy + margin) ++alike;
        };
        bool reached = false; // y itself among the nearest k
        const auto present = [&](const Entry& e) { return step_of(static_cast<VertexId>(e.second)) <= step && placer_[e.second] != inst; };
        double farthest = 0.0;
        std::size_t found = 0;
        for (auto it = streets.qbegin(bgi::nearest(spatial::point(p), k) && bgi::satisfies(present)); it != streets.qend(); ++it) {
            ++found;
            const Vec2& q = decoded_[it->second];
            farthest = std::max(farthest, (q - p).squaredNorm());
            if (static_cast<VertexId>(it->second) == y) {
                reached = true;
                continue;
            }
            count(q);
        }
        if (!reached) return std::nullopt;
        if (found == k && farthest <= dy + margin) return std::nullopt; // more may lie as near beyond the k
        const auto s = static_cast<std::size_t>(step + 1);
        if (s < nonterminals.size()) {
            const auto& placed = step_nonterminals_[s];
            const auto others = [&](const Entry& e) { return placed[e.second].instance != inst; };
            for (auto it = nonterminals[s].qbegin(bgi::intersects(spatial::around(p, std::sqrt(dy + margin) * (1 + 1e-12))) && bgi::satisfies(others));
                 it != nonterminals[s].qend(); ++it) {
                count(placed[it->second].position);
            }
        }
        if (alike || nearer > max_rank) return std::nullopt;
        return static_cast<std::int32_t>(nearer);
    };
    // How far apart things are around a partner, for the tolerance of links aimed by an offset:
    // all the streets (more than are placed by then, which only errs on the safe side) and
    // the nonterminals of the step.
    const double same_place = 0.1 * options_.quantum_m; // only the vertex itself is nearer
    auto nearest_other = [&](const Tree& tree, const Vec2& p) {
        for (auto it = tree.qbegin(bgi::nearest(spatial::point(p), 2)); it != tree.qend(); ++it) {
            const double d = std::hypot(bg::get<0>(it->first) - p.x(), bg::get<1>(it->first) - p.y());
            if (d > same_place) return d; // nearest first; a nearer one is the vertex itself
        }
        return std::numeric_limits<double>::infinity();
    };
    auto room = [&](const Vec2& p, int step) {
        const double d = nearest_other(streets, p);
        const auto s = static_cast<std::size_t>(step);
        return s < nonterminals.size() ? std::min(d, nearest_other(nonterminals[s], p)) : d;
    };
    for (std::size_t i = 0; i < raw.size(); ++i) {
        RuleInstance& ri = enc.instances[i];
        std::vector<RawLink> aimed; // the links that need an offset
        for (const RawLink& l : raw[i]) {
            const std::optional<std::int32_t> rank = ranks ? rank_of(i, l.x, l.y) : std::nullopt;
            if (rank) ri.neighbours.push_back({l.vertex, *rank, l.highway});
            else aimed.push_back(l);
        }
        if (aimed.empty()) continue;
        // Half the room around the instance's partners: an embedding point that lands
        // within half the tolerance of its partner has no other vertex nearer (the
        // instance's own vertices never merge, see derive_step).
        double r = std::numeric_limits<double>::infinity();
        for (const RawLink& l : aimed) r = std::min(r, room(decoded_[static_cast<std::size_t>(l.y)], depth[i] + 1));
        const double half = 0.5 * r;
        double tolerance = enc.tolerance_m;
        if (std::isfinite(half) && half > enc.tolerance_m) {
            const int exponent = static_cast<int>(std::floor(std::log10(half)));
            tolerance = one_digit_decimal(std::min(9.0, std::floor(half / std::pow(10.0, exponent))), exponent); // rounded down to one digit
        }
        if (tolerance > enc.tolerance_m) ri.tolerance_m = tolerance;
        const Similarity2& f = effective_[i];
        const auto& shared = rule_points[ri.symbol - 1];
        std::vector<char> taken(shared.size(), 0);
        for (const RawLink& l : aimed) {
            const Vec2 partner = decoded_[static_cast<std::size_t>(l.y)];
            bool reused = false;
            for (std::size_t p = 0; p < shared.size() && !reused; ++p) {
                if (taken[p] || shared[p].first != l.vertex || shared[p].second.highway != l.highway) continue;
                const Vec2 target = decoded_[static_cast<std::size_t>(l.x)] + f.apply_linear(shared[p].second.offset);
                if ((target - partner).norm() <= 0.5 * tolerance) {
                    taken[p] = 1;
                    ri.rule_points.push_back(static_cast<std::int32_t>(p));
                    reused = true;
                }
            }
            if (reused) continue;
            // Rounded so that the aim errs by at most 0.71 of the tolerance: every other vertex
            // is at least twice the tolerance from the partner, so the nearest within the
            // tolerance of the aim is the partner.
            const double inverse_step = inverse_power_of_ten(tolerance / f.scale());
            RuleInstance::Link link;
            link.vertex = l.vertex;
            link.point.offset = round_to(offset_of(i, l), inverse_step);
            link.point.highway = l.highway;
            ri.embedding.push_back(link);
        }
        std::sort(ri.rule_points.begin(), ri.rule_points.end());
    }
}

void Encoder::check_roundtrip() {
    const Grammar& grammar = result_.grammar;
    DeriveReport report;
    const GeometricGraph decoded = decode_grammar(grammar, &report);
    result_.grammar.encoding.decoded_vertices = static_cast<std::int64_t>(decoded.vertex_count());
    result_.grammar.encoding.decoded_edges = static_cast<std::int64_t>(decoded.edge_count());
    result_.grammar.encoding.decoded_length_m = street_length_m(decoded);
    std::vector<std::int32_t> original(decoded.vertex_count(), -1);
    std::vector<std::int32_t> axiom_vertex(grammar.axiom_vertices.size(), -1);
    for (std::size_t v = 0; v < input_.vertex_count(); ++v) {
        if (axiom_index_[v] >= 0) axiom_vertex[static_cast<std::size_t>(axiom_index_[v])] = static_cast<std::int32_t>(v);
    }
    for (std::size_t v = 0; v < decoded.vertex_count(); ++v) {
        const Placement& p = report.placed_by[v];
        if (p.instance >= 0) {
            const Node& n = instances_[static_cast<std::size_t>(p.instance)].members[static_cast<std::size_t>(p.rule_vertex)];
            if (!n.nonterminal) original[v] = n.id;
        } else if (report.source_vertex[v] >= 0) {
            original[v] = axiom_vertex[static_cast<std::size_t>(report.source_vertex[v])];
        }
    }
    RoundTrip& rt = result_.roundtrip;
    std::vector<char> seen(input_.vertex_count(), 0);
    double sum = 0.0;
    for (std::size_t v = 0; v < decoded.vertex_count(); ++v) {
        if (original[v] < 0) continue;
        const double d = (decoded.positions[v] - input_.positions[static_cast<std::size_t>(original[v])]).norm();
        rt.max_displacement_m = std::max(rt.max_displacement_m, d);
        sum += d;
        seen[static_cast<std::size_t>(original[v])] = 1;
    }
    rt.unplaced_vertices = static_cast<std::size_t>(std::count(seen.begin(), seen.end(), 0));
    const std::size_t matched = input_.vertex_count() - rt.unplaced_vertices;
    rt.mean_displacement_m = matched ? sum / static_cast<double>(matched) : 0.0;
    auto key = [](std::int64_t a, std::int64_t b) { return static_cast<std::uint64_t>(std::min(a, b)) << 32 | static_cast<std::uint64_t>(std::max(a, b)); };
    std::unordered_map<std::uint64_t, HighwayClass> expected;
    for (std::size_t e = 0; e < input_.edge_count(); ++e) expected.emplace(key(input_.edges[e][0], input_.edges[e][1]), input_.edge_highway[e]);
    std::unordered_set<std::uint64_t> found;
    bool classes = true;
    for (std::size_t e = 0; e < decoded.edge_count(); ++e) {
        const std::int32_t a = original[static_cast<std::size_t>(decoded.edges[e][0])];
        const std::int32_t b = original[static_cast<std::size_t>(decoded.edges[e][1])];
        const auto it = a >= 0 && b >= 0 ? expected.find(key(a, b)) : expected.end();
        if (it == expected.end()) {
            ++rt.extra_edges;
            continue;
        }
        found.insert(it->first);
        classes &= it->second == decoded.edge_highway[e];
    }
    rt.missing_edges = expected.size() - found.size();
    rt.edges_equal = rt.missing_edges == 0 && rt.extra_edges == 0 && decoded.edge_count() == input_.edge_count() &&
                     rt.unplaced_vertices == 0 && decoded.vertex_count() == input_.vertex_count();
    rt.classes_equal = rt.edges_equal && classes;
}

} // namespace ggg::encoding_detail
