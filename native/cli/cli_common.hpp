#pragma once
// What the ggg subcommands share: import flags, number checks, terminal progress.
#include <sys/resource.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <string>

#include <CLI/CLI.hpp>

#include "ggg/osm_import.hpp"
#include "ggg/progress.hpp"

namespace ggg::cli {


// CLI11's own NonNegativeNumber prints its whole numeric range in the message.
inline const CLI::Validator non_negative(
    [](std::string& value) {
        try {
            std::size_t used = 0;
            const double x = std::stod(value, &used);
            if (used != value.size() || !(x >= 0) || !std::isfinite(x)) return std::string("must be a number >= 0");
        } catch (const std::exception&) {
            return std::string("must be a number >= 0");
        }
        return std::string();
    },
    "NUMBER >= 0");

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
            ->check(non_negative)
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
inline ggg::ProgressCallback terminal_progress() {
    if (!isatty(STDERR_FILENO)) return {};
    return [](double fraction, std::string_view message) {
        std::fprintf(stderr, "\r%3d%% %-40.*s", static_cast<int>(fraction * 100), static_cast<int>(message.size()), message.data());
        if (fraction >= 1.0) std::fputc('\n', stderr);
        return true;
    };
}

inline double peak_memory_mb() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return static_cast<double>(usage.ru_maxrss) / 1024.0;
}

} // namespace ggg::cli
