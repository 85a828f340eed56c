#pragma once
// What the ggg subcommands share: import flags, number checks, terminal progress.
#include <sys/resource.h>
#include <unistd.h>

#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>
#include <cstdio>
#include <string>

#include <CLI/CLI.hpp>

#include "ggg/osm/osm_import.hpp"
#include "ggg/progress.hpp"
#include "ggg/osm/highway_filter.hpp"

namespace ggg::cli {


// Every number a flag takes is checked by its meaning before the run: NaN and infinities are
// refused (CLI11's Range lets NaN through, since every comparison with it is false), counts
// are whole and not negative (a size_t would wrap "-3" to 18446744073709551613), and a value
// that does not fit its type is refused rather than clamped. CLI11 names the flag in the message.
inline CLI::Validator number_in(double lo, double hi) {
    auto text = [](double x) {
        std::string s = std::to_string(x);
        s.erase(s.find_last_not_of('0') + 1);
        if (!s.empty() && s.back() == '.') s.pop_back();
        return s;
    };
    const bool any = lo == -std::numeric_limits<double>::max() && hi == std::numeric_limits<double>::max();
    const std::string range = any ? "a finite number" : std::isinf(hi) ? "a number >= " + text(lo) : "a number from " + text(lo) + " to " + text(hi);
    return CLI::Validator(
        [=](std::string& value) {
            try {
                std::size_t used = 0;
                const double x = std::stod(value, &used);
                if (used == value.size() && std::isfinite(x) && x >= lo && x <= hi) return std::string();
            } catch (const std::exception&) {
            }
            return "must be " + range + ", got '" + value + "'";
        },
        any ? "NUMBER" : std::isinf(hi) ? "NUMBER >= " + text(lo) : "NUMBER in [" + text(lo) + ", " + text(hi) + "]");
}

// Any finite number (negative ones included, for options where < 0 means "automatic").
inline const CLI::Validator finite_number = number_in(-std::numeric_limits<double>::max(), std::numeric_limits<double>::max());

inline const CLI::Validator non_negative = number_in(0.0, std::numeric_limits<double>::infinity());

// A whole number from lo to hi, digits only.
inline CLI::Validator whole_number(std::uint64_t lo, std::uint64_t hi) {
    return CLI::Validator(
        [=](std::string& value) {
            std::uint64_t x = 0;
            const char* end = value.data() + value.size();
            const auto [ptr, error] = std::from_chars(value.data(), end, x);
            if (!value.empty() && ptr == end && error == std::errc() && x >= lo && x <= hi) return std::string();
            return "must be a whole number from " + std::to_string(lo) + " to " + std::to_string(hi) + ", got '" + value + "'";
        },
        "INTEGER in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
}

template <typename T>
inline CLI::Validator count_from(std::uint64_t lo) {
    return whole_number(lo, static_cast<std::uint64_t>(std::numeric_limits<T>::max()));
}

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
