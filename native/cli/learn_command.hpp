#pragma once
// `ggg learn` (a road graph to a grammar) and `ggg decode` (a learned grammar back to streets).
#include <string>

#include <CLI/CLI.hpp>

#include "analyze_command.hpp"
#include "cli_common.hpp"
#include "ggg/encoding/grammar_encoder.hpp"

namespace ggg::cli {

class LearnCommand {
public:
    void add_to(CLI::App& app);
    bool chosen() const { return command_ && command_->parsed(); }
    // Writes the grammar (and the stats file), prints the stats on stdout.
    int run() const;

private:
    CLI::App* command_ = nullptr;
    std::string input_;
    std::string output_;
    std::string stats_path_;
    std::string seed_osm_nodes_;
    ImportFlags import_;
    AnalysisFlags analysis_;
    bool lossless_ = false;
    bool complete_ = LearnOptions{}.complete;
    int levels_ = 64;
    double max_shape_error_ = LearnOptions{}.max_shape_error;
    double max_vertex_error_m_ = LearnOptions{}.max_vertex_error_m;
};

class DecodeCommand {
public:
    void add_to(CLI::App& app);
    bool chosen() const { return command_ && command_->parsed(); }
    int run() const;

private:
    CLI::App* command_ = nullptr;
    std::string grammar_;
    std::string output_;
    int level_ = 0;
};

} // namespace ggg::cli
