// The 3-D city's ground plan (synthesis/city_layout.hpp) and the road width rule
// (graph/road_widths.hpp): the domain rules that the CLI, Python and Blender share.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "fixtures.hpp"
#include "ggg/error.hpp"
#include "ggg/graph/road_class.hpp"
#include "ggg/graph/road_widths.hpp"
#include "ggg/io/read_graph.hpp"
#include "ggg/osm/highway_filter.hpp"
#include "ggg/osm/osm_import.hpp"
#include "ggg/synthesis/city_layout.hpp"

namespace ggg {
namespace {

GeometricGraph three_roads() {
    GeometricGraph g;
    for (int i = 0; i < 3; ++i) {
        g.add_vertex({0.0, 50.0 * i});
        g.add_vertex({100.0, 50.0 * i});
    }
    EdgeAttributes primary, residential, path;
    primary.highway = HighwayClass::primary;
    primary.width_m = 7.5; // tagged
    residential.highway = HighwayClass::residential;
    residential.lanes = 2;
    path.highway = HighwayClass::path;
    g.add_edge(0, 1, primary);
    g.add_edge(2, 3, residential);
    g.add_edge(4, 5, path);
    return g;
}

GeometricGraph sample_town() {
    ImportOptions o;
    o.highways = HighwayFilter::all();
    return read_graph(std::string(GGG_SAMPLES_DIR) + "/sample_city.osm", o);
}

} // namespace

// A road is as wide as its `width` tag, else its lanes, else its class.
TEST(RoadWidths, TagThenLanesThenClass) {
    const GeometricGraph g = three_roads();
    const std::vector<double> w = road_widths(g);
    EXPECT_DOUBLE_EQ(w[0], 7.5);
    EXPECT_DOUBLE_EQ(w[1], 2 * RoadWidthRule{}.lane_width_m);
    EXPECT_DOUBLE_EQ(w[2], highway_default_width(HighwayClass::path));
    RoadWidthRule rule;
    rule.lane_width_m = 3.0;
    rule.class_widths_m.assign(highway_class_count, 4.0);
    const std::vector<double> custom = road_widths(g, rule);
    EXPECT_DOUBLE_EQ(custom[0], 7.5);
    EXPECT_DOUBLE_EQ(custom[1], 6.0);
    EXPECT_DOUBLE_EQ(custom[2], 4.0);
    rule.class_widths_m.pop_back();
    EXPECT_THROW(road_widths(g, rule), UsageError);
    rule.class_widths_m.assign(highway_class_count, -1.0);
    EXPECT_THROW(road_widths(g, rule), UsageError);
    rule.class_widths_m.clear();
    rule.lane_width_m = std::nan("");
    EXPECT_THROW(road_widths(g, rule), UsageError);
}

// Every building of the sample town has a height of whole floors plus a roof and a tint, the
// same for the same seed; the middle of the town is built higher than its edge.
TEST(CityLayout, BuildingHeightsFollowTheRule) {
    const GeometricGraph g = sample_town();
    CityLayoutOptions o;
    o.seed = 3;
    const CityLayout city = city_layout(g, o);
    ASSERT_GT(city.buildings.size(), 100u);
    ASSERT_EQ(city.building_height_m.size(), city.buildings.size());
    ASSERT_EQ(city.building_tint.size(), city.buildings.size());
    for (std::size_t b = 0; b < city.buildings.size(); ++b) {
        const double h = city.building_height_m[b];
        const double floors = std::floor((h - 0.3) / o.floor_height_m + 1e-9);
        EXPECT_GE(floors, 1.0);
        EXPECT_LE(floors, 60.0);
        EXPECT_LE(h - floors * o.floor_height_m, 1.2 + 1e-9) << "a roof of 0.3 to 1.2 m on whole floors";
        EXPECT_GE(city.building_tint[b], 0.0);
        EXPECT_LT(city.building_tint[b], 1.0);
    }
    EXPECT_EQ(city_layout(g, o).building_height_m, city.building_height_m);
    o.seed = 4;
    EXPECT_NE(city_layout(g, o).building_height_m, city.building_height_m);

    // Nearer the middle than a third of the town's half diagonal against farther out.
    double x0 = 1e18, y0 = 1e18, x1 = -1e18, y1 = -1e18;
    for (const Vec2& p : g.positions) x0 = std::min(x0, p.x()), y0 = std::min(y0, p.y()), x1 = std::max(x1, p.x()), y1 = std::max(y1, p.y());
    std::vector<double> xs, ys;
    for (const Vec2& p : g.positions) xs.push_back(p.x()), ys.push_back(p.y());
    std::nth_element(xs.begin(), xs.begin() + static_cast<long>(xs.size() / 2), xs.end());
    std::nth_element(ys.begin(), ys.begin() + static_cast<long>(ys.size() / 2), ys.end());
    const Vec2 centre(xs[xs.size() / 2], ys[ys.size() / 2]);
    const double radius = 0.5 * std::hypot(x1 - x0, y1 - y0);
    double inner = 0, outer = 0;
    std::size_t n_inner = 0, n_outer = 0;
    for (std::size_t b = 0; b < city.buildings.size(); ++b) {
        const Vec2 first = city.buildings.points[static_cast<std::size_t>(city.buildings.offsets[b])];
        const double d = (first - centre).norm() / radius;
        if (d < 0.3) inner += city.building_height_m[b], ++n_inner;
        else if (d > 0.6) outer += city.building_height_m[b], ++n_outer;
    }
    ASSERT_GT(n_inner, 10u);
    ASSERT_GT(n_outer, 10u);
    EXPECT_GT(inner / static_cast<double>(n_inner), outer / static_cast<double>(n_outer));
}

// Without half widths of its own, the layout draws each road as wide as road_widths says:
// the same plan as with those widths given.
TEST(CityLayout, DefaultWidthsAreTheRoadWidthRule) {
    const GeometricGraph g = sample_town();
    CityLayoutOptions given;
    given.half_widths = road_widths(g);
    for (double& h : given.half_widths) h *= 0.5;
    const CityLayout a = city_layout(g), b = city_layout(g, given);
    EXPECT_EQ(a.roads.points.size(), b.roads.points.size());
    EXPECT_EQ(a.roads.points, b.roads.points);
    EXPECT_EQ(a.buildings.size(), b.buildings.size());
}

} // namespace ggg
