#pragma once
// Shared helpers of the tests: inline OSM fixtures written to temporary files, the corpus
// of real extracts in ../shared/osm (skipped with a message where it is absent), and
// invariant checkers.
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "ggg/graph/geometric_graph.hpp"

namespace ggg::test {

// Writes `content` to a fresh temporary file whose name ends in `suffix` (".opl", ".osm", ...).
std::string temp_file(const std::string& content, const std::string& suffix);
std::string temp_path(const std::string& suffix);

// The folder of real extracts, or empty when ../shared is not beside the project.
std::string shared_osm_dir();
std::vector<std::string> corpus_files();

// Number of connected components (isolated vertices count as one each).
std::size_t component_count(const GeometricGraph& g);

// Pairs of edges, at least one of them from `from_edge` on, whose polylines cross away from
// their ends: a street that passes over another without an intersection.
std::size_t polyline_crossings(const GeometricGraph& g, std::size_t from_edge = 0);

// Vertices that share a place (the same `quantum` cell) with another vertex.
std::size_t shared_places(const GeometricGraph& g, double quantum = 0.01);

// Column `name` of `section` ("rules", "axiom" or "encoding") of a packed grammar document
// (version 6 places its columns instead of naming them), made present where it was left out;
// `settings` reaches the encoding's settings ("mode", "tolerance_m", ...) the same way.
nlohmann::json& packed_column(nlohmann::json& doc, const std::string& section, const std::string& name);

// Result of running the CLI: exit code, stdout, stderr.
struct CliResult {
    int code;
    std::string out;
    std::string err;
};
CliResult run_cli(const std::string& arguments);

} // namespace ggg::test

#define GGG_REQUIRE_CORPUS()                                                                          \
    do {                                                                                              \
        if (ggg::test::shared_osm_dir().empty())                                                      \
            GTEST_SKIP() << "../shared/osm not found: the real OSM extracts are not on this machine"; \
    } while (0)
