// Main roads continued through grown streets: a hand-made seam between two "cities", and a
// strip cut out of Columbus and grown again with Columbus' grammar, whose main roads must
// meet across it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "fixtures.hpp"
#include "ggg/encoding/grammar_encoder.hpp"
#include "ggg/error.hpp"
#include "ggg/graph/road_class.hpp"
#include "ggg/io/read_graph.hpp"
#include "ggg/synthesis/growth.hpp"
#include "ggg/synthesis/street_hierarchy.hpp"

namespace ggg {
namespace {

EdgeAttributes of(HighwayClass c) {
    EdgeAttributes a;
    a.highway = c;
    return a;
}

// Two cities with an east-west primary road each, ending 600 m apart, and a residential
// grid between them (the grown streets, edges from `first_new` on).
struct Seam {
    GeometricGraph g;
    EdgeId first_new = 0;
    VertexId west_end = -1, east_end = -1;
};

Seam seam() {
    Seam s;
    GeometricGraph& g = s.g;
    const VertexId w0 = g.add_vertex({-400, 200}), w1 = g.add_vertex({-200, 200});
    s.west_end = g.add_vertex({0, 200});
    g.add_edge(w0, w1, of(HighwayClass::primary));
    g.add_edge(w1, s.west_end, of(HighwayClass::primary));
    const VertexId e0 = g.add_vertex({1000, 180}), e1 = g.add_vertex({800, 180});
    s.east_end = g.add_vertex({600, 180});
    g.add_edge(e0, e1, of(HighwayClass::primary));
    g.add_edge(e1, s.east_end, of(HighwayClass::primary));
    // A secondary road that only touches the grid's corner: nothing to continue it to
    // within the detour.
    const VertexId s0 = g.add_vertex({-100, -100});
    const VertexId corner = g.add_vertex({0, 0});
    g.add_edge(s0, corner, of(HighwayClass::secondary));
    s.first_new = static_cast<EdgeId>(g.edge_count());
    // The grid: x 0..600, y 0..400, 100 m; its (0, 200) and (600, 200) rows meet the roads'
    // ends (the east road ends at (600, 180), joined to the grid's (600, 200) by one street).
    std::map<std::pair<int, int>, VertexId> at;
    at[{0, 0}] = corner;
    at[{0, 2}] = s.west_end;
    for (int i = 0; i <= 6; ++i) {
        for (int j = 0; j <= 4; ++j) {
            if (!at.count({i, j})) at[{i, j}] = g.add_vertex({100.0 * i, 100.0 * j});
        }
    }
    for (int i = 0; i <= 6; ++i) {
        for (int j = 0; j <= 4; ++j) {
            if (i < 6) g.add_edge(at[{i, j}], at[{i + 1, j}], of(HighwayClass::residential));
            if (j < 4) g.add_edge(at[{i, j}], at[{i, j + 1}], of(HighwayClass::residential));
        }
    }
    g.add_edge(at[{6, 2}], s.east_end, of(HighwayClass::residential));
    return s;
}

TEST(StreetHierarchy, AMainRoadContinuesAcrossTheGrownStreetsToTheOtherSide) {
    Seam s = seam();
    const GeometricGraph before = s.g;
    const HierarchyReport r = continue_hierarchy(s.g, s.first_new);
    EXPECT_EQ(r.main_roads, 3u);
    EXPECT_EQ(r.routes, 1u);
    // The straight row y = 200 (six streets) and the street to the east road's end.
    EXPECT_EQ(r.raised_streets, 7u);
    std::size_t primary = 0;
    for (std::size_t e = 0; e < s.g.edge_count(); ++e) {
        if (e < static_cast<std::size_t>(s.first_new)) {
            EXPECT_EQ(s.g.edge_highway[e], before.edge_highway[e]) << "a street the growth started from changed";
            continue;
        }
        if (s.g.edge_highway[e] != HighwayClass::primary) continue;
        ++primary;
        const Vec2 a = s.g.positions[static_cast<std::size_t>(s.g.edges[e][0])];
        const Vec2 b = s.g.positions[static_cast<std::size_t>(s.g.edges[e][1])];
        EXPECT_GE(std::min(a.y(), b.y()), 179.0);
        EXPECT_LE(std::max(a.y(), b.y()), 201.0);
    }
    EXPECT_EQ(primary, 7u);
    // Nothing left to join: a second pass changes nothing.
    const HierarchyReport again = continue_hierarchy(s.g, s.first_new);
    EXPECT_EQ(again.raised_streets, 0u);
}

TEST(StreetHierarchy, TooLongADetourIsNoRoute) {
    const Seam s = seam();
    HierarchyOptions strict;
    strict.max_detour = 1.05;
    // Along the row the route is 620 m for 600.3 m of straight line.
    GeometricGraph g = s.g;
    EXPECT_EQ(continue_hierarchy(g, s.first_new, strict).routes, 1u);
    // Without the row's middle street the way round one block is 1.37 times as long.
    GeometricGraph cut;
    cut.positions = s.g.positions;
    for (std::size_t e = 0; e < s.g.edge_count(); ++e) {
        const Vec2 a = s.g.positions[static_cast<std::size_t>(s.g.edges[e][0])];
        const Vec2 b = s.g.positions[static_cast<std::size_t>(s.g.edges[e][1])];
        const bool middle = std::abs(a.y() - 200) < 1 && std::abs(b.y() - 200) < 1 && std::min(a.x(), b.x()) > 250 &&
                            std::max(a.x(), b.x()) < 450;
        if (!middle) cut.add_edge(s.g.edges[e][0], s.g.edges[e][1], of(s.g.edge_highway[e]));
    }
    // Strictly, the primary road finds nothing across; it goes to the secondary road at the
    // corner instead (200 m straight down the grid's edge), which raises two streets.
    GeometricGraph cut_strict = cut;
    const HierarchyReport r = continue_hierarchy(cut_strict, s.first_new, strict);
    EXPECT_EQ(r.routes, 1u);
    EXPECT_EQ(r.raised_streets, 2u);
    for (std::size_t e = static_cast<std::size_t>(s.first_new); e < cut_strict.edge_count(); ++e) {
        EXPECT_NE(cut_strict.edge_highway[e], HighwayClass::primary);
    }
    // The default 1.6 allows the way round: the primary roads meet.
    const HierarchyReport loose = continue_hierarchy(cut, s.first_new);
    EXPECT_EQ(loose.routes, 1u);
    EXPECT_EQ(loose.raised_streets, 9u);
}

// Two main roads facing each other across grown streets that do not join them: a straight
// main road does, and the grown street it crosses gets an intersection.
TEST(StreetHierarchy, FacingMainRoadsWithoutARouteAreJoinedStraight) {
    auto build = [](bool city_street_in_the_way) {
        GeometricGraph g;
        const VertexId w0 = g.add_vertex({-200, 200}), w = g.add_vertex({0, 200});
        const VertexId e0 = g.add_vertex({800, 200}), e = g.add_vertex({600, 200});
        g.add_edge(w0, w, of(HighwayClass::secondary));
        g.add_edge(e0, e, of(HighwayClass::secondary));
        if (city_street_in_the_way) {
            const VertexId a = g.add_vertex({450, 150}), b = g.add_vertex({450, 250});
            g.add_edge(a, b, of(HighwayClass::residential));
        }
        const auto first = static_cast<EdgeId>(g.edge_count());
        // Grown: a stub at each road's end and a north-south street between them.
        g.add_edge(w, g.add_vertex({0, 300}), of(HighwayClass::residential));
        g.add_edge(e, g.add_vertex({600, 100}), of(HighwayClass::residential));
        g.add_edge(g.add_vertex({300, 0}), g.add_vertex({300, 400}), of(HighwayClass::residential));
        return std::pair{g, first};
    };
    auto [g, first] = build(false);
    const std::size_t vertices = g.vertex_count(), edges = g.edge_count();
    const HierarchyReport r = continue_hierarchy(g, first);
    EXPECT_EQ(r.routes, 0u);
    EXPECT_EQ(r.connectors, 1u);
    EXPECT_EQ(r.intersections, 1u);
    EXPECT_EQ(r.connector_streets, 2u);
    ASSERT_EQ(g.vertex_count(), vertices + 1);
    ASSERT_EQ(g.edge_count(), edges + 3); // the crossed street's second half and the two pieces
    const Vec2 x = g.positions.back();
    EXPECT_NEAR(x.x(), 300.0, 1e-9);
    EXPECT_NEAR(x.y(), 200.0, 1e-9);
    std::size_t secondary = 0, at_x = 0;
    for (std::size_t e = 0; e < g.edge_count(); ++e) {
        const bool touches = static_cast<std::size_t>(g.edges[e][0]) == vertices || static_cast<std::size_t>(g.edges[e][1]) == vertices;
        at_x += touches;
        secondary += e >= static_cast<std::size_t>(first) && g.edge_highway[e] == HighwayClass::secondary;
        // Every street's polyline still ends on its vertices.
        const Vec2* p = g.geometry_begin(static_cast<EdgeId>(e));
        EXPECT_EQ(p[0], g.positions[static_cast<std::size_t>(g.edges[e][0])]);
        EXPECT_EQ(p[g.geometry_size(static_cast<EdgeId>(e)) - 1], g.positions[static_cast<std::size_t>(g.edges[e][1])]);
    }
    EXPECT_EQ(at_x, 4u); // a four-way intersection
    EXPECT_EQ(secondary, 2u);

    // A street of a city in the way: no straight main road through it.
    auto [blocked, first_blocked] = build(true);
    const HierarchyReport none = continue_hierarchy(blocked, first_blocked);
    EXPECT_EQ(none.connectors, 0u);
    EXPECT_EQ(none.intersections, 0u);
}

// A grown T-junction right on the line between two facing main roads: going through it would
// give it five streets (Oakland's infill test, seed 1, had two such junctions). A grown
// vertex of two streets on the line is gone through, making a crossing of four.
TEST(StreetHierarchy, AConnectorMakesNoJunctionOfMoreThanFourStreets) {
    auto build = [](bool t_junction) {
        GeometricGraph g;
        const VertexId w0 = g.add_vertex({-200, 200}), w = g.add_vertex({0, 200});
        const VertexId e0 = g.add_vertex({800, 200}), e = g.add_vertex({600, 200});
        g.add_edge(w0, w, of(HighwayClass::secondary));
        g.add_edge(e0, e, of(HighwayClass::secondary));
        const auto first = static_cast<EdgeId>(g.edge_count());
        g.add_edge(w, g.add_vertex({0, 300}), of(HighwayClass::residential));
        g.add_edge(e, g.add_vertex({600, 100}), of(HighwayClass::residential));
        // A north-south street with a vertex on the line, and (or not) a third street there.
        const VertexId on_line = g.add_vertex({300, 200});
        g.add_edge(g.add_vertex({300, 0}), on_line, of(HighwayClass::residential));
        g.add_edge(on_line, g.add_vertex({300, 400}), of(HighwayClass::residential));
        if (t_junction) g.add_edge(on_line, g.add_vertex({380, 300}), of(HighwayClass::residential));
        return std::pair{g, first};
    };
    auto most_streets = [](const GeometricGraph& g) {
        std::vector<int> degree(g.vertex_count(), 0);
        for (const auto& [a, b] : g.edges) ++degree[static_cast<std::size_t>(a)], ++degree[static_cast<std::size_t>(b)];
        return *std::max_element(degree.begin(), degree.end());
    };
    auto [t, first_t] = build(true);
    const HierarchyReport blocked = continue_hierarchy(t, first_t);
    EXPECT_EQ(blocked.connectors, 0u);
    EXPECT_LE(most_streets(t), 4);

    auto [crossing, first_crossing] = build(false);
    const HierarchyReport through = continue_hierarchy(crossing, first_crossing);
    EXPECT_EQ(through.connectors, 1u);
    EXPECT_EQ(most_streets(crossing), 4);
}

// A trunk road cut where the region begins, with nothing grown reaching its end and no main
// road to meet (Krems' infill test, seed 3: its dual carriageway across the hole stopped at
// both sides): it goes straight on to the first grown street ahead and meets it in a T, or,
// where that street runs along it, bends a little to the next.
TEST(StreetHierarchy, AMainRoadThatEndsAtTheRegionGoesOnToTheFirstGrownStreet) {
    auto build = [](const Vec2& street_from, const Vec2& street_to, bool city_street_in_the_way) {
        GeometricGraph g;
        const VertexId far = g.add_vertex({-300, 200}), end = g.add_vertex({0, 200});
        g.add_edge(far, end, of(HighwayClass::trunk));
        if (city_street_in_the_way) g.add_edge(g.add_vertex({60, 150}), g.add_vertex({60, 250}), of(HighwayClass::residential));
        const auto first = static_cast<EdgeId>(g.edge_count());
        g.add_edge(g.add_vertex(street_from), g.add_vertex(street_to), of(HighwayClass::residential));
        g.add_edge(g.add_vertex({400, 0}), g.add_vertex({400, 400}), of(HighwayClass::residential));
        return std::pair{g, first};
    };
    HierarchyOptions options;
    options.region = {{0, 0}, {600, 0}, {600, 400}, {0, 400}};
    auto [g, first] = build({150, 0}, {150, 400}, false);
    const std::size_t vertices = g.vertex_count(), edges = g.edge_count();
    const HierarchyReport r = continue_hierarchy(g, first, options);
    EXPECT_EQ(r.extensions, 1u);
    ASSERT_EQ(g.vertex_count(), vertices + 1);
    ASSERT_EQ(g.edge_count(), edges + 2); // the street's second half and the road's new piece
    EXPECT_NEAR((g.positions.back() - Vec2(150, 200)).norm(), 0.0, 1e-9);
    EXPECT_EQ(g.edge_highway.back(), HighwayClass::trunk);
    EXPECT_EQ(g.edges.back()[0], 1); // from the road's end
    EXPECT_EQ(check_simple(g), "");

    // A street of the city in the way, straight on and turned: the road stays as it was.
    auto [blocked, first_blocked] = build({150, 0}, {150, 400}, true);
    const std::size_t blocked_edges = blocked.edge_count();
    EXPECT_EQ(continue_hierarchy(blocked, first_blocked, options).extensions, 0u);
    EXPECT_EQ(blocked.edge_count(), blocked_edges);
    // A grown street that runs along the road rather than across it (Krems' trunk road, seed 3):
    // the road bends a little, by the nearest turn of 5 to 15 degrees that passes it, and goes
    // on to the street across it beyond, which it meets in a T.
    auto [along, first_along] = build({100, 190}, {300, 215}, false);
    const std::size_t along_edges = along.edge_count();
    EXPECT_EQ(continue_hierarchy(along, first_along, options).extensions, 1u);
    ASSERT_EQ(along.edge_count(), along_edges + 2);
    const Vec2 reached = along.positions[static_cast<std::size_t>(along.edges.back()[1])];
    EXPECT_NEAR(reached.x(), 400.0, 1e-9);
    const double turn = std::abs(std::atan2(reached.y() - 200.0, reached.x())) * 180.0 / M_PI;
    EXPECT_GT(turn, 1.0);
    EXPECT_LE(turn, 15.0 + 1e-9);
    EXPECT_EQ(check_simple(along), "");
    // Without the region, an end that nothing grown reaches is no main road of the growth.
    auto [no_region, first_no_region] = build({150, 0}, {150, 400}, false);
    EXPECT_EQ(continue_hierarchy(no_region, first_no_region).extensions, 0u);
}

// The split behind junctions on grown streets (connectors here, T-junctions in growth).
TEST(GeometricGraph, SplitEdgeKeepsTheFirstHalfAndAppendsTheSecond) {
    GeometricGraph g;
    const VertexId a = g.add_vertex({0, 0}), b = g.add_vertex({100, 0}), c = g.add_vertex({0, 50});
    EdgeAttributes named = of(HighwayClass::tertiary);
    named.name = "High Street";
    named.lanes = 2;
    g.add_edge(a, b, named);
    g.add_edge(a, c, of(HighwayClass::residential), {{0, 0}, {-5, 25}, {0, 50}});
    const VertexId x = g.split_edge(0, {40, 0});
    EXPECT_EQ(x, 3);
    ASSERT_EQ(g.edge_count(), 3u);
    EXPECT_EQ(g.edges[0], (std::array<VertexId, 2>{a, x}));
    EXPECT_EQ(g.edges[2], (std::array<VertexId, 2>{x, b}));
    EXPECT_DOUBLE_EQ(g.edge_length(0), 40.0);
    EXPECT_DOUBLE_EQ(g.edge_length(2), 60.0);
    EXPECT_EQ(g.edge_name(2), "High Street");
    EXPECT_EQ(g.edge_lanes[2], 2);
    EXPECT_EQ(g.edge_highway[2], HighwayClass::tertiary);
    EXPECT_EQ(g.geometry_size(1), 3u); // the other edge's polyline is untouched
    // A polyline is split on its piece nearest the point; the streets stored after it keep theirs.
    const VertexId y = g.split_edge(1, {-2.5, 12.5});
    ASSERT_EQ(g.edge_count(), 4u);
    EXPECT_EQ(g.edges[1], (std::array<VertexId, 2>{a, y}));
    EXPECT_EQ(g.edges[3], (std::array<VertexId, 2>{y, c}));
    EXPECT_EQ(g.geometry_size(1), 2u);
    EXPECT_EQ(g.geometry_size(3), 3u);
    EXPECT_NEAR(g.edge_length(1) + g.edge_length(3), 2 * std::hypot(5.0, 25.0), 1e-9);
    EXPECT_EQ(g.geometry_begin(3)[1], Vec2(-5, 25));
    EXPECT_EQ(g.geometry_size(2), 2u);
    EXPECT_DOUBLE_EQ(g.edge_length(2), 60.0);
    EXPECT_EQ(g.geometry_begin(2)[0], Vec2(40, 0));
    EXPECT_EQ(g.edge_highway[3], HighwayClass::residential);
    EXPECT_THROW(g.split_edge(7, {0, 0}), UsageError);
    EXPECT_THROW(g.split_edge(0, {std::nan(""), 0}), UsageError);
}

TEST(StreetHierarchy, BadInput) {
    Seam s = seam();
    EXPECT_THROW(continue_hierarchy(s.g, -1), UsageError);
    EXPECT_THROW(continue_hierarchy(s.g, static_cast<EdgeId>(s.g.edge_count() + 1)), UsageError);
    HierarchyOptions o;
    o.max_detour = 0.5;
    EXPECT_THROW(continue_hierarchy(s.g, s.first_new, o), UsageError);
    // No grown streets: nothing to do, not an error.
    EXPECT_EQ(continue_hierarchy(s.g, static_cast<EdgeId>(s.g.edge_count())).routes, 0u);
}

// A strip cut out of Columbus and grown again with Columbus' grammar: the main roads that the
// cut interrupted meet again across the strip, through grown streets only.
TEST(StreetHierarchy, MainRoadsOfColumbusMeetAcrossAGrownStrip) {
    GGG_REQUIRE_CORPUS();
    const GeometricGraph city = read_graph(test::shared_osm_dir() + "/columbus_oh.osm.pbf");
    const Grammar grammar = learn_grammar(city).grammar;
    std::vector<double> xs, ys;
    for (const Vec2& p : city.positions) {
        xs.push_back(p.x());
        ys.push_back(p.y());
    }
    std::sort(xs.begin(), xs.end());
    std::sort(ys.begin(), ys.end());
    const double x0 = xs[xs.size() / 2] - 300, x1 = x0 + 600;
    const double y0 = ys[ys.size() / 5], y1 = ys[ys.size() * 4 / 5];
    auto in_strip = [&](const Vec2& p) { return p.x() > x0 && p.x() < x1 && p.y() > y0 && p.y() < y1; };
    GeometricGraph base;
    std::vector<VertexId> id(city.vertex_count(), -1);
    for (std::size_t v = 0; v < city.vertex_count(); ++v) {
        if (!in_strip(city.positions[v])) id[v] = base.add_vertex(city.positions[v]);
    }
    for (std::size_t e = 0; e < city.edge_count(); ++e) {
        const VertexId a = id[static_cast<std::size_t>(city.edges[e][0])], b = id[static_cast<std::size_t>(city.edges[e][1])];
        if (a >= 0 && b >= 0) base.add_edge(a, b, of(city.edge_highway[e]));
    }
    GrowReport report;
    GrowOptions o;
    o.seed = 3;
    // The hierarchy on streets grown from rules alone: traced streets (street_tracing.hpp)
    // continue the main roads themselves, as main roads. (Streets split after it would not
    // be split before it, nor dead-end streets added after it be there before it.)
    o.trace_streets = false;
    o.split_streets = false;
    o.cul_de_sacs = false;
    const std::vector<Vec2> strip{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
    const GeometricGraph grown = grow_region(base, grammar, strip, o, &report);
    ASSERT_GT(report.placements + report.traced_streets, 20u);
    // The same as growing without the hierarchy, then continuing it in the same region (the
    // main roads that end near it take part too).
    o.continue_hierarchy = false;
    const GeometricGraph flat = grow_region(base, grammar, strip, o);
    GeometricGraph continued = flat;
    HierarchyOptions in_strip_options;
    in_strip_options.region = strip;
    const HierarchyReport h = continue_hierarchy(continued, static_cast<EdgeId>(base.edge_count()), in_strip_options);
    ASSERT_EQ(continued.edges, grown.edges);
    ASSERT_EQ(continued.edge_highway, grown.edge_highway);
    EXPECT_EQ(h.routes, report.main_road_routes);
    EXPECT_GE(h.routes + h.connectors, 2u);
    EXPECT_GE(h.raised_streets + h.connector_streets, 2 * (h.routes + h.connectors));
    for (std::size_t e = 0; e < base.edge_count(); ++e) ASSERT_EQ(grown.edge_highway[e], base.edge_highway[e]);

    // Each run of raised streets joins main roads of the base on both sides of the strip.
    std::set<VertexId> main_road_ends;
    for (std::size_t e = 0; e < base.edge_count(); ++e) {
        if (highway_rank(base.edge_highway[e]) <= highway_rank(HighwayClass::unclassified)) {
            main_road_ends.insert(base.edges[e][0]);
            main_road_ends.insert(base.edges[e][1]);
        }
    }
    // Raised streets (a class changed) and the connectors' (new edges of a main road's class).
    std::vector<std::vector<VertexId>> around(grown.vertex_count());
    std::size_t raised = 0;
    for (std::size_t e = base.edge_count(); e < grown.edge_count(); ++e) {
        const bool changed = e < flat.edge_count() && grown.edge_highway[e] != flat.edge_highway[e];
        const bool connector = e >= flat.edge_count() && highway_rank(grown.edge_highway[e]) <= highway_rank(HighwayClass::unclassified);
        if (!changed && !connector) continue;
        if (changed) {
            EXPECT_LT(highway_rank(grown.edge_highway[e]), highway_rank(flat.edge_highway[e]));
            ++raised;
        }
        around[static_cast<std::size_t>(grown.edges[e][0])].push_back(grown.edges[e][1]);
        around[static_cast<std::size_t>(grown.edges[e][1])].push_back(grown.edges[e][0]);
    }
    EXPECT_EQ(raised, h.raised_streets);
    std::vector<char> seen(grown.vertex_count(), 0);
    std::size_t runs = 0;
    for (std::size_t v = 0; v < grown.vertex_count(); ++v) {
        if (seen[v] || around[v].empty()) continue;
        std::vector<VertexId> stack{static_cast<VertexId>(v)}, run;
        seen[v] = 1;
        while (!stack.empty()) {
            const VertexId x = stack.back();
            stack.pop_back();
            run.push_back(x);
            for (VertexId y : around[static_cast<std::size_t>(x)]) {
                if (!seen[static_cast<std::size_t>(y)]) {
                    seen[static_cast<std::size_t>(y)] = 1;
                    stack.push_back(y);
                }
            }
        }
        ++runs;
        std::size_t ends = 0;
        for (VertexId x : run) ends += main_road_ends.count(x);
        // (A main road that ended at the strip, extended alone to the grown street ahead, is
        // one new street from one main road.)
        const bool extension = run.size() == 2 && ends == 1;
        EXPECT_TRUE(ends >= 2 || extension) << "a run of raised streets that joins no two main roads";
    }
    EXPECT_GE(runs, 1u);
    EXPECT_LE(runs, h.routes + h.connectors + h.extensions);
}

} // namespace
} // namespace ggg
