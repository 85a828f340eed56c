// ggg: the command-line face of the library, for batch work without Blender.
// Exit codes: 0 success, 1 bad input (a file that cannot be read as a graph), 2 bad usage.
#include <sys/resource.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <iostream>
#include <string>

#include <CLI/CLI.hpp>

#include "ggg/error.hpp"
#include "ggg/graph_info.hpp"
#include "ggg/io/read_graph.hpp"

namespace {

struct ImportFlags {
    std::string highways = "drivable";
    bool keep_shape_nodes = false;
    double consolidate_m = 0.0;

    void add_to(CLI::App& command) {
        command.add_option("--highways", highways,
                           "Road classes to import: drivable, all, or a comma-separated list of highway values")
            ->capture_default_str();
        command.add_flag("--keep-shape-nodes", keep_shape_nodes, "Keep every OSM node as a vertex");
        command.add_option("--consolidate", consolidate_m,
                           "Merge intersections closer than this many metres (dual carriageways, roundabouts); 0 = off")
            ->check(CLI::NonNegativeNumber)
            ->capture_default_str();
    }

    ggg::ImportOptions options() const {
        ggg::ImportOptions o;
        o.highways = ggg::HighwayFilter::parse(highways);
        o.topology.keep_shape_nodes = keep_shape_nodes;
        o.topology.consolidate_m = consolidate_m;
        return o;
    }
};

// Progress on stderr only for a person watching a terminal.
ggg::ProgressCallback terminal_progress() {
    if (!isatty(STDERR_FILENO)) return {};
    return [](double fraction, std::string_view message) {
        std::fprintf(stderr, "\r%3d%% %-40.*s", static_cast<int>(fraction * 100), static_cast<int>(message.size()), message.data());
        if (fraction >= 1.0) std::fputc('\n', stderr);
        return true;
    };
}

double peak_memory_mb() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return static_cast<double>(usage.ru_maxrss) / 1024.0;
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

    try {
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
