// Patterns, least-squares similarity and geometric isomorphism (paper 3.1).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <cstdio>
#include <random>

#include "ggg/analysis/geometric_isomorphism.hpp"
#include "ggg/analysis/pattern.hpp"
#include "ggg/error.hpp"

using namespace ggg;

namespace {

constexpr double deg = M_PI / 180.0;
using Edges = std::vector<std::array<int, 2>>;

Pattern make_pattern(std::vector<Vec2> positions, Edges edges, std::vector<Symbol> symbols = {}) {
    Pattern p;
    p.positions = std::move(positions);
    p.symbols = symbols.empty() ? std::vector<Symbol>(p.positions.size(), 0) : std::move(symbols);
    for (auto& e : edges) {
        if (e[0] > e[1]) std::swap(e[0], e[1]);
    }
    std::sort(edges.begin(), edges.end());
    p.edges = std::move(edges);
    return p;
}

// The image of `p` under `t`, vertex i landing at index perm[i].
Pattern image(const Pattern& p, const Similarity2& t, const std::vector<int>& perm) {
    Pattern q;
    q.positions.resize(p.size());
    q.symbols.resize(p.size());
    q.metres_per_unit = p.metres_per_unit;
    for (std::size_t i = 0; i < p.size(); ++i) {
        q.positions[static_cast<std::size_t>(perm[i])] = t.apply(p.positions[i]);
        q.symbols[static_cast<std::size_t>(perm[i])] = p.symbols[i];
    }
    Edges edges;
    for (const auto& [u, v] : p.edges) edges.push_back({perm[static_cast<std::size_t>(u)], perm[static_cast<std::size_t>(v)]});
    return make_pattern(q.positions, edges, q.symbols);
}

std::vector<int> identity_perm(std::size_t k) {
    std::vector<int> perm(k);
    std::iota(perm.begin(), perm.end(), 0);
    return perm;
}

// Largest |match.transform(a_i) - b_mapping[i]| in b's coordinates.
double worst_distance(const Pattern& a, const Pattern& b, const IsomorphismMatch& m) {
    double worst = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        worst = std::max(worst, (m.transform.apply(a.positions[i]) - b.positions[static_cast<std::size_t>(m.mapping[i])]).norm());
    }
    return worst;
}

double rms_radius(const Pattern& p) {
    Vec2 c = Vec2::Zero();
    for (const Vec2& v : p.positions) c += v;
    c /= static_cast<double>(p.size());
    double s = 0.0;
    for (const Vec2& v : p.positions) s += (v - c).squaredNorm();
    return std::sqrt(s / static_cast<double>(p.size()));
}

double angle_mod(double angle, double period) {
    double r = std::fmod(angle, period);
    if (r < 0) r += period;
    return std::min(r, period - r);
}

Pattern unit_square() { return make_pattern({{0, 0}, {1, 0}, {1, 1}, {0, 1}}, {{0, 1}, {1, 2}, {2, 3}, {0, 3}}); }

// A street-like pattern without symmetry: a crossing with arms of different lengths and a
// block behind it.
Pattern crossing() {
    return make_pattern({{0, 0}, {3, 0.2}, {-2, 0}, {0.1, 2.5}, {0, -1.5}, {3, 2.5}, {4.5, 0.3}, {3.1, -1.2}},
                        {{0, 1}, {0, 2}, {0, 3}, {0, 4}, {1, 5}, {3, 5}, {1, 6}, {1, 7}});
}

const Similarity2 some_transform = Similarity2::from(3.2, 37 * deg, Vec2(250.0, -120.0));

} // namespace

TEST(GeometricIsomorphism, SquareRotatedScaledTranslatedPermuted) {
    const Pattern a = unit_square();
    const std::vector<int> perm{2, 0, 3, 1};
    const Pattern b = image(a, some_transform, perm);
    const auto m = geometrically_isomorphic(a, b);
    ASSERT_TRUE(m);
    EXPECT_LT(worst_distance(a, b, *m), 1e-9);
    EXPECT_NEAR(m->transform.scale(), 3.2, 1e-12);
    // A square maps onto itself four ways; each is a rotation by 37 + n * 90 degrees.
    EXPECT_NEAR(angle_mod(m->transform.angle() - 37 * deg, 90 * deg), 0.0, 1e-12);
    bool cyclic_shift = false;
    for (int s = 0; s < 4; ++s) {
        bool all = true;
        for (int i = 0; i < 4; ++i) all = all && m->mapping[static_cast<std::size_t>(i)] == perm[static_cast<std::size_t>((i + s) % 4)];
        cyclic_shift = cyclic_shift || all;
    }
    EXPECT_TRUE(cyclic_shift) << "the mapping must be a rotation of the square, never a reflection";
    EXPECT_LT(m->max_residual, 1e-9);
}

TEST(GeometricIsomorphism, MarkedSquareGivesTheExactMappingAndTransform) {
    Pattern a = unit_square();
    a.symbols[1] = 7; // breaks the symmetry
    const std::vector<int> perm{2, 0, 3, 1};
    const Pattern b = image(a, some_transform, perm);
    const auto m = geometrically_isomorphic(a, b);
    ASSERT_TRUE(m);
    EXPECT_EQ(m->mapping, perm);
    EXPECT_NEAR(m->transform.a, some_transform.a, 1e-12);
    EXPECT_NEAR(m->transform.b, some_transform.b, 1e-12);
    EXPECT_NEAR((m->transform.t - some_transform.t).norm(), 0.0, 1e-9);
}

TEST(GeometricIsomorphism, DiagonalChangesTheTopology) {
    const Pattern a = unit_square();
    Pattern b = unit_square();
    b.edges = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {2, 3}};
    EXPECT_FALSE(geometrically_isomorphic(a, b));
    EXPECT_FALSE(geometrically_isomorphic(b, a));
    EXPECT_NE(invariant_hash(a), invariant_hash(b));
    // The two diagonals are the same pattern turned by 90 degrees.
    Pattern c = unit_square();
    c.edges = {{0, 1}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
    EXPECT_TRUE(geometrically_isomorphic(b, c));
}

TEST(GeometricIsomorphism, SameInvariantsDifferentAdjacency) {
    // A hexagon ring and two triangles on the same six points: every vertex has degree 2 and
    // every edge joins two degree-2 vertices, so only the adjacency search can tell them apart.
    std::vector<Vec2> hexagon;
    for (int i = 0; i < 6; ++i) hexagon.emplace_back(std::cos(i * 60 * deg), std::sin(i * 60 * deg));
    const Pattern ring = make_pattern(hexagon, {{0, 1}, {1, 2}, {2, 3}, {3, 4}, {4, 5}, {0, 5}});
    const Pattern triangles = make_pattern(hexagon, {{0, 2}, {2, 4}, {0, 4}, {1, 3}, {3, 5}, {1, 5}});
    EXPECT_EQ(invariant_hash(ring), invariant_hash(triangles));
    EXPECT_FALSE(geometrically_isomorphic(ring, triangles));
    EXPECT_TRUE(geometrically_isomorphic(ring, image(ring, some_transform, {3, 5, 1, 0, 2, 4})));
}

TEST(GeometricIsomorphism, MirrorImageIsAnotherPattern) {
    // An L with arms 2 and 1, plus a vertex in the long arm.
    const Pattern l = make_pattern({{0, 0}, {1, 0}, {2, 0}, {0, 1}}, {{0, 1}, {1, 2}, {0, 3}});
    Pattern mirrored = l;
    for (Vec2& p : mirrored.positions) p.x() = -p.x();
    const std::vector<int> perm{3, 1, 0, 2};
    EXPECT_FALSE(geometrically_isomorphic(l, mirrored));
    EXPECT_FALSE(geometrically_isomorphic(l, image(mirrored, some_transform, perm)));
    IsomorphismOptions loose;
    loose.tolerance = 0.3;
    EXPECT_FALSE(geometrically_isomorphic(l, image(mirrored, some_transform, perm), loose));
    EXPECT_TRUE(geometrically_isomorphic(l, image(l, some_transform, perm)));
}

TEST(GeometricIsomorphism, NoiseWithinToleranceOnly) {
    const Pattern a = crossing();
    const double size = rms_radius(a);
    Pattern jittered = a;
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> angle(0.0, 2 * M_PI);
    for (Vec2& p : jittered.positions) {
        const double t = angle(rng);
        p += 0.02 * size * Vec2(std::cos(t), std::sin(t));
    }
    const Pattern b = image(jittered, some_transform, {5, 2, 7, 0, 1, 4, 6, 3});
    IsomorphismOptions options;
    options.tolerance = 0.05;
    const auto m = geometrically_isomorphic(a, b, options);
    ASSERT_TRUE(m);
    EXPECT_EQ(m->mapping, (std::vector<int>{5, 2, 7, 0, 1, 4, 6, 3}));
    EXPECT_LE(m->max_residual, 0.05);
    EXPECT_GT(m->max_residual, 0.005);
    EXPECT_LE(m->rms_residual, m->max_residual);
    EXPECT_NEAR(m->transform.scale(), 3.2, 0.1);
    options.tolerance = 0.005;
    EXPECT_FALSE(geometrically_isomorphic(a, b, options));
}

TEST(GeometricIsomorphism, RigidAndRangeCompareRealSizes) {
    const Pattern a = crossing(); // metres
    const Pattern twice = image(a, Similarity2::from(2.0, 20 * deg, Vec2(10, 10)), {1, 0, 2, 3, 4, 5, 6, 7});
    const Pattern turned = image(a, Similarity2::from(1.0, 120 * deg, Vec2(-40, 3)), {1, 0, 2, 3, 4, 5, 6, 7});
    IsomorphismOptions rigid;
    rigid.mode = IsomorphismOptions::Scale::rigid;
    EXPECT_FALSE(geometrically_isomorphic(a, twice, rigid));
    const auto same = geometrically_isomorphic(a, turned, rigid);
    ASSERT_TRUE(same);
    EXPECT_NEAR(same->transform.scale(), 1.0, 1e-12);
    EXPECT_NEAR(same->transform.angle(), 120 * deg, 1e-12);

    EXPECT_TRUE(geometrically_isomorphic(a, twice));
    IsomorphismOptions range;
    range.mode = IsomorphismOptions::Scale::range;
    EXPECT_TRUE(geometrically_isomorphic(a, twice, range));   // ratio 2 in [0.5, 2]
    EXPECT_TRUE(geometrically_isomorphic(twice, a, range));   // ratio 0.5
    range.max_scale = 1.9;
    EXPECT_FALSE(geometrically_isomorphic(a, twice, range));
    EXPECT_TRUE(geometrically_isomorphic(twice, a, range));
}

TEST(GeometricIsomorphism, RigidUsesTheSizeKeptByInducedPattern) {
    // The same block twice, once 100 m and once 200 m wide: canonical coordinates are equal,
    // metres_per_unit tells them apart.
    GeometricGraph g;
    for (double s : {100.0, 200.0}) {
        const Vec2 o(s * 5, 0);
        const VertexId v0 = g.add_vertex(o);
        const VertexId v1 = g.add_vertex(o + Vec2(s, 0));
        const VertexId v2 = g.add_vertex(o + Vec2(s, 0.6 * s));
        const VertexId v3 = g.add_vertex(o + Vec2(0, 0.6 * s));
        g.add_edge(v0, v1, {});
        g.add_edge(v1, v2, {});
        g.add_edge(v2, v3, {});
        g.add_edge(v3, v0, {});
    }
    const std::vector<VertexId> small{0, 1, 2, 3}, large{4, 5, 6, 7};
    const Pattern a = induced_pattern(g, small), b = induced_pattern(g, large);
    IsomorphismOptions rigid;
    rigid.mode = IsomorphismOptions::Scale::rigid;
    EXPECT_TRUE(geometrically_isomorphic(a, b));
    EXPECT_FALSE(geometrically_isomorphic(a, b, rigid));
    EXPECT_TRUE(geometrically_isomorphic(a, induced_pattern(g, small), rigid));
    IsomorphismOptions range;
    range.mode = IsomorphismOptions::Scale::range;
    range.min_scale = 1.5;
    range.max_scale = 2.5;
    const auto m = geometrically_isomorphic(a, b, range);
    ASSERT_TRUE(m);
    EXPECT_NEAR(m->transform.scale(), 1.0, 1e-12); // canonical to canonical
    EXPECT_FALSE(geometrically_isomorphic(b, a, range));
}

TEST(GeometricIsomorphism, SymbolsMustAgreeUnlessIgnored) {
    const Pattern a = crossing();
    Pattern b = image(a, some_transform, identity_perm(a.size()));
    b.symbols[5] = 3;
    EXPECT_FALSE(geometrically_isomorphic(a, b));
    IsomorphismOptions ignore;
    ignore.respect_symbols = false;
    EXPECT_TRUE(geometrically_isomorphic(a, b, ignore));
    EXPECT_NE(invariant_hash(a), invariant_hash(b));
    EXPECT_EQ(invariant_hash(a, false), invariant_hash(b, false));
}

TEST(GeometricIsomorphism, InducedPatternTakesExactlyTheInducedEdges) {
    //  3 --- 4       5
    //  |  \  |
    //  0 --- 1 --- 2
    GeometricGraph g;
    g.add_vertex({0, 0});
    g.add_vertex({100, 0});
    g.add_vertex({200, 0});
    g.add_vertex({0, 100});
    g.add_vertex({100, 100});
    g.add_vertex({300, 100});
    for (auto [u, v] : std::vector<std::array<VertexId, 2>>{{0, 1}, {1, 2}, {3, 4}, {0, 3}, {1, 4}, {3, 1}, {2, 5}}) {
        g.add_edge(u, v, {});
    }
    g.symbols[4] = 9;
    const std::vector<VertexId> vertices{4, 0, 1, 3};
    Similarity2 frame;
    const Pattern p = induced_pattern(g, vertices, &frame);
    // Local ids: 4 -> 0, 0 -> 1, 1 -> 2, 3 -> 3. Induced: 0-1 (1,2), 0-3 (1,3), 1-4 (0,2),
    // 3-4 (0,3), 3-1 (2,3); not 1-2 or 2-5.
    EXPECT_EQ(p.edges, (Edges{{0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}}));
    EXPECT_EQ(p.symbols, (std::vector<Symbol>{9, 0, 0, 0}));
    EXPECT_EQ(check_pattern(p), "");
    EXPECT_NEAR(rms_radius(p), 1.0, 1e-12);
    EXPECT_NEAR(p.metres_per_unit, std::sqrt(2.0) * 50.0, 1e-9);
    EXPECT_NEAR(frame.angle(), 0.0, 0.0);
    for (std::size_t i = 0; i < vertices.size(); ++i) {
        EXPECT_NEAR((frame.apply(p.positions[i]) - g.positions[static_cast<std::size_t>(vertices[i])]).norm(), 0.0, 1e-9);
    }
    const Adjacency adjacency(g);
    const Pattern q = induced_pattern(g, adjacency, vertices);
    EXPECT_EQ(q.edges, p.edges);
    EXPECT_EQ(q.symbols, p.symbols);
    EXPECT_EQ(q.metres_per_unit, p.metres_per_unit);

    EXPECT_THROW(induced_pattern(g, std::vector<VertexId>{}), UsageError);
    EXPECT_THROW(induced_pattern(g, std::vector<VertexId>{0, 6}), UsageError);
    EXPECT_THROW(induced_pattern(g, std::vector<VertexId>{-1}), UsageError);
    EXPECT_THROW(induced_pattern(g, adjacency, std::vector<VertexId>{1, 2, 1}), UsageError);
    GeometricGraph other;
    other.add_vertex({0, 0});
    EXPECT_THROW(induced_pattern(g, Adjacency(other), vertices), UsageError);
}

TEST(GeometricIsomorphism, FitSimilarityRecoversAKnownTransform) {
    const std::vector<Vec2> from{{0, 0}, {10, 0}, {3, 7}, {-4, 2}, {5, 5}};
    const Similarity2 t = Similarity2::from(0.37, -141 * deg, Vec2(1000.5, -20.25));
    std::vector<Vec2> to;
    for (const Vec2& p : from) to.push_back(t.apply(p));
    const SimilarityFit fit = fit_similarity(from, to);
    EXPECT_NEAR(fit.transform.a, t.a, 1e-14);
    EXPECT_NEAR(fit.transform.b, t.b, 1e-14);
    EXPECT_NEAR((fit.transform.t - t.t).norm(), 0.0, 1e-10);
    EXPECT_LT(fit.rms_residual, 1e-10);

    // A mirror image cannot be fitted: the residual stays.
    std::vector<Vec2> mirrored;
    for (const Vec2& p : from) mirrored.push_back(Vec2(-p.x(), p.y()));
    EXPECT_GT(fit_similarity(from, mirrored).rms_residual, 1.0);

    // All sources at one point: the best fit is the translation between the centroids.
    const std::vector<Vec2> point(3, Vec2(5, 5));
    const SimilarityFit translation = fit_similarity(point, std::vector<Vec2>{{0, 0}, {2, 0}, {1, 3}});
    EXPECT_EQ(translation.transform.a, 1.0);
    EXPECT_EQ(translation.transform.b, 0.0);
    EXPECT_NEAR((translation.transform.apply(Vec2(5, 5)) - Vec2(1, 1)).norm(), 0.0, 1e-12);
    EXPECT_TRUE(std::isfinite(translation.rms_residual));

    EXPECT_THROW(fit_similarity(std::vector<Vec2>{}, std::vector<Vec2>{}), UsageError);
    EXPECT_THROW(fit_similarity(from, std::span<const Vec2>(to).first(2)), UsageError);
}

TEST(GeometricIsomorphism, SmallAndDegeneratePatterns) {
    const Pattern one = make_pattern({{5, 5}}, {});
    EXPECT_TRUE(geometrically_isomorphic(one, make_pattern({{-3, 8}}, {})));
    EXPECT_FALSE(geometrically_isomorphic(one, make_pattern({{-3, 8}}, {}, {2})));
    const auto shift = geometrically_isomorphic(one, make_pattern({{-3, 8}}, {}));
    ASSERT_TRUE(shift);
    EXPECT_NEAR((shift->transform.apply(Vec2(5, 5)) - Vec2(-3, 8)).norm(), 0.0, 1e-12);

    const Pattern edge = make_pattern({{0, 0}, {1, 0}}, {{0, 1}});
    const Pattern turned_edge = image(edge, some_transform, {1, 0});
    const auto m = geometrically_isomorphic(edge, turned_edge);
    ASSERT_TRUE(m);
    // An edge maps onto itself turned by 180 degrees: either mapping is right.
    EXPECT_LT(worst_distance(edge, turned_edge, *m), 1e-12);
    EXPECT_NEAR(m->transform.scale(), 3.2, 1e-12);
    EXPECT_NEAR(angle_mod(m->transform.angle() - 37 * deg, 180 * deg), 0.0, 1e-12);
    EXPECT_LT(m->max_residual, 1e-12);
    Pattern marked_edge = edge;
    marked_edge.symbols[0] = 1;
    const auto marked = geometrically_isomorphic(marked_edge, image(marked_edge, some_transform, {1, 0}));
    ASSERT_TRUE(marked);
    EXPECT_EQ(marked->mapping, (std::vector<int>{1, 0}));
    EXPECT_FALSE(geometrically_isomorphic(edge, make_pattern({{0, 0}, {1, 0}}, {})));

    // All vertices at one point: topology and symbols alone decide.
    const Pattern pile = make_pattern({{2, 2}, {2, 2}, {2, 2}}, {{0, 1}, {1, 2}});
    const Pattern other_pile = make_pattern({{7, 1}, {7, 1}, {7, 1}}, {{0, 2}, {1, 2}});
    const auto piles = geometrically_isomorphic(pile, other_pile);
    ASSERT_TRUE(piles);
    EXPECT_EQ(piles->mapping[1], 2); // the middle of the path
    EXPECT_FALSE(geometrically_isomorphic(pile, make_pattern({{7, 1}, {7, 1}, {7, 1}}, {{0, 1}, {0, 2}, {1, 2}})));
    EXPECT_FALSE(geometrically_isomorphic(pile, make_pattern({{0, 0}, {1, 0}, {2, 0}}, {{0, 1}, {1, 2}})));
    EXPECT_FALSE(geometrically_isomorphic(make_pattern({{0, 0}, {1, 0}, {2, 0}}, {{0, 1}, {1, 2}}), pile));
    IsomorphismOptions rigid;
    rigid.mode = IsomorphismOptions::Scale::rigid;
    EXPECT_TRUE(geometrically_isomorphic(pile, other_pile, rigid));

    // Two vertices at one place inside a proper pattern.
    const Pattern twin = make_pattern({{0, 0}, {0, 0}, {1, 0}, {0, 1}}, {{0, 2}, {1, 3}, {2, 3}});
    EXPECT_TRUE(geometrically_isomorphic(twin, image(twin, some_transform, {2, 3, 0, 1})));
}

TEST(GeometricIsomorphism, BadArgumentsAreUsageErrors) {
    const Pattern a = unit_square();
    IsomorphismOptions o;
    o.tolerance = -0.1;
    EXPECT_THROW(geometrically_isomorphic(a, a, o), UsageError);
    o.tolerance = std::nan("");
    EXPECT_THROW(geometrically_isomorphic(a, a, o), UsageError);
    o = {};
    o.mode = IsomorphismOptions::Scale::range;
    o.min_scale = 2.0;
    o.max_scale = 1.0;
    EXPECT_THROW(geometrically_isomorphic(a, a, o), UsageError);
    o.min_scale = 0.0;
    EXPECT_THROW(geometrically_isomorphic(a, a, o), UsageError);

    auto broken = [&](auto edit) {
        Pattern p = a;
        edit(p);
        EXPECT_NE(check_pattern(p), "");
        EXPECT_THROW(geometrically_isomorphic(a, p), UsageError);
        EXPECT_THROW(geometrically_isomorphic(p, a), UsageError);
        EXPECT_THROW(invariant_hash(p), UsageError);
    };
    broken([](Pattern& p) { p.edges = {{1, 2}, {0, 1}, {2, 3}, {0, 3}}; });  // unsorted
    broken([](Pattern& p) { p.edges = {{0, 1}, {0, 1}, {2, 3}, {0, 3}}; });  // repeated
    broken([](Pattern& p) { p.edges = {{1, 0}, {1, 2}, {2, 3}, {0, 3}}; });  // wrong way round
    broken([](Pattern& p) { p.edges = {{0, 1}, {1, 2}, {2, 4}, {0, 3}}; });  // out of range
    broken([](Pattern& p) { p.edges = {{0, 0}, {1, 2}, {2, 3}, {0, 3}}; });  // loop
    broken([](Pattern& p) { p.symbols.pop_back(); });
    broken([](Pattern& p) { p.positions[2].y() = std::numeric_limits<double>::infinity(); });
    broken([](Pattern& p) { p.metres_per_unit = 0.0; });
    broken([](Pattern& p) { p = Pattern{}; });
}

TEST(GeometricIsomorphism, RandomPatternsMatchTheirImagesButNotDistortions) {
    std::mt19937 rng(20240611);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    int matched = 0, false_positives = 0, anywhere_accepted = 0, exact_mappings = 0;
    const int trials = 200;
    for (int trial = 0; trial < trials; ++trial) {
        // Planar-ish: points at least 0.2 apart in the unit square, each joined to its nearest
        // earlier point (a tree), plus some short extra edges.
        const int k = 3 + trial % 6;
        std::vector<Vec2> points;
        while (static_cast<int>(points.size()) < k) {
            const Vec2 p(unit(rng), unit(rng));
            bool apart = true;
            for (const Vec2& q : points) apart = apart && (p - q).norm() >= 0.2;
            if (apart) points.push_back(p);
        }
        Edges edges;
        for (int i = 1; i < k; ++i) {
            int nearest = 0;
            for (int j = 1; j < i; ++j) {
                if ((points[static_cast<std::size_t>(j)] - points[static_cast<std::size_t>(i)]).norm() <
                    (points[static_cast<std::size_t>(nearest)] - points[static_cast<std::size_t>(i)]).norm()) nearest = j;
            }
            edges.push_back({nearest, i});
            for (int j = 0; j < i; ++j) {
                if (j != nearest && (points[static_cast<std::size_t>(j)] - points[static_cast<std::size_t>(i)]).norm() < 0.45 && unit(rng) < 0.3) {
                    edges.push_back({j, i});
                }
            }
        }
        const Pattern a = make_pattern(points, edges);
        std::vector<int> perm = identity_perm(a.size());
        std::shuffle(perm.begin(), perm.end(), rng);
        const Similarity2 t = Similarity2::from(std::exp(std::log(100.0) * (unit(rng) - 0.5) * 2), 2 * M_PI * unit(rng),
                                                Vec2(2000 * unit(rng) - 1000, 2000 * unit(rng) - 1000));
        const Pattern b = image(a, t, perm);

        ASSERT_EQ(invariant_hash(a), invariant_hash(b));
        const auto m = geometrically_isomorphic(a, b);
        const auto back = geometrically_isomorphic(b, a);
        EXPECT_TRUE(back) << "trial " << trial;
        if (m) {
            ++matched;
            EXPECT_LT(m->max_residual, 1e-9) << "trial " << trial;
            EXPECT_LT(worst_distance(a, b, *m), 1e-9 * t.scale()) << "trial " << trial;
            exact_mappings += m->mapping == perm ? 1 : 0;
        }

        // One vertex moved by 30 % of the pattern's RMS radius. Moving a vertex far out from
        // the centroid can be mostly a rotation and scale of the whole (see
        // MovingAnOutlyingVertexCanBeASimilarity), so the vertex is one within the RMS radius:
        // then at least (1 - 2/k) of the move is a change of shape, and the least-squares
        // residual, a lower bound for any similarity, is above the tolerance.
        const double phi = 2 * M_PI * unit(rng);
        const Vec2 shift = 0.3 * rms_radius(b) * Vec2(std::cos(phi), std::sin(phi));
        Vec2 centroid = Vec2::Zero();
        for (const Vec2& p : b.positions) centroid += p;
        centroid /= static_cast<double>(b.size());
        std::vector<std::size_t> inner;
        for (std::size_t i = 0; i < b.size(); ++i) {
            if ((b.positions[i] - centroid).norm() <= rms_radius(b)) inner.push_back(i);
        }
        ASSERT_FALSE(inner.empty());
        Pattern moved = b;
        moved.positions[inner[rng() % inner.size()]] += shift;
        std::vector<Vec2> a_in_b_order(b.size());
        for (std::size_t i = 0; i < a.size(); ++i) a_in_b_order[static_cast<std::size_t>(perm[i])] = a.positions[i];
        EXPECT_GT(fit_similarity(a_in_b_order, moved.positions).rms_residual / rms_radius(moved), 0.08) << "trial " << trial;
        if (geometrically_isomorphic(a, moved)) ++false_positives;

        // Any vertex moved: what passes must be within the tolerance by least squares too.
        Pattern anywhere = b;
        anywhere.positions[rng() % b.size()] += shift;
        if (geometrically_isomorphic(a, anywhere)) {
            ++anywhere_accepted;
            EXPECT_LE(fit_similarity(a_in_b_order, anywhere.positions).rms_residual / rms_radius(anywhere), 0.05)
                << "trial " << trial;
        }
    }
    std::printf("distorted patterns accepted: %d of %d with an inner vertex moved, %d of %d with any vertex moved\n",
                false_positives, trials, anywhere_accepted, trials);
    EXPECT_EQ(matched, trials);
    EXPECT_EQ(exact_mappings, trials); // random patterns have no symmetry
    EXPECT_EQ(false_positives, 0) << false_positives << " of " << trials << " distorted patterns passed at tolerance 0.05";
}

TEST(GeometricIsomorphism, MovingAnOutlyingVertexCanBeASimilarity) {
    // Two vertices close together and one far away: moving the far one by 30 % of the RMS
    // radius mostly turns and scales the whole, so the shapes stay within 5 %. Moving a near
    // one by as much is a real change of shape.
    const Pattern thin = make_pattern({{0.34, 0.16}, {0.53, 0.01}, {0.87, 0.76}}, {{0, 1}, {0, 2}});
    const double shift = 0.3 * rms_radius(thin);
    Pattern far_moved = thin;
    far_moved.positions[2] += shift * Vec2(-0.6, 0.8);
    EXPECT_TRUE(geometrically_isomorphic(thin, far_moved));
    EXPECT_LE(fit_similarity(thin.positions, far_moved.positions).rms_residual / rms_radius(far_moved), 0.05);
    Pattern near_moved = thin;
    near_moved.positions[1] += shift * Vec2(-0.6, 0.8);
    EXPECT_FALSE(geometrically_isomorphic(thin, near_moved));
}

TEST(GeometricIsomorphism, DecisionIsSymmetric) {
    // Near the tolerance, which pattern comes first must not matter (merging order).
    std::mt19937 rng(99);
    std::normal_distribution<double> noise(0.0, 0.025);
    const Pattern a = crossing();
    const double size = rms_radius(a);
    int yes = 0;
    for (int trial = 0; trial < 300; ++trial) {
        Pattern b = a;
        for (Vec2& p : b.positions) p += size * Vec2(noise(rng), noise(rng));
        b = image(b, some_transform, {7, 6, 5, 4, 3, 2, 1, 0});
        for (auto mode : {IsomorphismOptions::Scale::similarity, IsomorphismOptions::Scale::rigid}) {
            IsomorphismOptions o;
            o.mode = mode;
            if (mode == IsomorphismOptions::Scale::rigid) b = image(b, some_transform.inverse(), identity_perm(b.size()));
            const auto ab = geometrically_isomorphic(a, b, o);
            const auto ba = geometrically_isomorphic(b, a, o);
            ASSERT_EQ(ab.has_value(), ba.has_value()) << "trial " << trial;
            if (ab) {
                ++yes;
                EXPECT_NEAR(ab->max_residual, ba->max_residual, 1e-9);
            }
        }
    }
    // The noise is chosen so that both answers occur.
    EXPECT_GT(yes, 20);
    EXPECT_LT(yes, 580);
}

TEST(GeometricIsomorphism, TenVertexGridPatches) {
    // A 6 x 5 street grid with 80 m blocks; 2 x 5 windows of it are the same pattern whether
    // lying or standing, a 3 x 4 window missing two corners is not.
    GeometricGraph g;
    const int w = 6, h = 5;
    auto id = [&](int x, int y) { return static_cast<VertexId>(y * w + x); };
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) g.add_vertex(Vec2(80.0 * x, 80.0 * y));
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            if (x + 1 < w) g.add_edge(id(x, y), id(x + 1, y), {});
            if (y + 1 < h) g.add_edge(id(x, y), id(x, y + 1), {});
        }
    const Adjacency adjacency(g);
    std::vector<VertexId> lying, standing, other;
    for (int x = 0; x < 5; ++x) {
        lying.push_back(id(x + 1, 2));
        lying.push_back(id(x + 1, 3));
    }
    for (int y = 4; y >= 0; --y) { // another order, to make the mapping nontrivial
        standing.push_back(id(4, y));
        standing.push_back(id(3, y));
    }
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 3; ++x)
            if (!((x == 0 && y == 0) || (x == 2 && y == 3))) other.push_back(id(x, y));
    const Pattern a = induced_pattern(g, adjacency, lying);
    const Pattern b = induced_pattern(g, adjacency, standing);
    const Pattern c = induced_pattern(g, adjacency, other);
    ASSERT_EQ(a.size(), 10u);
    ASSERT_EQ(c.size(), 10u);
    ASSERT_EQ(a.edges.size(), 13u);

    const auto m = geometrically_isomorphic(a, b);
    ASSERT_TRUE(m);
    EXPECT_LT(m->max_residual, 1e-9);
    EXPECT_NEAR(angle_mod(m->transform.angle(), 90 * deg), 0.0, 1e-9);
    IsomorphismOptions rigid;
    rigid.mode = IsomorphismOptions::Scale::rigid;
    EXPECT_TRUE(geometrically_isomorphic(a, b, rigid));
    EXPECT_FALSE(geometrically_isomorphic(a, c));

    // The same patch drawn by hand: jittered, rotated, scaled; and with one street missing.
    Pattern jittered = image(a, some_transform, {9, 8, 7, 6, 5, 4, 3, 2, 1, 0});
    const double size = rms_radius(jittered);
    for (std::size_t i = 0; i < jittered.size(); ++i) {
        jittered.positions[i] += 0.015 * size * Vec2(std::cos(1.7 * static_cast<double>(i)), std::sin(1.7 * static_cast<double>(i)));
    }
    EXPECT_TRUE(geometrically_isomorphic(a, jittered));
    EXPECT_TRUE(geometrically_isomorphic(jittered, b));
    Pattern missing = jittered;
    missing.edges.erase(missing.edges.begin() + 4);
    EXPECT_FALSE(geometrically_isomorphic(a, missing));
}
