// ggg: the command-line face of the library, for batch work without Blender.
// Exit codes: 0 success, 1 bad input (a file that cannot be read as a graph), 2 bad usage.
#include <sys/resource.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <string_view>
#include <type_traits>
#include <string>

#include <CLI/CLI.hpp>

#include "analyze_command.hpp"
#include "cli_common.hpp"
#include "learn_command.hpp"
#include "ggg/error.hpp"
#include "ggg/io/graph_info.hpp"
#include "ggg/files.hpp"
#include "ggg/io/grammar_file.hpp"
#include "ggg/io/geojson.hpp"
#include "ggg/measures/network_comparison.hpp"
#include "ggg/synthesis/growth.hpp"
#include "ggg/io/read_graph.hpp"
#include "ggg/io/reports.hpp"
#include "ggg/grammar/rewriting.hpp"

namespace {

using ggg::cli::ImportFlags;
using ggg::cli::count_from;
using ggg::cli::finite_number;
using ggg::cli::non_negative;
using ggg::cli::peak_memory_mb;
using ggg::cli::terminal_progress;

// Appends `extra` (e.g. an axiom) to `base`; positions are taken as they are, in base's frame.
void append_graph(ggg::GeometricGraph& base, const ggg::GeometricGraph& extra) {
    const auto offset = static_cast<ggg::VertexId>(base.vertex_count());
    for (std::size_t v = 0; v < extra.vertex_count(); ++v) {
        base.add_vertex(extra.positions[v], extra.vertex_osm_ids[v]);
        base.symbols.back() = extra.symbols[v];
        base.frames.back() = extra.frames[v];
        ggg::copy_more_rewrites(extra, static_cast<ggg::VertexId>(v), base, static_cast<ggg::VertexId>(offset + static_cast<ggg::VertexId>(v)));
    }
    for (std::size_t e = 0; e < extra.edge_count(); ++e) {
        const auto id = static_cast<ggg::EdgeId>(e);
        std::vector<ggg::Vec2> line(extra.geometry_begin(id), extra.geometry_begin(id) + extra.geometry_size(id));
        base.add_edge(extra.edges[e][0] + offset, extra.edges[e][1] + offset, extra.edge_attributes(id), line);
    }
}


} // namespace

int main(int argc, char** argv) {
    CLI::App app{"ggg: geometric graph grammars of road networks"};
    app.require_subcommand(1);
    app.set_version_flag("--version", std::string("ggg 0.1.0"));

    std::string input;
    ImportFlags import_flags;
    bool stats = false;
    auto* info = app.add_subcommand("info", "Print a JSON summary of a road graph (OSM, GeoJSON or .ggraph)");
    info->add_option("INPUT", input, "Input file")->required();
    import_flags.add_to(*info);
    info->add_flag("--stats", stats, "Also report read time (seconds) and peak memory (peak_memory_mb)");

    std::string output;
    auto* exp = app.add_subcommand("export", "Write a road graph as GeoJSON or .ggraph");
    exp->add_option("INPUT", input, "Input file")->required();
    exp->add_option("-o,--output", output, "Output file: .geojson or .ggraph")->required();
    import_flags.add_to(*exp);

    std::string grammar_path;
    ggg::DeriveOptions derive_options;
    double tolerance_m = -1;
    std::string base_path;
    auto* derive = app.add_subcommand("derive", "Derive a graph from a grammar's axiom (or grow a base graph) by parallel rewriting");
    derive->add_option("GRAMMAR", grammar_path, "Grammar file (.json)")->required();
    derive->add_option("--steps", derive_options.max_steps, "Derivation steps")->check(count_from<int>(0))->capture_default_str();
    derive->add_option("--max-vertices", derive_options.max_vertices, "Vertex budget: a step that would pass it is not applied")
        ->check(count_from<std::size_t>(1))
        ->capture_default_str();
    auto* relative = derive->add_option("--tolerance", derive_options.tolerance,
                                        "Embedding and merge tolerance as a fraction of the rewritten vertex's scale")
                         ->check(non_negative)
                         ->capture_default_str();
    derive->add_option("--tolerance-m", tolerance_m, "Embedding and merge tolerance in metres (instead of --tolerance)")
        ->check(non_negative)
        ->excludes(relative);
    derive->add_flag("--strict", derive_options.strict, "Apply a rule only where every embedding point finds a partner");
    derive->add_option("--base", base_path, "Grow this graph (OSM, GeoJSON or .ggraph) with the axiom's vertices added to it");
    derive->add_option("-o,--output", output, "Output file: .geojson or .ggraph (keeps symbols and frames)")->required();
    import_flags.add_to(*derive);

    ggg::cli::AnalyzeCommand analyze;
    analyze.add_to(app);
    ggg::cli::LearnCommand learn;
    learn.add_to(app);
    ggg::cli::DecodeCommand decode;
    decode.add_to(app);
    std::string grow_grammar, grow_region_path, grow_base;
    ggg::GrowOptions grow_options;
    auto* grow = app.add_subcommand("grow", "Grow streets into a region with a grammar's rules, from the streets that reach it; prints JSON");
    grow->add_option("GRAMMAR", grow_grammar, "Grammar file (.json), e.g. one learned by ggg learn")->required();
    grow->add_option("--region", grow_region_path, "GeoJSON file with the region's Polygon (longitude, latitude)")->required();
    grow->add_option("--base", grow_base, "Road graph the region lies in (OSM, GeoJSON or .ggraph); its streets are kept and grown from");
    grow->add_option("-o,--output", output, "Output file: .geojson or .ggraph (the base with the grown streets)")->required();
    ggg::visit_grow_options(grow_options, [&](std::string_view, std::string_view flag, std::string_view help, auto& field) {
        using Field = std::remove_reference_t<decltype(field)>;
        if constexpr (std::is_same_v<Field, bool>) {
            grow->add_flag("!" + std::string(flag), field, std::string(help)); // (every bool flag turns its option off)
        } else if constexpr (std::is_floating_point_v<Field>) {
            grow->add_option(std::string(flag), field, std::string(help))->check(finite_number)->capture_default_str();
        } else {
            grow->add_option(std::string(flag), field, std::string(help))->check(count_from<Field>(0))->capture_default_str();
        }
    });
    import_flags.add_to(*grow);
    std::string compare_a, compare_b;
    auto* compare = app.add_subcommand("compare", "How alike two street networks are: distances of their degree, edge length, "
                                                  "orientation and block area distributions (0 = same); prints JSON");
    compare->add_option("A", compare_a, "First road graph (OSM, GeoJSON or .ggraph)")->required();
    compare->add_option("B", compare_b, "Second road graph")->required();
    import_flags.add_to(*compare);

    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::cerr << "error: " << e.what() << "\n" << "run 'ggg --help' for usage\n";
        return 2;
    }

    // A file size limit (ulimit -f) makes a write fail with an error, not kill the process.
    std::signal(SIGXFSZ, SIG_IGN);
    try {
        // Outputs are checked before any work, so a bad path costs nothing and replaces nothing.
        if (!output.empty()) {
            if (ggg::graph_file_type(output) != ggg::GraphFileType::geojson && ggg::graph_file_type(output) != ggg::GraphFileType::graph_file) {
                throw ggg::UsageError(output + ": unknown output type (use .geojson or .ggraph)");
            }
            ggg::check_output_path(output);
        }
        if (learn.chosen()) return learn.run();
        if (*grow) {
            try { // before the files are read; the message names the flag, not the Python keyword
                ggg::check_options(grow_options);
            } catch (const ggg::UsageError& e) {
                std::string message = e.what();
                ggg::visit_grow_options(grow_options, [&](std::string_view keyword, std::string_view flag, std::string_view, const auto&) {
                    if (message.rfind(std::string(keyword) + ":", 0) == 0) message = std::string(flag) + message.substr(keyword.size());
                });
                throw ggg::UsageError(message);
            }
            const ggg::Grammar grammar = ggg::read_grammar(grow_grammar);
            ggg::GeometricGraph base;
            if (!grow_base.empty()) {
                base = ggg::read_graph(grow_base, import_flags.options());
            } else {
                base.origin = grammar.origin.lat != 0 || grammar.origin.lon != 0 ? grammar.origin : ggg::geojson_region_centre(grow_region_path);
            }
            const std::vector<ggg::Vec2> region = ggg::read_geojson_region(grow_region_path, base.origin);
            ggg::GrowReport report;
            const auto start = std::chrono::steady_clock::now();
            const ggg::GeometricGraph grown = ggg::grow_region(base, grammar, region, grow_options, &report, terminal_progress());
            const std::chrono::duration<double> seconds = std::chrono::steady_clock::now() - start;
            ggg::write_graph(grown, output);
            nlohmann::json out = ggg::growth_report_json(report);
            out["vertices"] = grown.vertex_count();
            out["edges"] = grown.edge_count();
            out["seconds"] = seconds.count();
            std::cout << out.dump() << std::endl;
            return 0;
        }
        if (*compare) {
            const ggg::GeometricGraph a = ggg::read_graph(compare_a, import_flags.options());
            const ggg::GeometricGraph b = ggg::read_graph(compare_b, import_flags.options());
            std::cout << ggg::compare_networks(a, b).dump() << std::endl;
            return 0;
        }
        if (decode.chosen()) return decode.run();
        if (analyze.chosen()) return analyze.run();
        if (*derive) {
            const ggg::Grammar grammar = ggg::read_grammar(grammar_path);
            if (tolerance_m >= 0) {
                derive_options.tolerance = tolerance_m;
                derive_options.tolerance_relative = false;
            }
            ggg::GeometricGraph graph = grammar.axiom_graph();
            if (!base_path.empty()) {
                ggg::GeometricGraph base = ggg::read_graph(base_path, import_flags.options());
                append_graph(base, graph);
                graph = std::move(base);
            }
            const auto start = std::chrono::steady_clock::now();
            const ggg::DeriveReport report = ggg::derive(graph, grammar, derive_options, terminal_progress());
            const std::chrono::duration<double> seconds = std::chrono::steady_clock::now() - start;
            ggg::write_graph(graph, output);
            nlohmann::json summary = ggg::derive_report_json(graph, report);
            summary["seconds"] = seconds.count();
            std::cout << summary.dump() << std::endl;
            if (report.stopped_by_budget) {
                std::cerr << "note: stopped after " << report.steps << " steps: the next step would pass --max-vertices "
                          << derive_options.max_vertices << "\n";
            }
            return 0;
        }
        const ggg::ImportOptions options = import_flags.options();
        const auto start = std::chrono::steady_clock::now();
        ggg::GeometricGraph graph = ggg::read_graph(input, options, nullptr, terminal_progress());
        const std::chrono::duration<double> seconds = std::chrono::steady_clock::now() - start;
        if (*info) {
            nlohmann::json summary = ggg::graph_info(graph);
            if (stats) {
                summary["seconds"] = seconds.count();
                summary["peak_memory_mb"] = peak_memory_mb();
            }
            std::cout << summary.dump() << std::endl;
        } else if (*exp) {
            ggg::write_graph(graph, output);
            std::cout << nlohmann::json{{"output", output}, {"vertices", graph.vertex_count()}, {"edges", graph.edge_count()}}.dump()
                      << std::endl;
        }
        return 0;
    } catch (const ggg::UsageError& e) {
        std::cerr << "error: " << e.what() << "\n";
        return 2;
    } catch (const ggg::Cancelled& e) {
        std::cerr << "error: " << e.what() << "\n";
        return 1;
    } catch (const ggg::Error& e) {
        std::cerr << "error: " << e.what() << "\n";
        return 1;
    } catch (const std::bad_alloc&) {
        std::cerr << "error: out of memory\n";
        return 1;
    } catch (const std::exception& e) {
        std::cerr << "error: " << e.what() << "\n";
        return 1;
    }
}
