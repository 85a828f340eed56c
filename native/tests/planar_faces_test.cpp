// Faces of the plane drawing of a road graph (city blocks): inline fixtures with known
// answers, then invariants on real extracts.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <set>

#include "fixtures.hpp"
#include "ggg/io/read_graph.hpp"
#include "ggg/graph/planar_faces.hpp"
#include "ggg/osm/highway_filter.hpp"

using namespace ggg;

namespace {

// An n x n grid of vertices, `step` metres apart; vertex (i, j) = i + n j.
GeometricGraph grid(int n, double step, Vec2 origin = {0, 0}, GeometricGraph g = {}) {
    const auto base = static_cast<VertexId>(g.vertex_count());
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) g.add_vertex(origin + Vec2{i * step, j * step});
    auto id = [&](int i, int j) { return base + static_cast<VertexId>(i + n * j); };
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            if (i + 1 < n) g.add_edge(id(i, j), id(i + 1, j), {});
            if (j + 1 < n) g.add_edge(id(i, j), id(i, j + 1), {});
        }
    return g;
}

std::vector<double> sorted_areas(const PlanarFaces& f) {
    std::vector<double> a = f.face_area;
    std::sort(a.begin(), a.end());
    return a;
}

// Area of face `face` summed over its rings.
double rings_area(const PlanarFaces& f, std::int32_t face) {
    double a = 0;
    for (std::size_t r = 0; r < f.ring_count(); ++r) {
        if (f.ring_face[r] != face) continue;
        a += ring_area(f.points.data() + f.ring_offsets[r], f.points.data() + f.ring_offsets[r + 1]);
    }
    return a;
}

} // namespace

TEST(PlanarFaces, GridHasOneFacePerCell) {
    for (int n : {2, 3, 7}) {
        const GeometricGraph g = grid(n, 100.0, {1000.0, -500.0});
        const PlanarFaces f = planar_faces(g);
        ASSERT_EQ(f.face_count(), static_cast<std::size_t>((n - 1) * (n - 1))) << "n = " << n;
        for (double a : f.face_area) EXPECT_NEAR(a, 100.0 * 100.0, 1e-6);
        EXPECT_EQ(f.ring_count(), f.face_count());
        for (std::size_t r = 0; r < f.ring_count(); ++r) EXPECT_EQ(f.ring_offsets[r + 1] - f.ring_offsets[r], 4);
        EXPECT_EQ(f.components, 1u);
        EXPECT_EQ(f.outer_dropped, 1u);
        EXPECT_EQ(f.genus, 0u);
        EXPECT_EQ(f.dangling_edges, 0u);
    }
}

TEST(PlanarFaces, OuterFaceIsKeptOnRequest) {
    const GeometricGraph g = grid(4, 10.0);
    PlanarFaceOptions options;
    options.keep_outer = true;
    const PlanarFaces f = planar_faces(g, options);
    ASSERT_EQ(f.face_count(), 10u);
    const auto areas = sorted_areas(f);
    EXPECT_NEAR(areas.front(), -900.0, 1e-9); // the outer face, clockwise
    EXPECT_NEAR(std::accumulate(areas.begin(), areas.end(), 0.0), 0.0, 1e-9);
    // Every half-edge lies on exactly one face.
    EXPECT_EQ(f.face_edges.size(), 2 * g.edge_count());
    std::set<std::pair<EdgeId, int>> seen;
    for (std::size_t k = 0; k < f.face_edges.size(); ++k) seen.insert({f.face_edges[k], f.face_edge_reversed[k]});
    EXPECT_EQ(seen.size(), 2 * g.edge_count());
}

TEST(PlanarFaces, FaceBoundaryFollowsThePolylines) {
    // A 100 m square whose top edge bulges outwards as a triangle 20 m high.
    GeometricGraph g;
    const auto a = g.add_vertex({0, 0}), b = g.add_vertex({100, 0}), c = g.add_vertex({100, 100}), d = g.add_vertex({0, 100});
    g.add_edge(a, b, {});
    g.add_edge(b, c, {});
    g.add_edge(d, c, {}, {{0, 100}, {50, 120}, {100, 100}}); // stored d -> c: walked backwards
    g.add_edge(d, a, {});
    const PlanarFaces f = planar_faces(g);
    ASSERT_EQ(f.face_count(), 1u);
    EXPECT_NEAR(f.face_area[0], 10000.0 + 1000.0, 1e-9);
    EXPECT_EQ(f.ring_offsets[1], 5); // the shape point is on the ring
    EXPECT_NEAR(rings_area(f, 0), f.face_area[0], 1e-9);
}

TEST(PlanarFaces, DeadEndIsCutOutOfTheRingAndReported) {
    // A 3 x 3 grid (4 blocks) with a cul-de-sac from the centre of the top-right block's
    // bottom edge into that block, and a second dead end hanging outside the grid.
    GeometricGraph g = grid(3, 100.0);
    const auto mid = g.add_vertex({150, 100});
    // Split edge (1,1)-(2,1) at x = 150: rebuild the graph without that edge.
    GeometricGraph h;
    h.positions = g.positions;
    h.vertex_osm_ids = g.vertex_osm_ids;
    h.symbols = g.symbols;
    h.frames = g.frames;
    for (std::size_t e = 0; e < g.edge_count(); ++e) {
        const auto [u, v] = g.edges[e];
        if ((u == 4 && v == 5) || (u == 5 && v == 4)) continue;
        h.add_edge(u, v, {});
    }
    h.add_edge(4, mid, {});
    h.add_edge(mid, 5, {});
    const auto tip = h.add_vertex({150, 160});
    h.add_edge(mid, tip, {}, {{150, 100}, {150, 130}, {150, 160}});
    const auto outside = h.add_vertex({-50, 0});
    h.add_edge(0, outside, {});

    const PlanarFaces f = planar_faces(h);
    ASSERT_EQ(f.face_count(), 4u);
    EXPECT_EQ(f.dangling_edges, 2u);
    EXPECT_EQ(f.genus, 0u);
    for (double a : f.face_area) EXPECT_NEAR(a, 10000.0, 1e-9); // the spike adds no area
    const auto with_spike = std::find(f.face_dangling.begin(), f.face_dangling.end(), 1) - f.face_dangling.begin();
    ASSERT_LT(with_spike, 4);
    EXPECT_EQ(std::count(f.face_dangling.begin(), f.face_dangling.end(), 0), 3);
    // The walk of that face goes up and down the cul-de-sac ...
    EXPECT_EQ(f.face_edge_offsets[static_cast<std::size_t>(with_spike) + 1] - f.face_edge_offsets[static_cast<std::size_t>(with_spike)], 7);
    // ... its ring does not: the block's corners and the split point only.
    for (std::size_t r = 0; r < f.ring_count(); ++r) {
        if (f.ring_face[r] != with_spike) continue;
        EXPECT_EQ(f.ring_offsets[r + 1] - f.ring_offsets[r], 5);
        for (auto k = f.ring_offsets[r]; k < f.ring_offsets[r + 1]; ++k) EXPECT_LE(f.points[static_cast<std::size_t>(k)].y(), 200.0);
        for (auto k = f.ring_offsets[r]; k < f.ring_offsets[r + 1]; ++k) EXPECT_NE(f.points[static_cast<std::size_t>(k)], Vec2(150, 160));
    }

    // Without removal, one ring per face that includes the spike (its points twice).
    PlanarFaceOptions raw;
    raw.remove_dangling = false;
    const PlanarFaces r = planar_faces(h, raw);
    ASSERT_EQ(r.ring_count(), 4u);
    EXPECT_EQ(r.ring_offsets[static_cast<std::size_t>(with_spike) + 1] - r.ring_offsets[static_cast<std::size_t>(with_spike)], 9);
}

TEST(PlanarFaces, LoopReachedOverABridgeBecomesAHole) {
    // A 100 m square block with a 20 m square loop in its middle, joined by one street.
    GeometricGraph g;
    const auto a = g.add_vertex({0, 0}), b = g.add_vertex({100, 0}), c = g.add_vertex({100, 100}), d = g.add_vertex({0, 100});
    g.add_edge(a, b, {});
    g.add_edge(b, c, {});
    g.add_edge(c, d, {});
    g.add_edge(d, a, {});
    const auto p = g.add_vertex({40, 40}), q = g.add_vertex({60, 40}), r = g.add_vertex({60, 60}), s = g.add_vertex({40, 60});
    g.add_edge(p, q, {});
    g.add_edge(q, r, {});
    g.add_edge(r, s, {});
    g.add_edge(s, p, {});
    g.add_edge(a, p, {});
    const PlanarFaces f = planar_faces(g);
    ASSERT_EQ(f.face_count(), 2u); // the block around the loop, and the loop's inside
    EXPECT_EQ(f.dangling_edges, 1u);
    const auto block = f.face_area[0] > f.face_area[1] ? 0 : 1;
    EXPECT_NEAR(f.face_area[static_cast<std::size_t>(block)], 10000.0 - 400.0, 1e-9);
    EXPECT_NEAR(f.face_area[static_cast<std::size_t>(1 - block)], 400.0, 1e-9);
    std::vector<double> ring_areas;
    for (std::size_t k = 0; k < f.ring_count(); ++k) {
        if (f.ring_face[k] == block)
            ring_areas.push_back(ring_area(f.points.data() + f.ring_offsets[k], f.points.data() + f.ring_offsets[k + 1]));
    }
    std::sort(ring_areas.begin(), ring_areas.end());
    ASSERT_EQ(ring_areas.size(), 2u);
    EXPECT_NEAR(ring_areas[0], -400.0, 1e-9); // the hole, clockwise
    EXPECT_NEAR(ring_areas[1], 10000.0, 1e-9);
}

TEST(PlanarFaces, ComponentsAreTracedApart) {
    // Two grids side by side, a lone edge, and an isolated vertex.
    GeometricGraph g = grid(3, 50.0);
    g = grid(4, 20.0, {500, 0}, std::move(g));
    const auto u = g.add_vertex({0, 900}), v = g.add_vertex({10, 900});
    g.add_edge(u, v, {});
    g.add_vertex({-300, -300});
    const PlanarFaces f = planar_faces(g);
    EXPECT_EQ(f.components, 3u);
    EXPECT_EQ(f.outer_dropped, 3u);
    EXPECT_EQ(f.dangling_edges, 1u);
    ASSERT_EQ(f.face_count(), 4u + 9u);
    EXPECT_EQ(std::count(f.face_component.begin(), f.face_component.end(), 0), 4);
    EXPECT_EQ(std::count(f.face_component.begin(), f.face_component.end(), 1), 9);
    const auto areas = sorted_areas(f);
    EXPECT_NEAR(areas.front(), 400.0, 1e-9);
    EXPECT_NEAR(areas.back(), 2500.0, 1e-9);
}

TEST(PlanarFaces, CrossingWithoutAVertexIsAHandle) {
    // A square with both diagonals as roads that cross without a shared vertex (a bridge).
    GeometricGraph g;
    const auto a = g.add_vertex({0, 0}), b = g.add_vertex({100, 0}), c = g.add_vertex({100, 100}), d = g.add_vertex({0, 100});
    g.add_edge(a, b, {});
    g.add_edge(b, c, {});
    g.add_edge(c, d, {});
    g.add_edge(d, a, {});
    g.add_edge(a, c, {});
    g.add_edge(b, d, {});
    PlanarFaceOptions options;
    options.keep_outer = true;
    const PlanarFaces f = planar_faces(g, options);
    EXPECT_EQ(f.genus, 1u); // V - E + F = 4 - 6 + 2 = 0
    EXPECT_EQ(f.face_count(), 2u);
    EXPECT_NEAR(f.face_area[0] + f.face_area[1], 0.0, 1e-9);
    const PlanarFaces dropped = planar_faces(g);
    EXPECT_EQ(dropped.outer_dropped + dropped.nonpositive_dropped + dropped.face_count(), 2u);
}

TEST(PlanarFaces, EmptyAndTreeGraphsHaveNoFaces) {
    EXPECT_EQ(planar_faces(GeometricGraph{}).face_count(), 0u);
    GeometricGraph star;
    const auto centre = star.add_vertex({0, 0});
    for (int k = 0; k < 5; ++k) star.add_edge(centre, star.add_vertex({std::cos(k) * 50, std::sin(k) * 50}), {});
    const PlanarFaces f = planar_faces(star);
    EXPECT_EQ(f.face_count(), 0u);
    EXPECT_EQ(f.dangling_edges, 5u);
    EXPECT_EQ(f.outer_dropped, 1u);
}

// Real extracts: every half-edge once, areas that add up, Euler's formula where the
// extract has no crossing roads, and rings whose areas are the face areas.
class PlanarFacesCorpus : public ::testing::TestWithParam<const char*> {};

TEST_P(PlanarFacesCorpus, Invariants) {
    GGG_REQUIRE_CORPUS();
    ImportOptions import;
    import.highways = HighwayFilter::all();
    const GeometricGraph g = read_graph(ggg::test::shared_osm_dir() + "/" + GetParam(), import);
    ASSERT_GT(g.edge_count(), 1000u);

    PlanarFaceOptions all;
    all.keep_outer = true;
    const PlanarFaces every = planar_faces(g, all);
    EXPECT_EQ(every.face_edges.size(), 2 * g.edge_count());
    std::vector<double> per_component(every.components, 0.0), scale(every.components, 0.0);
    for (std::size_t f = 0; f < every.face_count(); ++f) {
        per_component[static_cast<std::size_t>(every.face_component[f])] += every.face_area[f];
        scale[static_cast<std::size_t>(every.face_component[f])] += std::abs(every.face_area[f]);
    }
    for (std::size_t c = 0; c < every.components; ++c) EXPECT_NEAR(per_component[c], 0.0, 1e-9 * (1.0 + scale[c]));
    // V - E + F = 2 C - 2 genus, counting only vertices with edges.
    std::vector<char> used(g.vertex_count(), 0);
    for (const auto& [u, v] : g.edges) used[static_cast<std::size_t>(u)] = used[static_cast<std::size_t>(v)] = 1;
    const auto vertices = static_cast<std::int64_t>(std::count(used.begin(), used.end(), 1));
    EXPECT_EQ(vertices - static_cast<std::int64_t>(g.edge_count()) + static_cast<std::int64_t>(every.face_count()),
              2 * static_cast<std::int64_t>(every.components) - 2 * static_cast<std::int64_t>(every.genus));

    const PlanarFaces blocks = planar_faces(g);
    EXPECT_EQ(blocks.outer_dropped, blocks.components);
    EXPECT_EQ(blocks.face_count() + blocks.outer_dropped + blocks.nonpositive_dropped, every.face_count());
    ASSERT_GT(blocks.face_count(), 100u);
    double bounded = 0.0;
    for (std::size_t f = 0; f < blocks.face_count(); ++f) {
        ASSERT_GT(blocks.face_area[f], 0.0);
        bounded += blocks.face_area[f];
        // Cutting dead ends out of the rings changes no area.
        EXPECT_NEAR(rings_area(blocks, static_cast<std::int32_t>(f)), blocks.face_area[f], 1e-6 * (1.0 + blocks.face_area[f]));
    }
    // Without crossings, the blocks tile the area inside the outer boundaries exactly.
    if (every.genus == 0) {
        double outside = 0.0;
        for (std::size_t f = 0; f < every.face_count(); ++f) outside += std::min(every.face_area[f], 0.0);
        EXPECT_NEAR(bounded, -outside, 1e-9 * bounded);
    }
}

INSTANTIATE_TEST_SUITE_P(SharedOsm, PlanarFacesCorpus,
                         ::testing::Values("paris_marais.osm.pbf", "barcelona_eixample.osm", "porto_metro.osm.pbf"),
                         [](const auto& info) {
                             std::string name = info.param;
                             std::replace(name.begin(), name.end(), '.', '_');
                             return name;
                         });
