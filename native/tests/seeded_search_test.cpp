// User-seeded search and selection: the seed's copies against brute force on real
// extracts, the ranking by gain, shapes and constraints, and `ggg analyze`.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <set>

#include <nlohmann/json.hpp>

#include "analysis_fixtures.hpp"
#include "fixtures.hpp"
#include "ggg/analysis/seeded_search.hpp"
#include "ggg/analysis/analyzer.hpp"
#include "ggg/error.hpp"
#include "ggg/io/read_graph.hpp"

namespace ggg {
namespace {

// Every connected induced subgraph with k vertices (ESU enumeration), as sorted vertex sets.
std::vector<std::vector<VertexId>> connected_subgraphs(const GeometricGraph& g, std::size_t k) {
    const Adjacency adj(g);
    std::vector<std::vector<VertexId>> out;
    std::vector<VertexId> sub;
    std::function<void(std::vector<VertexId>, VertexId)> extend = [&](std::vector<VertexId> extension, VertexId root) {
        if (sub.size() == k) {
            std::vector<VertexId> s(sub);
            std::sort(s.begin(), s.end());
            out.push_back(std::move(s));
            return;
        }
        while (!extension.empty()) {
            const VertexId w = extension.back();
            extension.pop_back();
            // Exclusive neighbours of w: greater than root, not in sub, not adjacent to sub.
            std::vector<VertexId> next(extension);
            for (auto e = adj.offsets[static_cast<std::size_t>(w)]; e < adj.offsets[static_cast<std::size_t>(w) + 1]; ++e) {
                const VertexId u = adj.neighbors[static_cast<std::size_t>(e)];
                if (u <= root || std::find(sub.begin(), sub.end(), u) != sub.end() || u == w) continue;
                if (std::find(next.begin(), next.end(), u) != next.end()) continue;
                bool near_sub = false;
                for (VertexId s : sub) {
                    for (auto f = adj.offsets[static_cast<std::size_t>(s)]; f < adj.offsets[static_cast<std::size_t>(s) + 1]; ++f) {
                        near_sub = near_sub || adj.neighbors[static_cast<std::size_t>(f)] == u;
                    }
                }
                if (!near_sub) next.push_back(u);
            }
            sub.push_back(w);
            extend(next, root);
            sub.pop_back();
        }
    };
    for (VertexId v = 0; v < static_cast<VertexId>(g.vertex_count()); ++v) {
        std::vector<VertexId> extension;
        for (auto e = adj.offsets[static_cast<std::size_t>(v)]; e < adj.offsets[static_cast<std::size_t>(v) + 1]; ++e) {
            if (adj.neighbors[static_cast<std::size_t>(e)] > v) extension.push_back(adj.neighbors[static_cast<std::size_t>(e)]);
        }
        sub = {v};
        extend(extension, v);
    }
    return out;
}

// A seed of k vertices around the first vertex of degree >= 3 that has a cycle nearby, or
// the first connected k-set when there is none.
std::vector<VertexId> pick_seed(const GeometricGraph& g, std::size_t k, std::size_t edges_at_least) {
    const Adjacency adj(g);
    for (const auto& set : connected_subgraphs(g, k)) {
        std::size_t edges = 0;
        for (std::size_t i = 0; i < set.size(); ++i) {
            for (std::size_t j = i + 1; j < set.size(); ++j) {
                const auto u = static_cast<std::size_t>(set[i]);
                const auto first = adj.neighbors.begin() + adj.offsets[u];
                const auto last = adj.neighbors.begin() + adj.offsets[u + 1];
                edges += std::find(first, last, set[j]) != last;
            }
        }
        if (edges >= edges_at_least) return set;
    }
    return {};
}

void expect_brute_force_agrees(const GeometricGraph& g, const std::vector<VertexId>& seed, double tolerance) {
    ASSERT_FALSE(seed.empty());
    SeedSearchOptions o;
    o.tolerance = tolerance;
    const Isogroup found = find_occurrences(g, seed, o);
    ASSERT_GE(found.frequency(), 1u);
    // The seed itself comes first, in the seed's order.
    EXPECT_TRUE(std::equal(seed.begin(), seed.end(), found.occurrence(0).begin()));

    const Adjacency adj(g);
    const Pattern pattern = induced_pattern(g, adj, seed);
    IsomorphismOptions iso;
    iso.tolerance = tolerance;
    std::set<std::vector<VertexId>> truth;
    for (const auto& set : connected_subgraphs(g, seed.size())) {
        if (geometrically_isomorphic(pattern, induced_pattern(g, adj, set), iso)) truth.insert(set);
    }
    EXPECT_EQ(test::occurrence_sets(found), truth) << "seed of " << seed.size() << " vertices, " << truth.size() << " true copies";
    EXPECT_EQ(check_isogroup(g, adj, found, 2.0 * tolerance), "");
}

TEST(SeededSearch, FindsEveryTrueCopyOnRealExtracts) {
    GGG_REQUIRE_CORPUS();
    for (const char* name : {"krems_at.osm.gz", "paris_marais.osm.pbf"}) {
        SCOPED_TRACE(name);
        const GeometricGraph g = read_graph(test::shared_osm_dir() + "/" + name);
        // A city block (a 4-cycle), a T junction with its three arms, and a 5-vertex piece.
        expect_brute_force_agrees(g, pick_seed(g, 4, 4), 0.15);
        expect_brute_force_agrees(g, pick_seed(g, 4, 3), 0.15);
        expect_brute_force_agrees(g, pick_seed(g, 5, 4), 0.25);
    }
}

TEST(SeededSearch, GridSquareFindsEverySquare) {
    const int n = 10;
    const GeometricGraph g = test::make_grid({.n = n, .angle_rad = 0.4});
    const std::vector<VertexId> seed{0, 1, n + 1, n};
    const Isogroup found = find_occurrences(g, seed);
    EXPECT_EQ(test::occurrence_sets(found), test::grid_squares(n));
}

// A recount that starts from a poor estimate of a pattern (a skewed square, as the mean of a
// few noisy copies can be) settles on the copies of the pattern the data holds: every
// square of a jittered grid, whichever skew it started from.
TEST(SeededSearch, SettledCountDoesNotDependOnTheStartingEstimate) {
    const int n = 12;
    const GeometricGraph g = test::make_grid({.n = n, .jitter = 0.03, .angle_rad = 0.3, .seed = 5});
    auto skewed_square = [](double skew) {
        Pattern p;
        p.positions = {{0.0, 0.0}, {1.0, 0.0}, {1.0 + skew, 1.0}, {skew, 1.0}};
        p.symbols.assign(4, 0);
        p.edges = {{0, 1}, {0, 3}, {1, 2}, {2, 3}};
        const Spread s = spread_of(p.positions);
        for (Vec2& q : p.positions) q = (q - s.centroid) / s.rms;
        p.metres_per_unit = 100.0 * s.rms;
        return p;
    };
    SeedSearchOptions o;
    o.tolerance = 0.15;
    const std::set<std::vector<VertexId>> squares = test::grid_squares(n);
    const std::size_t once_left = find_pattern(g, skewed_square(0.26), o).frequency();
    const std::size_t once_right = find_pattern(g, skewed_square(-0.26), o).frequency();
    ASSERT_LT(once_left, squares.size() * 9 / 10) << "the skewed start must miss squares for the test to mean anything";
    ASSERT_LT(once_right, squares.size() * 9 / 10);
    const Isogroup left = find_settled_pattern(g, skewed_square(0.26), o);
    const Isogroup right = find_settled_pattern(g, skewed_square(-0.26), o);
    EXPECT_EQ(test::occurrence_sets(left), squares) << once_left << " " << left.frequency() << " of " << squares.size();
    EXPECT_EQ(test::occurrence_sets(right), squares) << once_right << " " << right.frequency();
    // The settled pattern is the mean of its copies: a square of the grid's spacing.
    const Pattern mean = mean_pattern(g, left);
    EXPECT_NEAR(mean.metres_per_unit, left.pattern.metres_per_unit, 1e-3 * left.pattern.metres_per_unit);
    EXPECT_NEAR(left.pattern.metres_per_unit, 100.0 / std::sqrt(2.0), 2.0);
    IsomorphismOptions iso;
    iso.tolerance = 0.03;

    EXPECT_TRUE(geometrically_isomorphic(left.pattern, skewed_square(0.0), iso));
}

TEST(SeededSearch, BadSeedsAreUsageErrors) {
    const GeometricGraph g = test::make_grid({.n = 4});
    EXPECT_THROW(find_occurrences(g, std::vector<VertexId>{}), UsageError);
    EXPECT_THROW(find_occurrences(g, std::vector<VertexId>{3}), UsageError);
    try {
        find_occurrences(g, std::vector<VertexId>{0, 15});
        ADD_FAILURE() << "a seed that is not connected was accepted";
    } catch (const UsageError& e) {
        EXPECT_NE(std::string(e.what()).find("not connected"), std::string::npos) << e.what();
    }
    EXPECT_THROW(find_occurrences(g, std::vector<VertexId>{0, 1, 10}), UsageError); // 10 hangs off nothing
    EXPECT_THROW(find_occurrences(g, std::vector<VertexId>{0, 99}), UsageError);  // not in the graph
    EXPECT_THROW(find_occurrences(g, std::vector<VertexId>{0, 1, 0}), UsageError); // repeated
}

TEST(SeededAnalysis, SeedGroupFirstThenItsGrowth) {
    const int n = 10;
    const GeometricGraph g = test::make_grid({.n = n});
    AnalyzeOptions o;
    o.seed = {0, 1, n + 1, n};
    o.detection.max_order = 6;
    const Analysis a = analyze(g, o);
    ASSERT_GE(a.isogroups.size(), 2u);
    EXPECT_EQ(a.isogroups.front().group.order(), 4u);
    EXPECT_EQ(test::occurrence_sets(a.isogroups.front().group), test::grid_squares(n));
    for (std::size_t i = 1; i < a.isogroups.size(); ++i) EXPECT_GT(a.isogroups[i].group.order(), 4u);
}

TEST(Selection, GainRanksLargeFrequentPatternsFirst) {
    EXPECT_LT(description_gain(4, 4, 1, 4), 0.0);    // once: a rule costs more than it saves
    EXPECT_LT(description_gain(2, 1, 100, 400), 0.0); // single edges are never worth a rule
    EXPECT_GT(description_gain(4, 4, 100, 800), 0.0); // grid blocks are
    EXPECT_GT(description_gain(9, 12, 10, 120), description_gain(4, 4, 10, 80));
    const GeometricGraph g = test::make_grid({.n = 12});
    AnalyzeOptions o;
    o.detection.max_order = 5;
    const Analysis a = analyze(g, o);
    for (std::size_t i = 1; i < a.isogroups.size(); ++i) {
        EXPECT_GE(a.isogroups[i - 1].selection.gain, a.isogroups[i].selection.gain);
    }
    // Non-overlapping occurrences share no vertex.
    for (const AnalyzedIsogroup& iso : a.isogroups) {
        std::set<VertexId> used;
        for (std::uint32_t i : iso.selection.non_overlapping) {
            for (VertexId v : iso.group.occurrence(i)) EXPECT_TRUE(used.insert(v).second);
        }
    }
}

TEST(Selection, ShapesAndConstraints) {
    Pattern square;
    square.positions = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    square.symbols.assign(4, 0);
    square.edges = {{0, 1}, {0, 3}, {1, 2}, {2, 3}};
    const PatternShape s = shape_of(square);
    EXPECT_NEAR(s.aspect, 1.0, 1e-9);
    EXPECT_EQ(s.leaves, 0u);
    EXPECT_NEAR(s.irregularity_deg, 0.0, 1e-9);
    Pattern path;
    path.positions = {{0, 0}, {1, 0.2}, {2, 0}};
    path.symbols.assign(3, 0);
    path.edges = {{0, 1}, {1, 2}};
    const PatternShape p = shape_of(path);
    EXPECT_LT(p.aspect, 0.2);
    EXPECT_EQ(p.leaves, 2u);
    EXPECT_GT(p.irregularity_deg, 5.0);
    SelectionConstraints c;
    c.min_aspect = 0.8;
    EXPECT_EQ(violated_constraint(s, c), "");
    EXPECT_NE(violated_constraint(p, c), "");

    const GeometricGraph g = test::make_grid({.n = 8});
    AnalyzeOptions o;
    o.detection.max_order = 5;
    o.constraints.min_aspect = 0.9;
    for (const AnalyzedIsogroup& iso : analyze(g, o).isogroups) EXPECT_GE(iso.selection.shape.aspect, 0.9);
}

TEST(AnalyzeCli, PrintsRankedIsogroupsWithOsmNodes) {
    const std::string opl = [] {
        std::string s;
        // A 6 x 6 street grid, 100 m apart at 40 N.
        for (int j = 0; j < 6; ++j) {
            for (int i = 0; i < 6; ++i) {
                s += "n" + std::to_string(1 + j * 6 + i) + " v1 x" + std::to_string(2.0 + i * 0.00117) + " y" +
                     std::to_string(40.0 + j * 0.0009) + "\n";
            }
        }
        int way = 1;
        for (int j = 0; j < 6; ++j) {
            for (int i = 0; i + 1 < 6; ++i) {
                s += "w" + std::to_string(way++) + " v1 Thighway=residential Nn" + std::to_string(1 + j * 6 + i) + ",n" +
                     std::to_string(2 + j * 6 + i) + "\n";
                s += "w" + std::to_string(way++) + " v1 Thighway=residential Nn" + std::to_string(1 + i * 6 + j) + ",n" +
                     std::to_string(7 + i * 6 + j) + "\n";
            }
        }
        return s;
    }();
    const std::string path = test::temp_file(opl, ".opl");
    const auto r = test::run_cli("analyze '" + path + "' --max-order 4 --occurrences --grid 12x10");
    ASSERT_EQ(r.code, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    ASSERT_TRUE(j.contains("seconds"));
    const auto& groups = j.at("isogroups");
    ASSERT_FALSE(groups.empty());
    for (std::size_t i = 1; i < groups.size(); ++i) EXPECT_GE(groups[i - 1].at("gain"), groups[i].at("gain"));
    bool squares = false;
    for (const auto& g : groups) {
        EXPECT_EQ(g.at("occurrence_osm_nodes").size(), g.at("occurrences").get<std::size_t>());
        if (g.at("order") == 4 && g.at("edge_count") == 4) {
            squares = true;
            EXPECT_EQ(g.at("occurrences"), 25);
            EXPECT_EQ(g.at("non_overlapping"), 9);
        }
    }
    EXPECT_TRUE(squares);

    // Seeded: the block of nodes 1, 2, 8, 7 and its copies first.
    const auto seeded = test::run_cli("analyze '" + path + "' --max-order 5 --seed-osm-nodes 1,2,8,7 --occurrences");
    ASSERT_EQ(seeded.code, 0) << seeded.err;
    const auto s = nlohmann::json::parse(seeded.out).at("isogroups");
    ASSERT_FALSE(s.empty());
    EXPECT_EQ(s[0].at("order"), 4);
    EXPECT_EQ(s[0].at("occurrences"), 25);
    EXPECT_EQ(s[0].at("occurrence_osm_nodes")[0], (nlohmann::json{1, 2, 8, 7}));

    // Bad usage.
    EXPECT_EQ(test::run_cli("analyze '" + path + "' --grid 12by10").code, 2);
    EXPECT_EQ(test::run_cli("analyze '" + path + "' --seed-osm-nodes 1,999").code, 2);
    EXPECT_EQ(test::run_cli("analyze '" + path + "' --scale huge").code, 2);
    EXPECT_EQ(test::run_cli("analyze /no/such/file.osm").code, 1);
}

} // namespace
} // namespace ggg

namespace ggg {

namespace {

// A 30 x 30 street grid of 100 m blocks whose every vertex is moved by up to 20 m along each
// axis (uniform): 841 squares, each one visibly a different shape from its neighbours.
GeometricGraph noisy_grid(int n, std::uint64_t seed) {
    std::mt19937_64 random(seed);
    std::uniform_real_distribution<double> noise(-20.0, 20.0);
    GeometricGraph g;
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) g.add_vertex({100.0 * i + noise(random), 100.0 * j + noise(random)});
    }
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            if (i + 1 < n) g.add_edge(j * n + i, j * n + i + 1, {});
            if (j + 1 < n) g.add_edge(j * n + i, (j + 1) * n + i, {});
        }
    }
    return g;
}

std::set<std::vector<VertexId>> vertex_sets(const Isogroup& group) { return test::occurrence_sets(group); }

} // namespace

// Find Similar agrees with the analysis: from one block of a noisy grid, where the automatic
// analysis groups all 841 squares, it finds them all at the default tolerance (the seed search
// alone, comparing every square with the one noisy seed, finds a sixth to three quarters of
// them, as square as the seed happens to be), with the seed
// first and a transform that puts each copy's vertices where they are.
TEST(FindSimilar, FindsEveryCopyTheAnalysisGroupsWithTheSeed) {
    const int n = 30;
    std::size_t exact_total = 0;
    for (std::uint64_t seed : {1u, 2u, 3u}) {
        const GeometricGraph g = noisy_grid(n, seed);
        const std::vector<VertexId> block{15 * n + 15, 15 * n + 16, 16 * n + 16, 16 * n + 15};
        const Isogroup exact = find_occurrences(g, block);
        const Isogroup similar = find_similar(g, block);
        const std::set<std::vector<VertexId>> squares = test::grid_squares(n);
        ASSERT_EQ(squares.size(), 841u);
        exact_total += exact.frequency();
        EXPECT_GE(similar.frequency(), squares.size() * 99 / 100) << "seed " << seed;
        const std::set<std::vector<VertexId>> found = vertex_sets(similar);
        for (const auto& square : found) EXPECT_TRUE(squares.count(square)) << "not a block of the grid";
        for (const auto& copy : vertex_sets(exact)) EXPECT_TRUE(found.count(copy)) << "a copy the seed search finds is missing";
        EXPECT_TRUE(std::equal(block.begin(), block.end(), similar.occurrence(0).begin()));
        // 20 m of noise on each axis: no vertex is more than about 60 m from its transformed
        // pattern vertex, relative to the block's RMS radius of 71 m.
        const Adjacency adj(g);
        EXPECT_EQ(check_isogroup(g, adj, similar, 0.9), "");
    }
    // How many the seed search alone finds depends on how square the seed block happens to be
    // (131 to 649 here): it must miss many for the test to mean anything.
    EXPECT_LT(exact_total, 3 * 841 * 2 / 3);
}

// On real streets: every copy that the analysis groups with a block of the Marais, and every
// copy the seed search finds, is among what Find Similar finds.
TEST(FindSimilar, ContainsTheAnalysisGroupOfARealBlock) {
    GGG_REQUIRE_CORPUS();
    const GeometricGraph g = read_graph(test::shared_osm_dir() + "/paris_marais.osm.pbf");
    AnalyzeOptions options;
    options.detection.max_order = 4;
    const Analysis analysis = analyze(g, options);
    const Isogroup* blocks = nullptr;
    for (const AnalyzedIsogroup& a : analysis.isogroups) {
        if (a.group.order() == 4 && a.group.pattern.edges.size() == 4 && a.group.frequency() >= 5) {
            blocks = &a.group;
            break;
        }
    }
    ASSERT_NE(blocks, nullptr) << "the Marais has blocks of four streets";
    const auto first = blocks->occurrence(0);
    const std::vector<VertexId> seed(first.begin(), first.end());
    const std::set<std::vector<VertexId>> found = vertex_sets(find_similar(g, seed, options));
    for (const auto& copy : vertex_sets(*blocks)) EXPECT_TRUE(found.count(copy));
    for (const auto& copy : vertex_sets(find_occurrences(g, seed))) EXPECT_TRUE(found.count(copy));
}

} // namespace ggg
