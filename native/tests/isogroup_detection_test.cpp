// Isogroup detection (paper 5.1): grids with and without noise (Fig. 14), a planted motif,
// pruned against full analysis on a real extract (Table 1), invariants and determinism.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include <tbb/global_control.h>

#include "analysis_fixtures.hpp"
#include "fixtures.hpp"
#include "ggg/analysis/isogroup_detection.hpp"
#include "ggg/analysis/analyzer.hpp"
#include "ggg/error.hpp"
#include "ggg/io/read_graph.hpp"

namespace ggg {
namespace {

using test::GridOptions;

bool is_four_cycle(const Pattern& p) {
    if (p.size() != 4 || p.edges.size() != 4) return false;
    std::array<int, 4> degree{};
    for (const auto& [u, v] : p.edges) {
        ++degree[static_cast<std::size_t>(u)];
        ++degree[static_cast<std::size_t>(v)];
    }
    return std::all_of(degree.begin(), degree.end(), [](int d) { return d == 2; });
}

// The largest group of 4-cycles.
const Isogroup* square_group(const DetectionResult& r) {
    const Isogroup* best = nullptr;
    for (const Isogroup& g : r.isogroups) {
        if (is_four_cycle(g.pattern) && (!best || g.frequency() > best->frequency())) best = &g;
    }
    return best;
}

void expect_invariants(const GeometricGraph& g, const DetectionResult& r) {
    const Adjacency adjacency(g);
    ASSERT_EQ(r.isogroups.size(), r.parents.size());
    ASSERT_EQ(r.isogroups.size(), r.scores.size());
    for (std::size_t i = 0; i < r.isogroups.size(); ++i) {
        // Every occurrence is an induced copy of the pattern, none twice, and the group's
        // transform puts each pattern vertex near its graph vertex.
        EXPECT_EQ(check_isogroup(g, adjacency, r.isogroups[i], 2.0), "") << "group " << i;
        EXPECT_GE(r.isogroups[i].frequency(), 2u);
        EXPECT_LT(r.parents[i], static_cast<long>(i));
        if (r.parents[i] >= 0) {
            EXPECT_EQ(r.isogroups[static_cast<std::size_t>(r.parents[i])].order() + 1, r.isogroups[i].order());
        }
    }
}

TEST(IsogroupDetection, RegularGridSquaresAreEverySquare) {
    const int n = 12;
    const GeometricGraph g = test::make_grid({.n = n});
    DetectionOptions o;
    o.max_order = 4;
    const DetectionResult r = detect_isogroups(g, o);
    expect_invariants(g, r);
    const Isogroup* squares = square_group(r);
    ASSERT_NE(squares, nullptr);
    EXPECT_EQ(test::occurrence_sets(*squares), test::grid_squares(n));
    // The order-2 group is every edge.
    ASSERT_FALSE(r.isogroups.empty());
    EXPECT_EQ(r.isogroups.front().order(), 2u);
    EXPECT_EQ(r.isogroups.front().frequency(), g.edge_count());
}

// Paper Fig. 14: Gaussian jitter of 5 to 20 % of the spacing, grid at an arbitrary angle.
class NoisyGrid : public ::testing::TestWithParam<double> {};

TEST_P(NoisyGrid, FindsAlmostEverySquare) {
    const int n = 25;
    for (std::uint64_t seed : {1u, 2u, 3u}) {
        const GeometricGraph g = test::make_grid({.n = n, .jitter = GetParam(), .angle_rad = 0.37 + seed, .seed = seed});
        DetectionOptions o;
        o.max_order = 4;
        const DetectionResult r = detect_isogroups(g, o);
        const Isogroup* squares = square_group(r);
        ASSERT_NE(squares, nullptr);
        const auto truth = test::grid_squares(n);
        const auto found = test::occurrence_sets(*squares);
        std::size_t hits = 0;
        for (const auto& s : found) hits += truth.count(s);

        EXPECT_EQ(hits, found.size()) << "only squares are 4-cycles in a grid";
        EXPECT_GE(static_cast<double>(hits), 0.99 * static_cast<double>(truth.size()))
            << "noise " << GetParam() << ", seed " << seed << ": " << hits << " of " << truth.size() << " squares";
    }
}

INSTANTIATE_TEST_SUITE_P(Jitter, NoisyGrid, ::testing::Values(0.05, 0.10, 0.15, 0.20));

// The group whose pattern matches the motif, or null.
const Isogroup* motif_group(const DetectionResult& r, const Pattern& motif, IsomorphismOptions::Scale mode, double size_m) {
    const Isogroup* found = nullptr;
    for (const Isogroup& g : r.isogroups) {
        if (g.order() != motif.size() || g.pattern.edges.size() != motif.edges.size()) continue;
        Pattern m = motif;
        IsomorphismOptions iso;
        iso.tolerance = 0.05;
        if (mode == IsomorphismOptions::Scale::rigid) {
            // Compare sizes in metres: the planted copies' size against the group's.
            const Spread s = spread_of(m.positions);
            m.metres_per_unit = size_m / s.rms;
            iso.mode = mode;
        }
        if (geometrically_isomorphic(m, g.pattern, iso) && (!found || g.frequency() > found->frequency())) found = &g;
    }
    return found;
}

TEST(IsogroupDetection, PlantedMotifFoundWithThePlantedCount) {
    std::vector<double> scales;
    for (int i = 0; i < 16; ++i) scales.push_back(40.0 + 3.0 * i); // RMS radius 40..85 m
    const test::PlantedMotif planted = test::plant_motif(scales, 7);
    DetectionOptions o;
    o.max_order = static_cast<int>(planted.motif.size());
    const DetectionResult r = detect_isogroups(planted.graph, o);
    expect_invariants(planted.graph, r);
    const Isogroup* group = motif_group(r, planted.motif, IsomorphismOptions::Scale::similarity, 0.0);
    ASSERT_NE(group, nullptr) << "the motif was not found";
    EXPECT_EQ(group->frequency(), scales.size());
    const auto found = test::occurrence_sets(*group);
    for (const auto& copy : planted.copies) EXPECT_TRUE(found.count(copy)) << "a planted copy is missing";
}

TEST(IsogroupDetection, RigidModeKeepsOnlyCopiesOfOneSize) {
    std::vector<double> scales(10, 60.0);
    for (int i = 0; i < 6; ++i) scales.push_back(i % 2 ? 30.0 : 110.0);
    const test::PlantedMotif planted = test::plant_motif(scales, 11);
    DetectionOptions o;
    o.max_order = static_cast<int>(planted.motif.size());
    o.scale_mode = IsomorphismOptions::Scale::rigid;
    // Ten copies of one size among 700 host streets split by size: the frequency cut would
    // stop growing them at order 3 (rigid patterns are rarer), so this is the full analysis.
    o.full = true;
    const DetectionResult r = detect_isogroups(planted.graph, o);
    expect_invariants(planted.graph, r);
    const Isogroup* group = motif_group(r, planted.motif, IsomorphismOptions::Scale::rigid, 60.0);
    ASSERT_NE(group, nullptr) << "the unscaled motif was not found";
    EXPECT_EQ(group->frequency(), 10u);
    const auto found = test::occurrence_sets(*group);
    for (std::size_t m = 0; m < 10; ++m) EXPECT_TRUE(found.count(planted.copies[m]));

    // In similarity mode all sixteen are one pattern.
    o.scale_mode = IsomorphismOptions::Scale::similarity;
    const DetectionResult any = detect_isogroups(planted.graph, o);
    const Isogroup* all = motif_group(any, planted.motif, IsomorphismOptions::Scale::similarity, 0.0);
    ASSERT_NE(all, nullptr);
    EXPECT_EQ(all->frequency(), scales.size());
}

TEST(IsogroupDetection, SameResultWhateverTheThreadCount) {
    const GeometricGraph g = test::make_grid({.n = 16, .jitter = 0.1, .angle_rad = 0.3});
    DetectionOptions o;
    o.max_order = 6;
    DetectionResult one;
    {
        tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
        one = detect_isogroups(g, o);
    }
    const DetectionResult many = detect_isogroups(g, o);
    ASSERT_EQ(one.isogroups.size(), many.isogroups.size());
    for (std::size_t i = 0; i < one.isogroups.size(); ++i) {
        EXPECT_EQ(one.isogroups[i].vertices, many.isogroups[i].vertices) << "group " << i;
        EXPECT_EQ(one.isogroups[i].pattern.positions, many.isogroups[i].pattern.positions) << "group " << i;
        EXPECT_EQ(one.parents[i], many.parents[i]);
    }
}

TEST(IsogroupDetection, StopsAtMaxOrderAndWhenNothingRepeats) {
    const GeometricGraph g = test::make_grid({.n = 6});
    DetectionOptions o;
    o.max_order = 5;
    const DetectionResult r = detect_isogroups(g, o);
    for (const Isogroup& group : r.isogroups) EXPECT_LE(group.order(), 5u);
    EXPECT_EQ(r.orders.back().order, 5);

    // A tree of distinct branch lengths repeats nothing beyond single edges and paths.
    GeometricGraph star;
    const VertexId centre = star.add_vertex({0, 0});
    for (int i = 0; i < 5; ++i) {
        const double angle = 2.0 * std::numbers::pi * i / 5.0 + 0.1 * i * i;
        const VertexId v = star.add_vertex({std::cos(angle) * (50.0 + 37.0 * i), std::sin(angle) * (50.0 + 37.0 * i)});
        star.add_edge(centre, v, {});
    }
    o.max_order = 0; // until nothing repeats
    const DetectionResult s = detect_isogroups(star, o);
    for (const Isogroup& group : s.isogroups) EXPECT_LT(group.order(), 6u);
    EXPECT_EQ(s.orders.back().groups, 0u) << "the last order tried found nothing that repeats";
}

TEST(IsogroupDetection, OptionsAreChecked) {
    const GeometricGraph g = test::make_grid({.n = 3});
    DetectionOptions o;
    o.angle_cells = 0;
    EXPECT_THROW(detect_isogroups(g, o), UsageError);
    o = {};
    o.cut = 1.0;
    EXPECT_THROW(detect_isogroups(g, o), UsageError);
    o = {};
    o.max_order = 1;
    EXPECT_THROW(detect_isogroups(g, o), UsageError);
    o = {};
    o.min_count = 0;
    EXPECT_THROW(detect_isogroups(g, o), UsageError);
    // An empty graph has nothing to find, which is not an error.
    const DetectionResult r = detect_isogroups(GeometricGraph{}, {});
    EXPECT_TRUE(r.isogroups.empty());
}

TEST(IsogroupDetection, CancelledThroughProgress) {
    const GeometricGraph g = test::make_grid({.n = 10});
    int calls = 0;
    EXPECT_THROW(detect_isogroups(g, {}, [&](double, std::string_view) { return ++calls < 3; }), Cancelled);
}

// Table 1 of the paper: the pruned analysis finds the leading patterns of the full
// analysis, with the same frequencies. Both recount their leading groups until each
// pattern is the mean of its copies, so a frequency no longer depends on the path the
// expansion took to the pattern.
TEST(IsogroupDetection, PrunedFindsTheLeadingPatternsOfTheFullAnalysisOnBarcelona) {
    GGG_REQUIRE_CORPUS();
    const GeometricGraph g = read_graph(test::shared_osm_dir() + "/barcelona_eixample.osm");
    AnalyzeOptions o;
    o.detection.max_order = 6;
    o.recount_top = 8;
    const Analysis pruned = analyze(g, o);
    o.detection.full = true;
    const Analysis full = analyze(g, o);
    ASSERT_GT(full.detected, 3 * pruned.detected) << "the full analysis grows every group";
    ASSERT_GE(full.isogroups.size(), 5u);
    IsomorphismOptions iso;
    iso.tolerance = 0.1;
    for (std::size_t i = 0; i < 5; ++i) {
        const AnalyzedIsogroup& f = full.isogroups[i];
        ASSERT_TRUE(f.recounted);
        ASSERT_GE(f.group.frequency(), 20u);
        const AnalyzedIsogroup* same = nullptr;
        for (std::size_t j = 0; j < std::min<std::size_t>(8, pruned.isogroups.size()) && !same; ++j) {
            const AnalyzedIsogroup& p = pruned.isogroups[j];
            if (p.group.order() == f.group.order() && geometrically_isomorphic(f.group.pattern, p.group.pattern, iso)) same = &p;
        }
        ASSERT_NE(same, nullptr) << "the full analysis' leading pattern " << i << " is not among the pruned one's first eight";
        const double ff = static_cast<double>(f.group.frequency());
        EXPECT_LE(std::abs(static_cast<double>(same->group.frequency()) - ff), 0.01 * ff)
            << "pattern " << i << ": full " << f.group.frequency() << ", pruned " << same->group.frequency();
    }
}

} // namespace
} // namespace ggg
