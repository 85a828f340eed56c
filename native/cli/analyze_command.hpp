#pragma once
// `ggg analyze`: the graph analyzer (isogroup detection and selection) on one road graph.
#include <string>

#include <CLI/CLI.hpp>

#include "cli_common.hpp"

namespace ggg::cli {

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
    std::string grid_ = "12x10";
    double cut_ = 0.8;
    bool full_ = false;
    int max_order_ = 8;
    std::size_t min_count_ = 2;
    std::string seed_osm_nodes_;
    double tolerance_ = 0.2;
    std::string scale_ = "similarity";
    double min_aspect_ = 0.0;
    std::size_t min_leaves_ = 0;
    double min_irregularity_ = 0.0;
    std::size_t top_ = 0;
    std::size_t recount_ = 0;
    bool occurrences_ = false;
    bool stats_ = false;
};

} // namespace ggg::cli
