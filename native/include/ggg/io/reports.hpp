#pragma once
// The reports of long operations as JSON: one definition of each report's fields, which the
// CLI prints and the Python module returns as a dict (docs/cli.md lists them).
#include <nlohmann/json.hpp>

#include "ggg/analysis/analyzer.hpp"
#include "ggg/encoding/grammar_encoder.hpp"
#include "ggg/grammar/grammar.hpp"
#include "ggg/grammar/rewriting.hpp"
#include "ggg/graph/geometric_graph.hpp"
#include "ggg/measures/network_comparison.hpp"
#include "ggg/synthesis/growth.hpp"
#include "ggg/synthesis/replacement.hpp"
#include "ggg/synthesis/street_hierarchy.hpp"

namespace ggg {

// What an analysis report holds besides its isogroups' figures.
struct AnalysisReportOptions {
    std::size_t top = 0;               // only the best this many isogroups (0 = all)
    bool occurrence_osm_nodes = false; // each isogroup's occurrences as the OSM node ids of their vertices
    bool orders = false;               // the per-order counts of the detection
};

// `ggg analyze`'s report (ggg.Analysis.report): graph {vertices, edges}, detected,
// stopped_by_budget, and the isogroups, best first, each with order, edge_count,
// occurrences, non_overlapping, score, gain, selection_exact, parent, size_m, recounted
// (and occurrence_osm_nodes); with `orders`, detection_orders_json.
nlohmann::json analysis_report_json(const GeometricGraph& graph, const Analysis& analysis,
                                    const AnalysisReportOptions& options = {});

// The detection's counts per order: order, parents, candidates, children, groups,
// expanded_next, occurrences.
nlohmann::json detection_orders_json(const std::vector<OrderReport>& orders);

// Every field of GrowReport, flat: "placements", "rejected_crossing", "traced_streets", ...
nlohmann::json growth_report_json(const GrowReport& report);

// A derivation's figures (`ggg derive`, ggg.derive): the graph's vertices and edges after it,
// steps, stopped_by_budget, converged, rewrites, embedding_edges, missed_embeddings, refused,
// merged_vertices, nothing_to_rewrite.
nlohmann::json derive_report_json(const GeometricGraph& derived, const DeriveReport& report);

// ggg.continue_hierarchy's: main_roads, routes, raised_streets, connectors, connector_streets,
// intersections.
nlohmann::json hierarchy_report_json(const HierarchyReport& report);

// ggg.replace_isogroup's: replaced, removed_vertices, added_vertices, joined_streets, intersections.
nlohmann::json replacement_report_json(const ReplaceReport& report);

// The figures of a learning as `ggg learn` prints them (docs/learning.md): input, mode,
// rules, instances, levels, axiom, seconds (analysis, encoding), bytes, roundtrip, per_level.
nlohmann::json learn_report(const GeometricGraph& input, const LearnResult& result);

// The sizes `ggg learn` compares (docs/learning.md#size), in the same kind of encoding: a
// graph as packed columns of what a grammar keeps (positions in quanta and delta-coded,
// edges, road classes), and a grammar file as write_grammar writes it; each as JSON text
// (with its newline) or as CBOR.
std::size_t graph_structure_bytes(const GeometricGraph& graph, double quantum_m = LearnOptions{}.quantum_m, bool cbor = false);
std::size_t grammar_bytes(const Grammar& grammar, bool cbor = false);

// `ggg compare`'s output: {"distances": {degree, edge_length, orientation, block_area, mean,
// junction_angle}, "a": summary, "b": summary} with vertices, edges, mean degree, median edge
// length, orientation entropy and order, blocks and median block area, and the structure:
// junctions, dead_end_share, degree2_share, star_share (of the vertices), crossing_share (of
// the junctions: four streets), right_angle_share (of the junction angles), through_share (of
// the junctions) and circuity of each.
nlohmann::json compare_networks(const GeometricGraph& a, const GeometricGraph& b);

} // namespace ggg
