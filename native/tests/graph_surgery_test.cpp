// Cutting a graph down and putting back what was grown on the cut: every column follows its
// vertex or edge, and an edge of the part that growth split comes back split.
#include <gtest/gtest.h>

#include "ggg/error.hpp"
#include "ggg/graph/graph_surgery.hpp"

namespace ggg {
namespace {

// A 100 m square of named streets (OSM ids 11..14) with a nonterminal in its middle joined
// to its first corner.
GeometricGraph square_with_rule() {
    GeometricGraph g;
    g.origin = {41.39, 2.16};
    const Vec2 corners[] = {{0, 0}, {100, 0}, {100, 100}, {0, 100}};
    for (int i = 0; i < 4; ++i) g.add_vertex(corners[i], 11 + i);
    const VertexId rule = g.add_vertex({50, 50});
    g.symbols[static_cast<std::size_t>(rule)] = 7;
    g.frames[static_cast<std::size_t>(rule)] = Similarity2::from(20.0, 0.0, {50, 50});
    for (int i = 0; i < 4; ++i) {
        EdgeAttributes a;
        a.highway = HighwayClass::residential;
        a.name = "street " + std::to_string(i);
        a.way_id = 100 + i;
        a.lanes = 2;
        g.add_edge(i, (i + 1) % 4, a, {corners[i], 0.5 * (corners[i] + corners[(i + 1) % 4]) + Vec2(0, 3), corners[(i + 1) % 4]});
    }
    g.add_edge(0, rule, {});
    return g;
}

std::vector<bool> streets_of(const GeometricGraph& g) {
    std::vector<bool> keep(g.vertex_count());
    for (std::size_t v = 0; v < g.vertex_count(); ++v) keep[v] = g.symbols[v] == 0;
    return keep;
}

} // namespace

TEST(GraphSurgery, TheInducedSubgraphKeepsEveryColumn) {
    const GeometricGraph g = square_with_rule();
    const Subgraph part = induced_subgraph(g, streets_of(g));
    EXPECT_EQ(part.vertex_ids, (std::vector<VertexId>{0, 1, 2, 3}));
    EXPECT_EQ(part.edge_ids, (std::vector<EdgeId>{0, 1, 2, 3}));
    ASSERT_EQ(part.graph.vertex_count(), 4u);
    ASSERT_EQ(part.graph.edge_count(), 4u);
    EXPECT_EQ(part.graph.origin.lat, 41.39);
    for (std::size_t v = 0; v < 4; ++v) EXPECT_EQ(part.graph.vertex_osm_ids[v], g.vertex_osm_ids[v]);
    for (EdgeId e = 0; e < 4; ++e) {
        EXPECT_EQ(part.graph.edge_name(e), g.edge_name(e));
        EXPECT_EQ(part.graph.edge_way_ids[static_cast<std::size_t>(e)], 100 + e);
        EXPECT_EQ(part.graph.edge_lanes[static_cast<std::size_t>(e)], 2);
        ASSERT_EQ(part.graph.geometry_size(e), 3u);
        EXPECT_EQ(part.graph.geometry_begin(e)[1], g.geometry_begin(e)[1]);
    }
    EXPECT_TRUE(check_simple(part.graph).empty()) << check_simple(part.graph);
}

TEST(GraphSurgery, WhatWasGrownComesBackWithTheRestOfTheGraph) {
    const GeometricGraph g = square_with_rule();
    const std::vector<bool> streets = streets_of(g);
    const Subgraph part = induced_subgraph(g, streets);
    // "Growth": the first street is split in its middle and a new street leaves from there.
    GeometricGraph grown = part.graph;
    const VertexId x = grown.split_edge(0, {50, 3});
    const VertexId y = grown.add_vertex({50, -80});
    EdgeAttributes a;
    a.name = "grown";
    grown.add_edge(x, y, a);

    // The rule was used: everything but it comes back, with the grown streets.
    const Regrown back = with_grown(g, streets, part, grown);
    ASSERT_EQ(back.graph.vertex_count(), 6u);
    EXPECT_EQ(back.source_vertex, (std::vector<VertexId>{0, 1, 2, 3, -1, -1}));
    ASSERT_EQ(back.graph.edge_count(), 6u); // four sides, one of them in two, and the new street
    EXPECT_EQ(back.graph.edges[0], (std::array<VertexId, 2>{0, 4})); // split where the new street meets it
    EXPECT_EQ(back.graph.edge_name(0), "street 0");
    EXPECT_EQ(back.graph.edge_name(5), "grown");
    EXPECT_EQ(back.graph.positions[5], Vec2(50, -80));
    EXPECT_EQ(back.graph.vertex_osm_ids[2], 13);
    EXPECT_TRUE(check_simple(back.graph).empty()) << check_simple(back.graph);
    for (EdgeId e = 0; e < 6; ++e) {
        const auto [u, v] = back.graph.edges[static_cast<std::size_t>(e)];
        EXPECT_EQ(back.graph.geometry_begin(e)[0], back.graph.positions[static_cast<std::size_t>(u)]);
        EXPECT_EQ(back.graph.geometry_begin(e)[back.graph.geometry_size(e) - 1], back.graph.positions[static_cast<std::size_t>(v)]);
    }

    // The rule was not used: it stays, with its frame and its edge.
    const Regrown kept = with_grown(g, std::vector<bool>(g.vertex_count(), true), part, grown);
    ASSERT_EQ(kept.graph.vertex_count(), 7u);
    EXPECT_EQ(kept.source_vertex[4], 4);
    EXPECT_EQ(kept.graph.symbols[4], 7u);
    EXPECT_EQ(kept.graph.frames[4].scale(), 20.0);
    EXPECT_EQ(kept.graph.edge_count(), 7u);
    EXPECT_EQ(kept.graph.edges[4], (std::array<VertexId, 2>{0, 4}));
}

TEST(GraphSurgery, AMismatchIsAClearError) {
    const GeometricGraph g = square_with_rule();
    EXPECT_THROW(induced_subgraph(g, {true, true}), UsageError);
    const Subgraph part = induced_subgraph(g, streets_of(g));
    std::vector<bool> without_a_corner = streets_of(g);
    without_a_corner[2] = false;
    EXPECT_THROW(with_grown(g, without_a_corner, part, part.graph), UsageError);
    EXPECT_THROW(with_grown(g, streets_of(g), part, GeometricGraph{}), UsageError);
}

} // namespace ggg
