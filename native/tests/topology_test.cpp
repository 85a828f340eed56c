// The topology rules on small inline OSM fixtures (OPL), one rule per case.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>

#include "fixtures.hpp"
#include "ggg/error.hpp"
#include "ggg/osm/osm_import.hpp"
#include "ggg/osm/projection.hpp"
#include "ggg/osm/highway_filter.hpp"

using namespace ggg;
using ggg::test::temp_file;

namespace {

// An OPL fixture built from node positions in metres around (46 N, 8 E).
class Fixture {
public:
    Fixture& node(int id, double x_m, double y_m) {
        static const LocalProjection projection({46.0, 8.0});
        const Vec2 lonlat = projection.inverse(Vec2{x_m, y_m});
        char line[128];
        std::snprintf(line, sizeof line, "n%d v1 x%.7f y%.7f\n", id, lonlat.x(), lonlat.y());
        nodes_ << line;
        return *this;
    }
    Fixture& way(int id, const std::string& tags, std::initializer_list<int> refs) {
        return way(id, tags, std::vector<int>(refs));
    }
    Fixture& way(int id, const std::string& tags, const std::vector<int>& refs) {
        ways_ << "w" << id << " v1 T" << tags << " N";
        bool first = true;
        for (int r : refs) {
            ways_ << (first ? "" : ",") << "n" << r;
            first = false;
        }
        ways_ << "\n";
        return *this;
    }
    std::string opl(bool ways_first = false) const { return ways_first ? ways_.str() + nodes_.str() : nodes_.str() + ways_.str(); }

    GeometricGraph import(TopologyOptions topology = {}, ImportReport* report = nullptr, bool ways_first = false) const {
        ImportOptions options;
        options.highways = HighwayFilter::all();
        options.topology = topology;
        return import_osm(temp_file(opl(ways_first), ".opl"), options, report);
    }

private:
    std::ostringstream nodes_;
    std::ostringstream ways_;
};

std::map<std::int64_t, std::size_t> degrees_by_osm_id(const GeometricGraph& g) {
    std::map<std::int64_t, std::size_t> d;
    for (std::size_t v = 0; v < g.vertex_count(); ++v) d[g.vertex_osm_ids[v]] = 0;
    for (const auto& [u, v] : g.edges) {
        ++d[g.vertex_osm_ids[static_cast<std::size_t>(u)]];
        ++d[g.vertex_osm_ids[static_cast<std::size_t>(v)]];
    }
    return d;
}

} // namespace

TEST(Topology, DegreeTwoChainsBecomeOneEdgeWithItsPolyline) {
    Fixture f;
    f.node(1, 0, 0).node(2, 50, 5).node(3, 100, 0).node(4, 200, 0).node(5, 100, 80);
    f.way(10, "highway=residential,name=Long", {1, 2, 3, 4}).way(11, "highway=residential", {3, 5});
    const GeometricGraph g = f.import();
    EXPECT_EQ(check_simple(g), "");
    EXPECT_EQ(g.vertex_count(), 4u); // node 2 is shape only
    EXPECT_EQ(g.edge_count(), 3u);
    const auto degrees = degrees_by_osm_id(g);
    EXPECT_EQ(degrees.count(2), 0u);
    EXPECT_EQ(degrees.at(3), 3u);
    std::size_t three_point_edges = 0;
    for (std::size_t e = 0; e < g.edge_count(); ++e) three_point_edges += g.geometry_size(static_cast<EdgeId>(e)) == 3;
    EXPECT_EQ(three_point_edges, 1u);
    EXPECT_EQ(g.edge_name(0), "Long");
}

TEST(Topology, KeepShapeNodesMakesEverySegmentAnEdge) {
    Fixture f;
    f.node(1, 0, 0).node(2, 50, 5).node(3, 100, 0).node(4, 200, 0).node(5, 100, 80);
    f.way(10, "highway=residential", {1, 2, 3, 4}).way(11, "highway=residential", {3, 5});
    const GeometricGraph g = f.import({.keep_shape_nodes = true});
    EXPECT_EQ(g.vertex_count(), 5u);
    EXPECT_EQ(g.edge_count(), 4u);
    EXPECT_EQ(check_simple(g), "");
}

TEST(Topology, WayEndsStayVerticesEvenAtDegreeTwo) {
    Fixture f;
    f.node(1, 0, 0).node(2, 100, 0).node(3, 200, 0);
    f.way(10, "highway=primary", {1, 2}).way(11, "highway=secondary", {2, 3});
    const GeometricGraph g = f.import();
    EXPECT_EQ(g.vertex_count(), 3u);
    EXPECT_EQ(g.edge_count(), 2u);
}

TEST(Topology, ClosedRoundaboutBecomesACycle) {
    Fixture f;
    f.node(1, -100, 0).node(10, -20, 0).node(11, 0, 20).node(12, 20, 0).node(13, 0, -20);
    f.way(5, "highway=residential", {1, 10}).way(6, "highway=tertiary,junction=roundabout", {10, 11, 12, 13, 10});
    const GeometricGraph g = f.import();
    EXPECT_EQ(check_simple(g), "");
    EXPECT_EQ(g.vertex_count(), 4u); // 1, 10 and two promoted shape nodes
    EXPECT_EQ(g.edge_count(), 4u);
    const double ring = 4 * std::sqrt(800.0);
    EXPECT_NEAR(g.total_length(), 80.0 + ring, 0.05);
    for (std::size_t e = 0; e < g.edge_count(); ++e) {
        if (g.edge_highway[e] == HighwayClass::tertiary) EXPECT_EQ(g.edge_oneway[e], 1); // roundabouts are one-way
    }
}

TEST(Topology, DifferentRoadsBetweenTheSameVerticesAreKeptApart) {
    Fixture f;
    f.node(1, 0, 0).node(2, 100, 0).node(3, 20, 40).node(4, 80, 40);
    f.way(10, "highway=residential", {1, 2}).way(11, "highway=residential", {1, 3, 4, 2});
    const GeometricGraph g = f.import();
    EXPECT_EQ(check_simple(g), "");
    EXPECT_EQ(g.vertex_count(), 3u);
    EXPECT_EQ(g.edge_count(), 3u);
    EXPECT_NEAR(g.total_length(), 100.0 + 2 * std::hypot(20.0, 40.0) + 60.0, 0.05);
}

TEST(Topology, DuplicateWaysAreStoredOnce) {
    Fixture f;
    f.node(1, 0, 0).node(2, 100, 10).node(3, 200, 0);
    f.way(10, "highway=residential", {1, 2, 3}).way(11, "highway=residential", {3, 2, 1});
    ImportReport report;
    const GeometricGraph g = f.import({}, &report);
    EXPECT_EQ(check_simple(g), "");
    EXPECT_EQ(g.edge_count(), 2u);
    EXPECT_NEAR(g.total_length(), 2 * std::hypot(100.0, 10.0), 0.05);
    EXPECT_EQ(report.topology.duplicate_pieces, 2u);
}

TEST(Topology, NodesAtOnePlaceAreOneVertexAndNoEdgeHasZeroLength) {
    Fixture f;
    f.node(1, 0, 0).node(2, 100, 0).node(3, 100, 0).node(4, 100, 100).node(5, 200, 0);
    f.way(10, "highway=residential", {1, 2, 3, 4}).way(11, "highway=residential", {3, 5});
    const GeometricGraph g = f.import();
    EXPECT_EQ(check_simple(g), "");
    EXPECT_EQ(g.vertex_count(), 4u); // 2 and 3 share a place
    EXPECT_EQ(g.edge_count(), 3u);
}

TEST(Topology, MissingNodesSplitTheWay) {
    Fixture f;
    f.node(1, 0, 0).node(2, 100, 0).node(3, 300, 0).node(4, 400, 0);
    f.way(10, "highway=residential", {1, 2, 99, 3, 4});
    ImportReport report;
    const GeometricGraph g = f.import({}, &report);
    EXPECT_EQ(g.vertex_count(), 4u);
    EXPECT_EQ(g.edge_count(), 2u);
    EXPECT_EQ(report.missing_nodes, 1u);
    EXPECT_EQ(report.referenced_nodes, 5u);
}

TEST(Topology, UnsortedFileGivesTheSameGraph) {
    Fixture f;
    f.node(3, 100, 0).node(1, 0, 0).node(5, 100, 80).node(2, 50, 5).node(4, 200, 0);
    f.way(11, "highway=residential", {3, 5}).way(10, "highway=residential", {1, 2, 3, 4});
    const GeometricGraph sorted_order = f.import();
    const GeometricGraph ways_first = f.import({}, nullptr, true);
    EXPECT_EQ(ways_first.vertex_count(), 4u);
    EXPECT_EQ(ways_first.edge_count(), 3u);
    EXPECT_EQ(ways_first.positions, sorted_order.positions);
    EXPECT_EQ(ways_first.edges, sorted_order.edges);
}

TEST(Topology, ConsolidationMergesDualCarriagewayIntersections) {
    Fixture f;
    // Two one-way carriageways 10 m apart crossed by two streets 200 m apart.
    f.node(1, -50, 5).node(2, 0, 5).node(3, 200, 5).node(4, 250, 5);
    f.node(5, 250, -5).node(6, 200, -5).node(7, 0, -5).node(8, -50, -5);
    f.node(20, 0, 100).node(21, 0, -100).node(22, 200, 100).node(23, 200, -100);
    f.way(30, "highway=primary,oneway=yes", {1, 2, 3, 4}).way(31, "highway=primary,oneway=yes", {5, 6, 7, 8});
    f.way(32, "highway=residential", {20, 2, 7, 21}).way(33, "highway=residential", {22, 3, 6, 23});
    const GeometricGraph raw = f.import();
    EXPECT_EQ(raw.vertex_count(), 12u);
    ImportReport report;
    const GeometricGraph g = f.import({.consolidate_m = 15.0}, &report);
    EXPECT_EQ(check_simple(g), "");
    EXPECT_EQ(g.vertex_count(), 8u);
    EXPECT_EQ(g.edge_count(), 7u);
    EXPECT_EQ(report.topology.merged_parallel, 3u);
    for (std::size_t e = 0; e < g.edge_count(); ++e) {
        if (g.edge_highway[e] == HighwayClass::primary) EXPECT_EQ(g.edge_oneway[e], 0) << "a merged carriageway carries both directions";
    }
}

TEST(Topology, FilterKeepsOnlyChosenClasses) {
    Fixture f;
    f.node(1, 0, 0).node(2, 100, 0).node(3, 100, 100);
    f.way(10, "highway=residential", {1, 2}).way(11, "highway=footway", {2, 3}).way(12, "building=yes", {1, 2, 3, 1});
    ImportOptions options; // drivable
    ImportReport report;
    const GeometricGraph g = import_osm(temp_file(f.opl(), ".opl"), options, &report);
    EXPECT_EQ(g.edge_count(), 1u);
    EXPECT_EQ(report.highway_ways, 2u);
    EXPECT_EQ(report.ways_kept, 1u);
}

TEST(Topology, AttributesComeFromTags) {
    Fixture f;
    f.node(1, 0, 0).node(2, 100, 0).node(3, 200, 0).node(4, 300, 0);
    f.way(10, "highway=secondary,lanes=3,width=7.5%20%m,oneway=-1,name=Rue", {1, 2});
    f.way(11, "highway=motorway", {2, 3});
    f.way(12, "highway=residential,width=12%20%ft,lanes=many", {3, 4});
    const GeometricGraph g = f.import();
    ASSERT_EQ(g.edge_count(), 3u);
    EXPECT_EQ(g.edge_highway[0], HighwayClass::secondary);
    EXPECT_EQ(g.edge_lanes[0], 3);
    EXPECT_DOUBLE_EQ(g.edge_width_m[0], 7.5);
    EXPECT_EQ(g.edge_oneway[0], -1);
    EXPECT_EQ(g.edge_way_ids[0], 10);
    EXPECT_EQ(g.edge_name(0), "Rue");
    EXPECT_EQ(g.edge_oneway[1], 1); // motorways are one-way by convention
    EXPECT_NEAR(g.edge_width_m[2], 12 * 0.3048, 1e-12);
    EXPECT_EQ(g.edge_lanes[2], 0);
}

TEST(Topology, ConsolidationDoesNotChainAlongAStreet) {
    // A road with 60 side streets 8 m apart, alternately to the north and the south (their
    // ends 16 m apart): at a 10 m tolerance crossings merge in small groups around seeds;
    // the road does not collapse into one point.
    Fixture f;
    std::vector<int> road;
    auto end_of = [](int i) { return Vec2(8.0 * i, i % 2 ? 100.0 : -100.0); };
    for (int i = 0; i < 60; ++i) {
        f.node(100 + i, 8.0 * i, 0).node(300 + i, end_of(i).x(), end_of(i).y());
        f.way(1000 + i, "highway=residential", {100 + i, 300 + i});
        road.push_back(100 + i);
    }
    f.way(999, "highway=primary", road);
    GeometricGraph merged = f.import({.consolidate_m = 10.0});
    reproject(merged, {46.0, 8.0}); // into the fixture's frame
    EXPECT_EQ(check_simple(merged), "");
    EXPECT_GE(merged.vertex_count(), 60u + 20u); // the 60 far ends and at least a third of the crossings
    EXPECT_GT(merged.total_length(), 0.9 * 60 * 100.0);
    // Every vertex stays within twice the tolerance of a crossing or a street end.
    for (const Vec2& p : merged.positions) {
        double nearest = 1e9;
        for (int i = 0; i < 60; ++i) nearest = std::min({nearest, (p - Vec2(8.0 * i, 0)).norm(), (p - end_of(i)).norm()});
        EXPECT_LE(nearest, 20.5);
    }
}

TEST(Topology, TheLastVersionOfADuplicateWayWins) {
    Fixture f;
    f.node(1, 0, 0).node(2, 100, 0).node(3, 100, 100);
    f.way(1, "highway=residential", {1, 2}).way(1, "highway=primary", {1, 3});
    const GeometricGraph g = f.import();
    ASSERT_EQ(g.edge_count(), 1u);
    EXPECT_EQ(g.edge_highway[0], HighwayClass::primary);
}
