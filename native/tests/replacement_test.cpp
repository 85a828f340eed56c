// Terminal replacement (paper Fig. 1): the squares of a grid replaced by round plazas.
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "analysis_fixtures.hpp"
#include "ggg/analysis/analyzer.hpp"
#include "ggg/error.hpp"
#include "ggg/synthesis/replacement.hpp"

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
    EXPECT_EQ(out.vertex_count(), g.vertex_count() - 16 * 4 + 16 * 12);
    EXPECT_EQ(report.added_vertices, 16u * 12);
    EXPECT_TRUE(check_simple(out).empty()) << check_simple(out);
    // Each plaza is as large as the square it replaces (fitted: same RMS radius, 50 * sqrt 2 m)
    // and sits on its centre.
    for (std::size_t c = 0; c < chosen.size(); ++c) {
        Vec2 centre = Vec2::Zero();
        for (VertexId v : squares->group.occurrence(chosen[c])) centre += g.positions[static_cast<std::size_t>(v)];
        centre /= 4.0;
        std::size_t near = 0;
        for (std::size_t v = g.vertex_count() - 64; v < out.vertex_count(); ++v) {
            near += std::abs((out.positions[v] - centre).norm() - 50.0 * std::sqrt(2.0)) < 1e-6;
        }
        EXPECT_EQ(near, 12u) << "plaza " << c;
    }
    // Every street that left a square now ends on its plaza: the grid's 8 x 8 - 16 x 4 streets
    // between squares and the rest, and no vertex is left without a street.
    std::vector<int> degree(out.vertex_count(), 0);
    for (const auto& [u, v] : out.edges) {
        ++degree[static_cast<std::size_t>(u)];
        ++degree[static_cast<std::size_t>(v)];
    }
    for (std::size_t v = 0; v < out.vertex_count(); ++v) EXPECT_GT(degree[v], 0) << v;
    EXPECT_EQ(out.edge_count(), g.edge_count() - 16 * 4 + 16 * 12);
    std::set<VertexId> replaced;
    for (std::uint32_t c : chosen) {
        for (VertexId v : squares->group.occurrence(c)) replaced.insert(v);
    }
    std::size_t leaving = 0;
    for (const auto& [u, v] : g.edges) leaving += replaced.count(u) != replaced.count(v) || (replaced.count(u) && replaced.count(v));
    EXPECT_EQ(report.reconnected_streets, leaving - 16 * 4); // streets with an end in a square, less the squares' own
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
