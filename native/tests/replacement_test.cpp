// Terminal replacement (paper Fig. 1): the squares of a grid replaced by round plazas.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>

#include "analysis_fixtures.hpp"
#include "ggg/analysis/analyzer.hpp"
#include "ggg/error.hpp"
#include "ggg/io/read_graph.hpp"
#include "ggg/graph/plane_geometry.hpp"
#include "ggg/synthesis/replacement.hpp"
#include "fixtures.hpp"

namespace ggg {
namespace {

ReplacementGraph plaza(int n, double radius) {
    ReplacementGraph r;
    for (int i = 0; i < n; ++i) r.positions.emplace_back(radius * std::cos(2 * M_PI * i / n), radius * std::sin(2 * M_PI * i / n));
    for (int i = 0; i < n; ++i) r.edges.push_back({i, (i + 1) % n});
    return r;
}

} // namespace

TEST(Replacement, EverySquareBecomesAPlazaJoinedToItsStreets) {
    test::GridOptions grid;
    grid.n = 9;
    const GeometricGraph g = test::make_grid(grid);
    AnalyzeOptions o;
    o.detection.max_order = 4;
    const Analysis a = analyze(g, o);
    const AnalyzedIsogroup* squares = nullptr;
    for (const AnalyzedIsogroup& i : a.isogroups) {
        if (i.group.order() == 4 && i.group.pattern.edges.size() == 4) squares = &i;
        if (squares) break;
    }
    ASSERT_NE(squares, nullptr);
    const auto& chosen = squares->selection.non_overlapping;
    ASSERT_EQ(chosen.size(), 16u);
    const ReplacementGraph ring = fit_replacement(plaza(12, 7.0), squares->group.pattern);
    ReplaceReport report;
    const GeometricGraph out = replace_occurrences(g, squares->group, chosen, ring, &report);
    EXPECT_EQ(report.replaced, 16u);
    // A corner where streets of the grid around meet stays, and the plaza is joined to it; a
    // corner with none (the grid's own corners) goes with its square.
    std::set<VertexId> replaced;
    std::map<VertexId, std::uint32_t> owner;
    for (std::uint32_t c : chosen) {
        for (VertexId v : squares->group.occurrence(c)) replaced.insert(v), owner[v] = c;
    }
    std::set<VertexId> junctions;
    std::size_t inside = 0;
    for (const auto& [u, v] : g.edges) {
        const bool same = owner.count(u) && owner.count(v) && owner[u] == owner[v];
        inside += same;
        if (same) continue;
        if (owner.count(u)) junctions.insert(u);
        if (owner.count(v)) junctions.insert(v);
    }
    EXPECT_EQ(inside, 16u * 4);
    EXPECT_EQ(report.removed_vertices, replaced.size() - junctions.size());
    EXPECT_EQ(report.joined_streets, junctions.size());
    EXPECT_EQ(report.intersections, 0u);
    EXPECT_EQ(out.vertex_count(), g.vertex_count() - report.removed_vertices + 16 * 12);
    EXPECT_EQ(report.added_vertices, 16u * 12);
    EXPECT_EQ(out.edge_count(), g.edge_count() - 16 * 4 + 16 * 12 + junctions.size());
    EXPECT_TRUE(check_simple(out).empty()) << check_simple(out);
    // Each plaza fits into the square it replaces: on its centre, the vertices that face its
    // sides at 0.8 of the half-side (40 m), none outside.
    for (std::size_t c = 0; c < chosen.size(); ++c) {
        Vec2 centre = Vec2::Zero();
        for (VertexId v : squares->group.occurrence(chosen[c])) centre += g.positions[static_cast<std::size_t>(v)];
        centre /= 4.0;
        std::size_t near = 0;
        for (std::size_t v = out.vertex_count() - 16 * 12; v < out.vertex_count(); ++v) {
            const Vec2 d = out.positions[v] - centre;
            if (d.norm() > 60.0) continue;
            near += std::abs(d.norm() - 40.0) < 1e-6;
            EXPECT_LE(d.cwiseAbs().maxCoeff(), 40.0 + 1e-6) << "plaza " << c;
        }
        EXPECT_EQ(near, 12u) << "plaza " << c;
    }
    // The streets around keep their course: every kept vertex is where it was, and every
    // vertex has a street.
    for (std::size_t v = 0, w = 0; v < g.vertex_count(); ++v) {
        if (replaced.count(static_cast<VertexId>(v)) && !junctions.count(static_cast<VertexId>(v))) continue;
        EXPECT_EQ(out.positions[w++], g.positions[v]);
    }
    std::vector<int> degree(out.vertex_count(), 0);
    for (const auto& [u, v] : out.edges) {
        ++degree[static_cast<std::size_t>(u)];
        ++degree[static_cast<std::size_t>(v)];
    }
    for (std::size_t v = 0; v < out.vertex_count(); ++v) EXPECT_GT(degree[v], 0) << v;
    EXPECT_EQ(test::component_count(out), 1u);
}

TEST(Replacement, BadInput) {
    test::GridOptions grid;
    const GeometricGraph g = test::make_grid(grid);
    Isogroup group;
    group.pattern.positions = {{0, 0}, {1, 0}};
    group.pattern.symbols = {0, 0};
    group.pattern.edges = {{0, 1}};
    group.vertices = {0, 1, 1, 2};
    group.transforms = {Similarity2{}, Similarity2{}};
    const std::vector<std::uint32_t> overlapping{0, 1};
    EXPECT_THROW(replace_occurrences(g, group, overlapping, plaza(4, 1.0)), UsageError);
    const std::vector<std::uint32_t> out_of_range{5};
    EXPECT_THROW(replace_occurrences(g, group, out_of_range, plaza(4, 1.0)), UsageError);
    EXPECT_THROW(replace_occurrences(g, group, std::vector<std::uint32_t>{0}, ReplacementGraph{}), UsageError);
    ReplacementGraph bad = plaza(4, 1.0);
    bad.edges.push_back({0, 9});
    EXPECT_THROW(replace_occurrences(g, group, std::vector<std::uint32_t>{0}, bad), UsageError);
}

} // namespace ggg

namespace ggg {

// Paper Fig. 1 on the real Eixample: its most frequent block replaced by a round plaza with
// a square inside. Every plaza lies inside the block it replaces, the streets around keep
// their course and their junctions, every plaza is joined to them, and no street passes
// over another without an intersection.
TEST(Replacement, BarcelonaBlocksBecomePlazasInsideThemJoinedToTheirJunctions) {
    GGG_REQUIRE_CORPUS();
    ImportOptions import;
    import.highways = HighwayFilter::all();
    const GeometricGraph g = read_graph(test::shared_osm_dir() + "/barcelona_eixample.osm", import);
    AnalyzeOptions o;
    o.detection.max_order = 8;
    const Analysis a = analyze(g, o);
    const AnalyzedIsogroup* block = nullptr;
    for (const AnalyzedIsogroup& i : a.isogroups) {
        if (i.group.order() >= 4 && i.group.pattern.edges.size() == i.group.order() &&
            (!block || i.selection.non_overlapping.size() > block->selection.non_overlapping.size())) {
            block = &i;
        }
    }
    ASSERT_NE(block, nullptr);
    const auto& chosen = block->selection.non_overlapping;
    ASSERT_GE(chosen.size(), 50u);
    ReplacementGraph drawn = plaza(16, 1.0);
    for (int j = 0; j < 4; ++j) {
        drawn.positions.push_back(0.45 * drawn.positions[static_cast<std::size_t>(4 * j)]);
        drawn.edges.push_back({16 + j, 16 + (j + 1) % 4});
        drawn.edges.push_back({4 * j, 16 + j});
    }
    ReplaceReport report;
    const GeometricGraph out = replace_occurrences(g, block->group, chosen, fit_replacement(drawn, block->group.pattern), &report);
    EXPECT_EQ(report.replaced, chosen.size());
    EXPECT_EQ(report.added_vertices, chosen.size() * 20 + report.intersections);
    EXPECT_GE(report.joined_streets, 3 * chosen.size());

    // Each plaza inside its block: the 20 vertices placed for it lie in the block's polygon
    // (the intersections made where a plaza met a street come after them).
    const std::size_t first_placed = out.vertex_count() - report.added_vertices;
    std::size_t placed_inside = 0;
    for (std::uint32_t c : chosen) {
        std::vector<Vec2> ring;
        for (VertexId v : block->group.occurrence(c)) ring.push_back(g.positions[static_cast<std::size_t>(v)]);
        Vec2 centre = Vec2::Zero();
        for (const Vec2& p : ring) centre += p / static_cast<double>(ring.size());
        std::sort(ring.begin(), ring.end(), [&](const Vec2& p, const Vec2& q) {
            return std::atan2(p.y() - centre.y(), p.x() - centre.x()) < std::atan2(q.y() - centre.y(), q.x() - centre.x());
        });
        std::size_t here = 0;
        for (std::size_t v = first_placed; v < first_placed + chosen.size() * 20; ++v) here += inside(ring, out.positions[v]);
        EXPECT_EQ(here, 20u) << "occurrence " << c;
        placed_inside += here;
    }
    EXPECT_EQ(placed_inside, chosen.size() * 20);

    // The streets around stay where they were, in their order: every vertex but those of an
    // occurrence that no other street reaches; one vertex per place.
    std::vector<std::int32_t> owner(g.vertex_count(), -1);
    for (std::size_t c = 0; c < chosen.size(); ++c) {
        for (VertexId v : block->group.occurrence(chosen[c])) owner[static_cast<std::size_t>(v)] = static_cast<std::int32_t>(c);
    }
    std::vector<char> reached(g.vertex_count(), 0);
    for (const auto& [a, b] : g.edges) {
        const std::int32_t oa = owner[static_cast<std::size_t>(a)], ob = owner[static_cast<std::size_t>(b)];
        if (oa < 0 || oa != ob) reached[static_cast<std::size_t>(a)] = reached[static_cast<std::size_t>(b)] = 1;
    }
    std::size_t kept = 0;
    for (std::size_t v = 0; v < g.vertex_count(); ++v) {
        if (owner[v] >= 0 && !reached[v]) continue;
        ASSERT_LT(kept, out.vertex_count());
        EXPECT_EQ(out.positions[kept++], g.positions[v]) << v;
    }
    EXPECT_EQ(kept + report.added_vertices, out.vertex_count());
    EXPECT_EQ(report.removed_vertices, g.vertex_count() - kept);
    EXPECT_TRUE(check_simple(out).empty()) << check_simple(out);
    EXPECT_LE(test::shared_places(out), test::shared_places(g));
    // No street of the result crosses another without an intersection, beyond the bridges
    // and tunnels the Eixample already has; every plaza is joined to the network (a plaza
    // that crosses a path the network did not reach joins it too).
    EXPECT_LE(test::polyline_crossings(out), test::polyline_crossings(g));
    EXPECT_LE(test::component_count(out), test::component_count(g));
}

} // namespace ggg
