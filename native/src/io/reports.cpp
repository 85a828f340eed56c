#include "ggg/io/reports.hpp"

#include <algorithm>
#include <cmath>

#include "ggg/io/grammar_file.hpp"
#include "grammar_packing.hpp"
#include "json_util.hpp"

namespace ggg {

nlohmann::json detection_orders_json(const std::vector<OrderReport>& orders) {
    nlohmann::json out = nlohmann::json::array();
    for (const OrderReport& r : orders) {
        out.push_back({{"order", r.order},
                       {"parents", r.parents},
                       {"candidates", r.candidates},
                       {"children", r.children},
                       {"groups", r.groups},
                       {"expanded_next", r.expanded_next},
                       {"occurrences", r.occurrences}});
    }
    return out;
}

nlohmann::json analysis_report_json(const GeometricGraph& graph, const Analysis& analysis,
                                    const AnalysisReportOptions& options) {
    nlohmann::json groups = nlohmann::json::array();
    const std::size_t shown = options.top == 0 ? analysis.isogroups.size() : std::min(options.top, analysis.isogroups.size());
    for (std::size_t i = 0; i < shown; ++i) {
        const AnalyzedIsogroup& a = analysis.isogroups[i];
        nlohmann::json j{{"order", a.group.order()},
                         {"edge_count", a.group.pattern.edges.size()},
                         {"occurrences", a.group.frequency()},
                         {"non_overlapping", a.selection.non_overlapping.size()},
                         {"score", a.score},
                         {"gain", a.selection.gain},
                         {"selection_exact", a.selection.exact},
                         {"parent", a.parent},
                         {"size_m", a.group.pattern.metres_per_unit},
                         {"recounted", a.recounted}};
        if (options.occurrence_osm_nodes) {
            nlohmann::json list = nlohmann::json::array();
            for (std::size_t o = 0; o < a.group.frequency(); ++o) {
                nlohmann::json ids = nlohmann::json::array();
                for (VertexId v : a.group.occurrence(o)) {
                    const auto index = static_cast<std::size_t>(v);
                    ids.push_back(index < graph.vertex_osm_ids.size() ? graph.vertex_osm_ids[index] : 0);
                }
                list.push_back(std::move(ids));
            }
            j["occurrence_osm_nodes"] = std::move(list);
        }
        groups.push_back(std::move(j));
    }
    nlohmann::json out{{"graph", {{"vertices", graph.vertex_count()}, {"edges", graph.edge_count()}}},
                       {"detected", analysis.detected},
                       {"stopped_by_budget", analysis.stopped_by_budget},
                       {"isogroups", std::move(groups)}};
    if (options.orders) out["orders"] = detection_orders_json(analysis.orders);
    return out;
}

nlohmann::json growth_report_json(const GrowReport& r) {
    nlohmann::json hand = nlohmann::json::array();
    for (const PlacementOutcome outcome : r.hand_placements) hand.push_back(std::string(outcome_name(outcome)));
    return {
        {"hand_placements", std::move(hand)},
        {"placements", r.placements},
        {"attempts", r.attempts},
        {"rejected_outside", r.rejected_outside},
        {"rejected_crossing", r.rejected_crossing},
        {"rejected_crowded", r.rejected_crowded},
        {"rejected_off_grid", r.rejected_off_grid},
        {"rejected_small_block", r.rejected_small_block},
        {"rejected_star", r.rejected_star},
        {"rejected_sharp", r.rejected_sharp},
        {"traced_seeds", r.traced_seeds},
        {"traced_streets", r.traced_streets},
        {"traced_joined", r.traced_joined},
        {"traced_t_junctions", r.traced_t_junctions},
        {"traced_dense", r.traced_dense},
        {"traced_across", r.traced_across},
        {"traced_avenues", r.traced_avenues},
        {"traced_crossed", r.traced_crossed},
        {"traced_empty_ground", r.traced_empty_ground},
        {"traced_joined_offsets", r.traced_joined_offsets},
        {"traced_closed_corners", r.traced_closed_corners},
        {"traced_offset_crossings", r.traced_offset_crossings},
        {"thinned_streets", r.thinned_streets},
        {"traced_junction_islands", r.traced_junction_islands},
        {"added_vertices", r.added_vertices},
        {"added_edges", r.added_edges},
        {"border_connections", r.border_connections},
        {"closing_edges", r.closing_edges},
        {"t_junctions", r.t_junctions},
        {"pruned_stubs", r.pruned_stubs},
        {"roundabouts", r.roundabouts},
        {"cul_de_sacs", r.cul_de_sacs},
        {"dissolved_vertices", r.dissolved_vertices},
        {"squared_junctions", r.squared_junctions},
        {"split_vertices", r.split_vertices},
        {"removed_crossing_streets", r.removed_crossing_streets},
        {"island_streets", r.island_streets},
        {"main_road_routes", r.main_road_routes},
        {"raised_streets", r.raised_streets},
        {"main_road_connectors", r.main_road_connectors},
        {"main_road_extensions", r.main_road_extensions},
        {"intersections", r.intersections},
        {"grid", r.grid},
        {"filled", r.filled},
        {"stopped_by_budget", r.stopped_by_budget},
    };
}


namespace {

// Where the bytes of a packed file (CBOR) go: each part the CBOR bytes of its columns, and
// "header" the rest (format, name, symbols, settings, the arrays that hold the columns). A
// grammar is smaller than its graph where its parts, together, take less than positions
// and edges do. A column is named by its section and its name in io_detail's lists.
using Parts = std::vector<std::pair<const char*, std::vector<std::pair<const char*, const char*>>>>;

// `placed`: the document lays its columns out by place (a grammar that does not pack, a
// value off the packed units, is version 1 and all header).
nlohmann::json cbor_parts(const nlohmann::json& doc, const Parts& parts, bool placed_columns = true) {
    nlohmann::json out = nlohmann::json::object();
    std::size_t counted = 0;
    for (const auto& [part, columns] : parts) {
        std::size_t bytes = 0;
        for (const auto& [section, key] : columns) {
            if (!placed_columns || !doc.contains(section)) continue;
            const nlohmann::json& placed = doc.at(section);
            const auto at = io_detail::column_place(section, key);
            if (at && placed.is_array() && *at < placed.size() && !placed[*at].empty()) bytes += nlohmann::json::to_cbor(placed[*at]).size();
        }
        out[part] = bytes;
        counted += bytes;
    }
    out["header"] = nlohmann::json::to_cbor(doc).size() - counted;
    return out;
}

nlohmann::json bytes_report(const GeometricGraph& input, const Grammar& g) {
    const double quantum = g.encoding.quantum_m > 0 ? g.encoding.quantum_m : LearnOptions{}.quantum_m;
    nlohmann::json out = {{"original", graph_structure_bytes(input, quantum)},
                          {"encoded", grammar_bytes(g)},
                          {"original_cbor", graph_structure_bytes(input, quantum, true)},
                          {"encoded_cbor", grammar_bytes(g, true)}};
    static const Parts graph_parts = {{"positions", {{"graph", "x"}, {"graph", "y"}}}, {"edges", {{"graph", "edges"}}}};
    static const Parts grammar_parts = {
        {"rules", {{"rules", "uses"}, {"rules", "size_cm"}, {"rules", "vertices"}, {"rules", "edges"}, {"rules", "x"}, {"rules", "y"},
                   {"rules", "symbol"}, {"rules", "transform"}, {"rules", "embedding"}, {"rules", "points"}, {"rules", "edge_list"}}},
        {"axiom_positions", {{"axiom", "x"}, {"axiom", "y"}}},
        {"axiom_edges", {{"axiom", "edges"}}},
        {"nonterminals", {{"axiom", "nonterminals"}, {"axiom", "symbol_order"}, {"axiom", "symbol"}, {"axiom", "frames"}}},
        {"corrections", {{"encoding", "correction"}, {"encoding", "shift"}, {"encoding", "tolerance"}}},
        {"links", {{"encoding", "neighbours"}, {"encoding", "embedding"}, {"encoding", "link_classes"}, {"encoding", "rule_points"},
                   {"encoding", "edge_classes"}}},
        {"residuals", {{"encoding", "residuals"}}}};
    const nlohmann::json grammar_doc = grammar_to_json(g);
    out["parts_cbor"] = {{"original", cbor_parts(io_detail::pack_graph(input, quantum), graph_parts)},
                         {"encoded", cbor_parts(grammar_doc, grammar_parts, grammar_doc.value("version", 0) == io_detail::packed_grammar_version)}};
    return out;
}

} // namespace

nlohmann::json learn_report(const GeometricGraph& input, const LearnResult& result) {
    nlohmann::json levels = nlohmann::json::array();
    for (const LevelReport& l : result.levels) {
        levels.push_back({{"level", l.level},
                          {"vertices", l.vertices},
                          {"edges", l.edges},
                          {"rules", l.rules},
                          {"instances", l.instances},
                          {"frame_rejected", l.frame_rejected},
                          {"shape_rejected", l.shape_rejected},
                          {"error_rejected", l.error_rejected},
                          {"bytes_saved", std::lround(l.bytes_saved)},
                          {"seconds", l.seconds}});
    }
    const RoundTrip& rt = result.roundtrip;
    const Grammar& g = result.grammar;
    return {
        {"input", {{"vertices", input.vertex_count()}, {"edges", input.edge_count()}}},
        {"mode", g.encoding.mode},
        {"rules", g.rules.size()},
        {"instances", g.encoding.instances.size()},
        {"levels", g.encoding.levels},
        {"stopped_by_budget", result.stopped_by_budget},
        {"axiom", {{"vertices", g.axiom_vertices.size()}, {"edges", result.axiom_edges}}},
        {"seconds", {{"analysis", result.analysis_seconds}, {"encoding", result.encoding_seconds}}},
        {"bytes", bytes_report(input, g)},
        {"roundtrip",
         {{"edges_equal", rt.edges_equal},
          {"classes_equal", rt.classes_equal},
          {"missing_edges", rt.missing_edges},
          {"extra_edges", rt.extra_edges},
          {"unplaced_vertices", rt.unplaced_vertices},
          {"max_displacement_m", rt.max_displacement_m},
          {"mean_displacement_m", rt.mean_displacement_m}}},
        {"per_level", std::move(levels)},
    };
}

std::size_t graph_structure_bytes(const GeometricGraph& g, double quantum_m, bool cbor) {
    const nlohmann::json doc = io_detail::pack_graph(g, quantum_m);
    return cbor ? nlohmann::json::to_cbor(doc).size() : io_detail::dump(doc).size() + 1;
}

std::size_t grammar_bytes(const Grammar& grammar, bool cbor) { return grammar_bytes_text(grammar, cbor).size(); }

namespace {

// The figures of one network in `ggg compare` (docs/measures.md).
nlohmann::json summary(const StreetStatistics& s) {
    auto median = [](const std::vector<double>& sorted) {
        if (sorted.empty()) return 0.0;
        const std::size_t n = sorted.size();
        return n % 2 ? sorted[n / 2] : 0.5 * (sorted[n / 2 - 1] + sorted[n / 2]);
    };
    const auto bins = static_cast<int>(s.degree_histogram.size());
    double mean_degree = 0.0;
    for (int d = 0; d < bins; ++d) mean_degree += d * s.degree_histogram[static_cast<std::size_t>(d)];
    double stars = 0.0, junctions = 0.0;
    for (int d = 5; d < bins; ++d) stars += s.degree_histogram[static_cast<std::size_t>(d)];
    for (int d = 3; d < bins; ++d) junctions += s.degree_histogram[static_cast<std::size_t>(d)];
    // Crossings among the junctions (the share of four-way intersections): a grid's are most
    // of them, a network grown street by street into T-junctions has few.
    const double crossings = bins > 4 && junctions > 0 ? s.degree_histogram[4] / junctions : 0.0;
    return {{"vertices", s.vertices},
            {"junctions", s.junctions},
            {"dead_end_share", s.degree_histogram[1]},
            {"degree2_share", s.degree_histogram[2]},
            {"star_share", stars},
            {"crossing_share", crossings},
            {"right_angle_share", s.right_angle_share},
            {"through_share", s.through_share},
            {"circuity", std::isfinite(s.circuity) ? nlohmann::json(s.circuity) : nlohmann::json(nullptr)},
            {"edges", s.edges},
            {"mean_degree", mean_degree},
            {"median_edge_length_m", median(s.edge_lengths_m)},
            {"orientation_entropy", s.orientation_entropy},
            {"orientation_order", s.orientation_order},
            {"blocks", s.block_areas_m2.size()},
            {"median_block_area_m2", median(s.block_areas_m2)}};
}

} // namespace

nlohmann::json compare_networks(const GeometricGraph& a, const GeometricGraph& b) {
    const StreetStatistics sa = street_statistics(a);
    const StreetStatistics sb = street_statistics(b);
    const NetworkDistances d = network_distances(sa, sb);
    return {{"distances",
             {{"degree", d.degree},
              {"edge_length", d.edge_length},
              {"orientation", d.orientation},
              {"block_area", d.block_area},
              {"mean", d.mean()},
              {"junction_angle", d.junction_angle}}},
            {"a", summary(sa)},
            {"b", summary(sb)}};
}

nlohmann::json derive_report_json(const GeometricGraph& derived, const DeriveReport& report) {
    return {{"vertices", derived.vertex_count()},
            {"edges", derived.edge_count()},
            {"steps", report.steps},
            {"stopped_by_budget", report.stopped_by_budget},
            {"converged", report.converged},
            {"rewrites", report.totals.rewrites},
            {"embedding_edges", report.totals.embedding_edges},
            {"missed_embeddings", report.totals.missed_embeddings},
            {"refused", report.totals.refused},
            {"merged_vertices", report.totals.merged_vertices},
            {"nothing_to_rewrite", report.nothing_to_rewrite}};
}

nlohmann::json hierarchy_report_json(const HierarchyReport& report) {
    return {{"main_roads", report.main_roads},
            {"routes", report.routes},
            {"raised_streets", report.raised_streets},
            {"connectors", report.connectors},
            {"connector_streets", report.connector_streets},
            {"intersections", report.intersections},
            {"extensions", report.extensions}};
}

nlohmann::json replacement_report_json(const ReplaceReport& report) {
    return {{"replaced", report.replaced},
            {"removed_vertices", report.removed_vertices},
            {"added_vertices", report.added_vertices},
            {"joined_streets", report.joined_streets},
            {"intersections", report.intersections}};
}

} // namespace ggg
