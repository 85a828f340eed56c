// Every real extract in ../shared/osm: the import is checked against counts this test makes
// itself from the raw file with libosmium, and the graph against its invariants.
#include <gtest/gtest.h>

#include <osmium/io/any_input.hpp>
#include <osmium/osm/node.hpp>
#include <osmium/osm/way.hpp>

#include <algorithm>
#include <filesystem>
#include <map>
#include <set>
#include <unordered_map>
#include <unordered_set>

#include "fixtures.hpp"
#include "ggg/osm/osm_import.hpp"
#include "ggg/osm/projection.hpp"
#include "ggg/osm/highway_filter.hpp"

using namespace ggg;

namespace {

struct RawCounts {
    std::size_t highway_ways = 0;
    std::size_t referenced = 0;
    std::size_t missing = 0;
    // Distinct undirected segments between distinct places, as pairs of places.
    std::set<std::pair<std::uint64_t, std::uint64_t>> segments;
    std::unordered_map<std::uint64_t, osmium::Location> places;
    std::unordered_set<std::uint64_t> way_ends;  // places where a way run starts or ends
    std::unordered_map<std::uint64_t, int> uses; // way visits per place
};

std::uint64_t place_key(const osmium::Location& l) {
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(l.x())) << 32) | static_cast<std::uint32_t>(l.y());
}

RawCounts count_raw(const std::string& path) {
    RawCounts c;
    std::unordered_map<std::int64_t, osmium::Location> nodes;
    std::vector<std::vector<std::int64_t>> ways;
    osmium::io::Reader reader(path, osmium::osm_entity_bits::node | osmium::osm_entity_bits::way);
    while (osmium::memory::Buffer buffer = reader.read()) {
        for (const auto& node : buffer.select<osmium::Node>()) nodes[node.id()] = node.location();
        for (const auto& way : buffer.select<osmium::Way>()) {
            const char* hw = way.tags()["highway"];
            if (!hw || !*hw) continue;
            ++c.highway_ways;
            std::vector<std::int64_t> refs;
            for (const auto& r : way.nodes()) refs.push_back(r.ref());
            ways.push_back(std::move(refs));
        }
    }
    reader.close();
    std::unordered_set<std::int64_t> referenced;
    for (const auto& w : ways) referenced.insert(w.begin(), w.end());
    c.referenced = referenced.size();
    for (auto id : referenced) c.missing += !nodes.count(id);
    for (const auto& w : ways) {
        std::vector<std::uint64_t> run;
        auto flush = [&] {
            if (run.size() >= 2) {
                c.way_ends.insert(run.front());
                c.way_ends.insert(run.back());
                for (std::size_t i = 0; i < run.size(); ++i) {
                    if (i == 0 || run[i] != run[i - 1]) ++c.uses[run[i]];
                    if (i > 0 && run[i] != run[i - 1]) c.segments.emplace(std::min(run[i], run[i - 1]), std::max(run[i], run[i - 1]));
                }
            }
            run.clear();
        };
        for (auto id : w) {
            const auto it = nodes.find(id);
            if (it == nodes.end() || !it->second.valid()) {
                flush();
                continue;
            }
            const auto key = place_key(it->second);
            c.places.emplace(key, it->second);
            run.push_back(key);
        }
        flush();
    }
    return c;
}

std::string test_name(const testing::TestParamInfo<std::string>& info) {
    std::string name = std::filesystem::path(info.param).filename().string();
    std::replace_if(name.begin(), name.end(), [](char ch) { return !std::isalnum(static_cast<unsigned char>(ch)); }, '_');
    return name;
}

class Corpus : public testing::TestWithParam<std::string> {};

} // namespace

TEST_P(Corpus, ImportMatchesRawCountsAndKeepsInvariants) {
    const std::string path = GetParam();
    const RawCounts raw = count_raw(path);

    ImportOptions options;
    options.highways = HighwayFilter::all();
    ImportReport report;
    const GeometricGraph g = import_osm(path, options, &report);
    EXPECT_EQ(report.highway_ways, raw.highway_ways);
    EXPECT_EQ(report.ways_kept, raw.highway_ways);
    EXPECT_EQ(report.referenced_nodes, raw.referenced);
    EXPECT_EQ(report.missing_nodes + report.invalid_locations, raw.missing);

    // The graph is simple and its edges join their vertices.
    EXPECT_EQ(check_simple(g), "");

    // Every segment is kept exactly once: lengths agree with the raw distinct segments.
    LocalProjection projection(g.origin);
    double raw_length = 0;
    for (const auto& [a, b] : raw.segments) {
        const auto& la = raw.places.at(a);
        const auto& lb = raw.places.at(b);
        raw_length += (projection.forward(lb.lon(), lb.lat()) - projection.forward(la.lon(), la.lat())).norm();
    }
    EXPECT_NEAR(g.total_length(), raw_length, 1e-7 * raw_length);

    // Keeping shape nodes: one edge per distinct segment, one vertex per place.
    options.topology.keep_shape_nodes = true;
    const GeometricGraph full = import_osm(path, options);
    EXPECT_EQ(full.edge_count(), raw.segments.size());
    std::set<std::uint64_t> segment_places;
    for (const auto& [a, b] : raw.segments) {
        segment_places.insert(a);
        segment_places.insert(b);
    }
    EXPECT_EQ(full.vertex_count(), segment_places.size());
    EXPECT_EQ(check_simple(full), "");
    // Merging chains changes no connectivity.
    EXPECT_EQ(ggg::test::component_count(g), ggg::test::component_count(full));

    // A vertex of degree 2 is a way end, a crossing, or a shape node promoted to keep the
    // graph simple (counted by the builder).
    std::unordered_map<std::int64_t, std::uint64_t> place_of_osm;
    {
        std::vector<std::size_t> degree(g.vertex_count(), 0);
        for (const auto& [u, v] : g.edges) {
            ++degree[static_cast<std::size_t>(u)];
            ++degree[static_cast<std::size_t>(v)];
        }
        std::size_t unexplained = 0;
        for (std::size_t v = 0; v < g.vertex_count(); ++v) {
            if (degree[v] != 2) continue;
            const Vec2 ll = projection.inverse(g.positions[v]);
            const osmium::Location loc(ll.x(), ll.y());
            const auto key = place_key(loc);
            const bool end = raw.way_ends.count(key) > 0;
            const auto uses = raw.uses.find(key);
            if (!end && (uses == raw.uses.end() || uses->second < 2)) ++unexplained;
        }
        EXPECT_LE(unexplained, report.topology.promoted_shape_nodes);
    }
    std::printf("[ corpus   ] %s: %zu highway ways, %zu nodes (%zu missing) -> V=%zu E=%zu, %.1f km, %zu promoted\n",
                std::filesystem::path(path).filename().c_str(), raw.highway_ways, raw.referenced, raw.missing, g.vertex_count(),
                g.edge_count(), g.total_length() / 1000, report.topology.promoted_shape_nodes);
}

TEST_P(Corpus, DrivableImportIsASubsetOfAll) {
    const std::string path = GetParam();
    ImportOptions all;
    all.highways = HighwayFilter::all();
    const GeometricGraph everything = import_osm(path, all);
    const GeometricGraph drivable = import_osm(path);
    EXPECT_EQ(check_simple(drivable), "");
    EXPECT_LE(drivable.total_length(), everything.total_length()); // equal in a roads-only extract
    for (HighwayClass c : drivable.edge_highway) EXPECT_TRUE(HighwayFilter::drivable().accepts(highway_name(c)));
}

INSTANTIATE_TEST_SUITE_P(SharedOsm, Corpus, testing::ValuesIn(ggg::test::corpus_files()), test_name);
GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(Corpus);

TEST(CorpusPresence, SharedExtractsAreHere) {
    GGG_REQUIRE_CORPUS();
    EXPECT_GE(ggg::test::corpus_files().size(), 19u);
}
