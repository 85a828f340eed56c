#pragma once
// `ggg analyze`: the graph analyzer (isogroup detection and selection) on one road graph.
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "cli_common.hpp"
#include "ggg/analysis/analyzer.hpp"

namespace ggg::cli {

// The analysis options that `analyze` and `learn` share.
struct AnalysisFlags {
    std::string grid = "12x10";
    double cut = 0.8;
    bool full = false;
    int max_order = 8;
    std::size_t min_count = 2;
    double tolerance = AnalyzeOptions{}.tolerance;
    std::string scale = "similarity";
    double min_aspect = 0.0;
    std::size_t min_leaves = 0;
    double min_irregularity = 0.0;
    std::size_t recount = 0;
    double max_seconds = DetectionOptions{}.max_seconds;
    double max_memory_mb = DetectionOptions{}.max_memory_mb;

    void add_to(CLI::App& command);
    // Throws UsageError for a bad grid, scale or option value.
    AnalyzeOptions options() const;
};

// The vertices of the OSM nodes listed in `osm_ids` ("123,456,..."); UsageError for an id
// that is not a vertex of `graph`.
std::vector<VertexId> seed_vertices(const GeometricGraph& graph, const std::string& osm_ids);

class AnalyzeCommand {
public:
    void add_to(CLI::App& app);
    bool chosen() const { return command_ && command_->parsed(); }
    // Prints the JSON result on stdout; throws ggg errors for bad input or usage.
    int run() const;

private:
    CLI::App* command_ = nullptr;
    std::string input_;
    ImportFlags import_;
    AnalysisFlags analysis_;
    std::string seed_osm_nodes_;
    std::size_t top_ = 0;
    bool occurrences_ = false;
    bool seed_within_tolerance_ = false;
    bool stats_ = false;
};

} // namespace ggg::cli
