#include "learn_command.hpp"

#include <chrono>
#include <cstdio>
#include <iostream>

#include <nlohmann/json.hpp>

#include "ggg/encoding/decoding.hpp"
#include "ggg/encoding/grammar_encoder.hpp"
#include "ggg/error.hpp"
#include "ggg/files.hpp"
#include "ggg/io/grammar_file.hpp"
#include "ggg/io/read_graph.hpp"
#include "ggg/io/reports.hpp"
#include "../src/io/json_util.hpp"

namespace ggg::cli {

namespace {

// On a terminal, the usual progress line; elsewhere (a log, CI) one line per stage.
ProgressCallback learning_progress() {
    if (ProgressCallback terminal = terminal_progress()) return terminal;
    return [last = std::string()](double, std::string_view message) mutable {
        const std::string stage(message.substr(0, message.find(':')));
        if (stage != last) {
            last = stage;
            std::fprintf(stderr, "%.*s\n", static_cast<int>(message.size()), message.data());
        }
        return true;
    };
}

} // namespace

void LearnCommand::add_to(CLI::App& app) {
    command_ = app.add_subcommand("learn", "Learn a grammar of a road graph (rules and axiom), check that it decodes; prints JSON stats");
    auto& c = *command_;
    c.add_option("INPUT", input_, "Input road graph (OSM, GeoJSON or .ggraph)")->required();
    c.add_option("-o,--output", output_, "Grammar file to write (.json)")->required();
    c.add_flag("--complete", complete_,
               "Encode level after level until the axiom is a single vertex (paper Fig. 13): smaller repeating patterns "
               "keep the encoding going where nothing pays, and what never repeats becomes a rule used once");
    c.add_flag("--lossless", lossless_, "Store per-vertex residuals: decoding gives back exactly the input's edges and positions");
    c.add_option("--levels", levels_, "Most passes of the encoder, each adding at most one level of hierarchy (0 = until nothing repeats)")->check(whole_number(0, 100000))->capture_default_str();
    c.add_option("--stats", stats_path_, "Also write the stats to this JSON file");
    c.add_option("--seed-osm-nodes", seed_osm_nodes_,
                 "Comma-separated OSM node ids of a piece to learn first: its pattern becomes the first rule, with all its copies");
    c.add_option("--max-shape-error", max_shape_error_,
                 "Leave out copies farther than this from the pattern's shape (RMS, relative to its size; 0 = keep all)")
        ->check(number_in(0.0, 10.0))
        ->capture_default_str();
    c.add_option("--max-vertex-error", max_vertex_error_m_,
                 "Leave out copies with a street vertex farther than this many metres from the rule's shape "
                 "(bounds the paper-mode error of every vertex; 0 = no bound)")
        ->check(number_in(0.0, 1e6))
        ->capture_default_str();
    import_.add_to(c);
    analysis_.max_order = LearnOptions::default_analysis().detection.max_order;
    analysis_.add_to(c);
}

int LearnCommand::run() const {
    LearnOptions options;
    options.analysis = analysis_.options();
    options.lossless = lossless_;
    options.complete = complete_;
    options.max_levels = levels_;
    options.max_shape_error = max_shape_error_;
    options.max_vertex_error_m = max_vertex_error_m_;
    check_options(options);
    check_output_paths({output_, stats_path_});
    const auto t0 = std::chrono::steady_clock::now();
    const GeometricGraph graph = read_graph(input_, import_.options(), nullptr, terminal_progress());
    const std::chrono::duration<double> import_seconds = std::chrono::steady_clock::now() - t0;
    if (!seed_osm_nodes_.empty()) options.seed = seed_vertices(graph, seed_osm_nodes_);
    const LearnResult result = learn_grammar(graph, options, learning_progress());
    write_grammar(result.grammar, output_);
    const std::chrono::duration<double> total = std::chrono::steady_clock::now() - t0;

    nlohmann::json stats = learn_report(graph, result);
    stats["seconds"]["import"] = import_seconds.count();
    stats["seconds"]["total"] = total.count();
    stats["peak_memory_mb"] = peak_memory_mb();
    if (!stats_path_.empty()) {
        io_detail::write_file(stats_path_, [&](std::ostream& out) { out << stats.dump(1) << '\n'; });
    }
    std::cout << stats.dump() << std::endl;
    if (result.stopped_by_budget) {
        std::cerr << "note: stopped at the time or memory budget (--max-seconds, --max-memory); the grammar holds the levels found so far\n";
    }
    return 0;
}

void DecodeCommand::add_to(CLI::App& app) {
    command_ = app.add_subcommand("decode", "Decode a learned grammar back to a road graph (or to one level of its hierarchy)");
    auto& c = *command_;
    c.add_option("GRAMMAR", grammar_, "Learned grammar file (.json)")->required();
    c.add_option("-o,--output", output_, "Output file: .geojson or .ggraph (keeps symbols and frames)")->required();
    c.add_option("--level", level_, "Write the graph encoded to this level instead (0 = the streets)")->check(count_from<int>(0));
}

int DecodeCommand::run() const {
    if (graph_file_type(output_) != GraphFileType::geojson && graph_file_type(output_) != GraphFileType::graph_file) {
        throw UsageError(output_ + ": unknown output type (use .geojson or .ggraph)");
    }
    check_output_path(output_);
    const Grammar grammar = read_grammar(grammar_);
    const auto t0 = std::chrono::steady_clock::now();
    const GeometricGraph graph = level_ == 0 ? decode_grammar(grammar, nullptr, terminal_progress())
                                             : encoded_graph(grammar, level_, terminal_progress());
    const std::chrono::duration<double> seconds = std::chrono::steady_clock::now() - t0;
    write_graph(graph, output_);
    std::cout << nlohmann::json{{"output", output_},
                                {"vertices", graph.vertex_count()},
                                {"edges", graph.edge_count()},
                                {"level", level_},
                                {"levels", grammar.encoding.levels},
                                {"mode", grammar.encoding.mode},
                                {"seconds", seconds.count()}}
                     .dump()
              << std::endl;
    return 0;
}

} // namespace ggg::cli
