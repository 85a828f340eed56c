// Street-network statistics and distances: exact values on small graphs, invariances, and
// the difference between grid and irregular cities on real extracts.
#include <gtest/gtest.h>

#include <cmath>

#include "analysis_fixtures.hpp"
#include "fixtures.hpp"
#include "ggg/io/read_graph.hpp"
#include "ggg/measures/network_comparison.hpp"
#include "ggg/io/reports.hpp"

namespace ggg {
namespace {

using test::GridOptions;

TEST(NetworkComparison, StatisticsOfAGrid) {
    GridOptions o;
    o.n = 5; // 4 x 4 blocks of 100 m
    const StreetStatistics s = street_statistics(test::make_grid(o));
    EXPECT_EQ(s.vertices, 25u);
    EXPECT_EQ(s.edges, 40u);
    EXPECT_DOUBLE_EQ(s.degree_histogram[2], 4.0 / 25);  // corners
    EXPECT_DOUBLE_EQ(s.degree_histogram[3], 12.0 / 25); // sides
    EXPECT_DOUBLE_EQ(s.degree_histogram[4], 9.0 / 25);  // inside
    ASSERT_EQ(s.block_areas_m2.size(), 16u);
    for (double a : s.block_areas_m2) EXPECT_NEAR(a, 10'000.0, 1e-6);
    // Four directions (0, 90, 180, 270 degrees), a quarter of the length each: a perfect grid.
    EXPECT_NEAR(s.orientation_entropy, std::log(4.0), 1e-12);
    EXPECT_NEAR(s.orientation_order, 1.0, 1e-12);
    for (double l : s.edge_lengths_m) EXPECT_NEAR(l, 100.0, 1e-9);
}

TEST(NetworkComparison, DistancesAreZeroForTheSameNetworkAndIgnoreRotation) {
    GridOptions o;
    o.n = 8;
    o.jitter = 0.05;
    const GeometricGraph a = test::make_grid(o);
    const NetworkDistances same = network_distances(street_statistics(a), street_statistics(a));
    EXPECT_EQ(same.mean(), 0.0);
    o.angle_rad = 30.0 * M_PI / 180.0; // the same grid turned by three orientation bins
    const StreetStatistics sa = street_statistics(a);
    const NetworkDistances turned = network_distances(sa, street_statistics(test::make_grid(o)));
    EXPECT_EQ(turned.degree, 0.0);
    // Rotating moves lengths and areas by rounding only, which can swap two neighbours in
    // the sorted samples: one step of the cumulative distribution at most.
    EXPECT_LE(turned.edge_length, 1.0 / static_cast<double>(sa.edges) + 1e-12);
    EXPECT_LE(turned.block_area, 1.0 / static_cast<double>(sa.block_areas_m2.size()) + 1e-12);
    EXPECT_LT(turned.orientation, 0.02);
    // Other block sizes are another street pattern.
    o.spacing = 200.0;
    const NetworkDistances larger = network_distances(street_statistics(a), street_statistics(test::make_grid(o)));
    EXPECT_EQ(larger.edge_length, 1.0);
    EXPECT_EQ(larger.block_area, 1.0);
}

TEST(NetworkComparison, GridCitiesAreCloserToEachOtherThanToAnIrregularOne) {
    GGG_REQUIRE_CORPUS();
    const std::string dir = test::shared_osm_dir();
    const GeometricGraph barcelona = read_graph(dir + "/barcelona_eixample.osm");
    const GeometricGraph columbus = read_graph(dir + "/columbus_oh.osm.pbf");
    const GeometricGraph paris = read_graph(dir + "/paris_marais.osm.pbf");
    const StreetStatistics b = street_statistics(barcelona), c = street_statistics(columbus), p = street_statistics(paris);
    EXPECT_GT(b.orientation_order, 0.5);
    EXPECT_LT(p.orientation_order, 0.3);
    EXPECT_LT(network_distances(b, c).orientation, network_distances(b, p).orientation);
    const nlohmann::json j = compare_networks(barcelona, paris);
    for (const char* key : {"degree", "edge_length", "orientation", "block_area", "mean", "junction_angle"}) {
        const double d = j["distances"][key].get<double>();
        EXPECT_GT(d, 0.0) << key;
        EXPECT_LE(d, 1.0) << key;
    }
    EXPECT_EQ(j["a"]["vertices"].get<std::size_t>(), barcelona.vertex_count());
    // The Eixample meets at right angles and its streets run straight through; the Marais less so.
    EXPECT_GT(b.right_angle_share, p.right_angle_share + 0.1);
    EXPECT_GT(b.through_share, p.through_share);
    EXPECT_GT(p.circuity, 1.0);
    EXPECT_GT(b.circuity, 1.0);
    EXPECT_GT(network_distances(b, p).junction_angle, network_distances(b, c).junction_angle);
}

TEST(NetworkComparison, StructureOfAGridAndAStar) {
    GridOptions o;
    o.n = 5; // 4 x 4 blocks: 4 corners, 12 T-junctions on the sides, 9 crossings inside
    const GeometricGraph grid = test::make_grid(o);
    const StreetStatistics s = street_statistics(grid);
    EXPECT_EQ(s.junctions, 21u);
    ASSERT_EQ(s.junction_angles_deg.size(), 12u * 3 + 9u * 4);
    EXPECT_NEAR(s.junction_angles_deg.front(), 90.0, 1e-9);
    EXPECT_NEAR(s.junction_angles_deg.back(), 180.0, 1e-9); // the straight side of each T
    EXPECT_DOUBLE_EQ(s.right_angle_share, 60.0 / 72.0);
    EXPECT_DOUBLE_EQ(s.through_share, 1.0);
    // Manhattan over straight distance: between 1 (along a street) and sqrt(2) (diagonals).
    EXPECT_GT(s.circuity, 1.05);
    EXPECT_LT(s.circuity, std::sqrt(2.0));
    const nlohmann::json summary = compare_networks(grid, grid)["a"];
    EXPECT_DOUBLE_EQ(summary["dead_end_share"].get<double>(), 0.0);
    EXPECT_DOUBLE_EQ(summary["degree2_share"].get<double>(), 4.0 / 25.0);
    EXPECT_DOUBLE_EQ(summary["star_share"].get<double>(), 0.0);
    EXPECT_DOUBLE_EQ(summary["crossing_share"].get<double>(), 9.0 / 21.0);

    // Six streets from one point, 60 degrees apart, then a seventh bent 20 degrees off a line:
    // a star, and each street is straight through with the one opposite.
    GeometricGraph star;
    star.add_vertex({0, 0});
    for (int i = 0; i < 6; ++i) {
        const double a = i * M_PI / 3.0;
        star.add_vertex({100 * std::cos(a), 100 * std::sin(a)});
        star.add_edge(0, static_cast<VertexId>(i + 1), EdgeAttributes{});
    }
    const StreetStatistics t = street_statistics(star);
    EXPECT_EQ(t.junctions, 1u);
    EXPECT_DOUBLE_EQ(t.through_share, 1.0);
    EXPECT_DOUBLE_EQ(t.right_angle_share, 0.0);
    EXPECT_NEAR(compare_networks(star, star)["a"]["star_share"].get<double>(), 1.0 / 7.0, 1e-12);
    EXPECT_DOUBLE_EQ(compare_networks(star, star)["a"]["crossing_share"].get<double>(), 0.0); // a star is no crossing
    EXPECT_NEAR(compare_networks(star, star)["a"]["dead_end_share"].get<double>(), 6.0 / 7.0, 1e-12);
    // Spokes meet only at the centre: every path from spoke to spoke goes through it.
    EXPECT_GT(t.circuity, 1.1);
    // A single vertex has no pairs: no circuity.
    GeometricGraph lone;
    lone.add_vertex({0, 0});
    EXPECT_TRUE(std::isnan(street_statistics(lone).circuity));
    EXPECT_TRUE(compare_networks(lone, lone)["a"]["circuity"].is_null());
}

TEST(NetworkComparison, CommandLine) {
    const std::string sample = std::string(GGG_SAMPLES_DIR) + "/sample_city.osm";
    const test::CliResult r = test::run_cli("compare " + sample + " " + sample + " --highways all");
    ASSERT_EQ(r.code, 0) << r.err;
    const nlohmann::json j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["distances"]["mean"].get<double>(), 0.0);
    EXPECT_EQ(test::run_cli("compare " + sample + " /nonexistent.osm").code, 1);
    EXPECT_EQ(test::run_cli("compare " + sample).code, 2);
}

} // namespace
} // namespace ggg
