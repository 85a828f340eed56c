// The encoder: levels of rules from the analyzer's isogroups, then the instances' frame
// corrections, residuals and embedding against a real derivation. See grammar_encoder.hpp;
// encoder.hpp names the stages, of which this file holds the levels.
#include "ggg/encoding/grammar_encoder.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>
#include <unordered_map>

#include "ggg/error.hpp"
#include "encoder.hpp"

namespace ggg {

namespace encoding_detail {

namespace {

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

} // namespace

LearnResult Encoder::run() {
    const auto start = Clock::now();
    start_ = start;
    start_level_graph();
    const int max_levels = options_.max_levels > 0 ? options_.max_levels : 1'000'000;
    int level = 1;
    if (!options_.seed.empty()) encode_level(level++, true);
    for (; level <= max_levels; ++level) {
        // Complete encoding: where nothing pays any more, whatever still repeats keeps the
        // encoding going (smaller patterns, down to a pair of vertices).
        if (!encode_level(level, false) && !(options_.complete && !result_.stopped_by_budget && encode_level(level, false, Take::repeating))) break;
        if (result_.stopped_by_budget) break;
    }
    // ... and what never repeated becomes one rule, used once: the axiom is one vertex.
    if (options_.complete && graph_.vertex_count() > 1) encode_rest(level);
    report(progress_, 0.92, "building the grammar");
    result_.axiom_edges = graph_.edge_count();
    number_in_derivation_order();
    for (std::size_t i = 0; i < instances_.size(); ++i) instances_[i].first_number = static_cast<std::int32_t>(i);
    order_axiom_nonterminals();
    number_in_derivation_order();
    Grammar grammar = build_grammar();
    report(progress_, 0.94, "computing each instance's frame and residuals");
    simulate(grammar);
    report(progress_, 0.97, "joining the instances to their streets");
    embed(grammar);
    result_.grammar = std::move(grammar);
    report(progress_, 0.98, "decoding the grammar to check it");
    check_roundtrip();
    result_.encoding_seconds = seconds_since(start) - result_.analysis_seconds;
    report(progress_, 1.0, "done");
    return std::move(result_);
}

void Encoder::start_level_graph() {
    graph_.origin = input_.origin;
    graph_.reserve(input_.vertex_count(), input_.edge_count(), 2 * input_.edge_count());
    for (std::size_t v = 0; v < input_.vertex_count(); ++v) {
        graph_.add_vertex(input_.positions[v]);
        nodes_.push_back({false, static_cast<std::int32_t>(v)});
    }
    for (std::size_t e = 0; e < input_.edge_count(); ++e) {
        EdgeAttributes a;
        a.highway = input_.edge_highway[e];
        graph_.add_edge(input_.edges[e][0], input_.edges[e][1], a);
    }
    // What a vertex and an edge cost in the packed graph (io/grammar_packing.cpp): the
    // yardstick of what a rule saves.
    const double inverse = inverse_of(options_.quantum_m);
    double vertex_bytes = 0.0, edge_bytes = 0.0;
    std::int64_t px = 0, py = 0, previous = 0;
    for (const Vec2& p : input_.positions) {
        const auto x = std::llround(p.x() * inverse), y = std::llround(p.y() * inverse);
        vertex_bytes += cbor_bytes(x - px) + cbor_bytes(y - py);
        px = x;
        py = y;
    }
    for (std::size_t e = 0; e < input_.edge_count(); ++e) {
        const auto [u, v] = input_.edges[e];
        edge_bytes += cbor_bytes(u - previous) + cbor_bytes(static_cast<std::int64_t>(v) - u) + 1;
        previous = u;
    }
    if (input_.vertex_count()) vertex_bytes_ = vertex_bytes / static_cast<double>(input_.vertex_count());
    if (input_.edge_count()) edge_bytes_ = edge_bytes / static_cast<double>(input_.edge_count());
}

bool Encoder::encode_level(int level, bool seeded, Take take) {
    if (graph_.edge_count() == 0) return false;
    const auto level_start = Clock::now();
    // Each level takes half of what is left of the first 90 %: the count of levels is not
    // known in advance, and the first levels, on the largest graphs, take longest.
    const double done = progress_done_;
    const double share = (0.9 - done) * 0.5;
    progress_done_ += share;
    ProgressCallback stage;
    if (progress_) {
        const std::string prefix = "level " + std::to_string(level) + ": ";
        stage = [&, prefix](double f, std::string_view message) { return progress_(done + share * f, prefix + std::string(message)); };
    }
    report(stage, 0.0, "analysing " + std::to_string(graph_.vertex_count()) + " vertices");
    const auto analysis_start = Clock::now();
    AnalyzeOptions analysis_options = options_.analysis;
    if (seeded) analysis_options.seed = options_.seed;
    // The analysis budget is the whole learning's: each level gets what is left of it.
    if (const double budget = time_budget_seconds(options_.analysis.detection); budget > 0) {
        const double left = budget - seconds_since(start_);
        if (left <= 0) {
            result_.stopped_by_budget = true;
            return false;
        }
        analysis_options.detection.max_seconds = left;
    }
    const Analysis analysis = analyze(graph_, analysis_options, stage);
    result_.analysis_seconds += seconds_since(analysis_start);
    if (analysis.stopped_by_budget) result_.stopped_by_budget = true;

    const Adjacency adj(graph_);
    std::vector<char> used(graph_.vertex_count(), 0);
    std::vector<std::int32_t> level_instances;
    LevelReport lr;
    lr.level = level;
    lr.vertices = graph_.vertex_count();
    lr.edges = graph_.edge_count();
    auto eligible = [&](const AnalyzedIsogroup& ag) {
        // The analyzer ranks by its own count of numbers; whether a group pays in the
        // packed file is decided for each (encode_group), so every group is tried, best first.
        if (ag.group.order() < 2 || ag.group.pattern.edges.empty()) return false;
        // One street between two street vertices is no pattern (every street is one): with
        // links as cheap as they are, it would pay as a rule, and a grammar of single streets
        // shows nothing and grows nothing. Complete encoding takes it when nothing else is left.
        const auto& symbols = ag.group.pattern.symbols;
        if (take == Take::paying && ag.group.order() == 2 && symbols[0] == 0 && symbols[1] == 0) return false;
        return ag.selection.non_overlapping.size() >= options_.analysis.detection.min_count;
    };
    for (const AnalyzedIsogroup& ag : analysis.isogroups) {
        if (seeded && &ag != &analysis.isogroups.front()) break; // the seed's own group only
        if (eligible(ag)) encode_group(ag.group, seeded ? Take::seed : take, level, adj, used, level_instances, lr);
    }
    if (level_instances.empty() && rules_.empty() && take == Take::paying && !seeded) {
        // Nothing pays for its rule and residuals as well: a grammar without rules shows
        // nothing and grows nothing, so the first pass takes one pattern whose copies would
        // pay for themselves in paper mode: of those, the one that costs least with its rule
        // and residuals (the file grows by little, or even shrinks: the count is an estimate).
        const AnalyzedIsogroup* cheapest = nullptr;
        double cheapest_gain = -std::numeric_limits<double>::infinity();
        LevelReport scratch;
        for (const AnalyzedIsogroup& ag : analysis.isogroups) {
            if (!eligible(ag)) continue;
            const auto gains = encode_group(ag.group, take, level, adj, used, level_instances, scratch, true);
            if (gains && gains->paper > 0 && gains->strict > cheapest_gain) cheapest = &ag, cheapest_gain = gains->strict;
        }
        if (cheapest) {
            strict_gain_ = false;
            encode_group(cheapest->group, take, level, adj, used, level_instances, lr);
            strict_gain_ = true;
        }
    }
    if (level_instances.empty()) {
        if (seeded) lr.seconds = seconds_since(level_start), result_.levels.push_back(lr);
        return false;
    }
    contract(level_instances, used);
    occurrence_of_.clear();
    lr.seconds = seconds_since(level_start);
    result_.levels.push_back(lr);
    return true;
}

void Encoder::encode_rest(int level) {
    const auto level_start = Clock::now();
    const Adjacency adj(graph_);
    std::vector<VertexId> all(graph_.vertex_count());
    for (std::size_t v = 0; v < all.size(); ++v) all[v] = static_cast<VertexId>(v);
    Similarity2 frame;
    Isogroup rest;
    rest.pattern = induced_pattern(graph_, adj, all, &frame);
    rest.vertices = all;
    rest.transforms.push_back(frame);
    LevelReport lr;
    lr.level = level;
    lr.vertices = graph_.vertex_count();
    lr.edges = graph_.edge_count();
    std::vector<char> used(graph_.vertex_count(), 0);
    std::vector<std::int32_t> level_instances;
    encode_group(rest, Take::once, level, adj, used, level_instances, lr);
    if (level_instances.empty()) return;
    contract(level_instances, used);
    occurrence_of_.clear();
    lr.seconds = seconds_since(level_start);
    result_.levels.push_back(lr);
}

void Encoder::contract(const std::vector<std::int32_t>& level_instances, const std::vector<char>& used) {
    GeometricGraph next;
    next.origin = graph_.origin;
    std::vector<Node> next_nodes;
    std::vector<VertexId> new_id(graph_.vertex_count(), -1);
    for (std::size_t v = 0; v < graph_.vertex_count(); ++v) {
        if (used[v]) continue;
        new_id[v] = next.add_vertex(graph_.positions[v]);
        next.symbols.back() = graph_.symbols[v];
        next.frames.back() = graph_.frames[v];
        next_nodes.push_back(nodes_[v]);
    }
    for (std::size_t i = 0; i < level_instances.size(); ++i) {
        const auto id = static_cast<std::size_t>(level_instances[i]);
        const InstanceDraft& inst = instances_[id];
        const VertexId n = next.add_vertex(inst.frame.t);
        next.symbols.back() = inst.symbol;
        next.frames.back() = inst.frame;
        next_nodes.push_back({true, static_cast<std::int32_t>(id)});
        for (VertexId v : occurrence_of_[i]) new_id[static_cast<std::size_t>(v)] = n;
    }
    std::unordered_map<std::uint64_t, EdgeId> seen;
    seen.reserve(graph_.edge_count());
    for (std::size_t e = 0; e < graph_.edge_count(); ++e) {
        const VertexId a = new_id[static_cast<std::size_t>(graph_.edges[e][0])];
        const VertexId b = new_id[static_cast<std::size_t>(graph_.edges[e][1])];
        if (a == b) continue;
        const std::uint64_t key = static_cast<std::uint64_t>(std::min(a, b)) << 32 | static_cast<std::uint32_t>(std::max(a, b));
        const auto [it, inserted] = seen.emplace(key, static_cast<EdgeId>(next.edge_count()));
        if (inserted) {
            EdgeAttributes attributes;
            attributes.highway = graph_.edge_highway[e];
            next.add_edge(a, b, attributes);
        } else if (highway_rank(graph_.edge_highway[e]) < highway_rank(next.edge_highway[static_cast<std::size_t>(it->second)])) {
            next.edge_highway[static_cast<std::size_t>(it->second)] = graph_.edge_highway[e];
        }
    }
    graph_ = std::move(next);
    nodes_ = std::move(next_nodes);
}

} // namespace encoding_detail

void check_options(const LearnOptions& o) {
    check_options(o.analysis);
    if (!o.analysis.seed.empty()) throw UsageError("learning analyses the whole graph: it takes no seed");
    if (o.max_levels < 0) throw UsageError("levels: the number of levels must be >= 0 (0 = until nothing repeats)");
    const double exponent = std::log10(o.quantum_m);
    if (!(o.quantum_m >= 1e-9 && o.quantum_m <= 1e-2) || std::abs(exponent - std::round(exponent)) > 1e-9) {
        throw UsageError("the quantum must be a power of ten between 1e-9 and 1e-2 m");
    }
    if (!(o.max_shape_error >= 0) || !std::isfinite(o.max_shape_error)) throw UsageError("max_shape_error: the shape error must be a finite number >= 0");
    if (!(o.max_vertex_error_m >= 0) || !std::isfinite(o.max_vertex_error_m)) throw UsageError("max_vertex_error_m: the vertex error must be a finite number of metres >= 0");
    if (!(o.frame_tolerance_deg >= 0) || !(o.frame_scale_tolerance >= 1) || !std::isfinite(o.frame_scale_tolerance)) {
        throw UsageError("the frame tolerance must be >= 0 degrees and the scale tolerance a finite factor >= 1");
    }
}

LearnResult learn_grammar(const GeometricGraph& graph, const LearnOptions& options, const ProgressCallback& progress) {
    check_options(options);
    if (graph.edge_count() == 0) throw InputError("the graph has no streets to learn from");
    for (VertexId v : options.seed) {
        if (v < 0 || static_cast<std::size_t>(v) >= graph.vertex_count()) throw UsageError("a seed vertex is out of range");
    }
    return encoding_detail::Encoder(graph, options, progress).run();
}

} // namespace ggg
