#include "analysis_fixtures.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

namespace ggg::test {

namespace {

EdgeAttributes street() {
    EdgeAttributes a;
    a.highway = HighwayClass::residential;
    return a;
}

} // namespace

GeometricGraph make_grid(const GridOptions& o) {
    GeometricGraph g;
    std::mt19937_64 rng(o.seed);
    // The standard library requires sigma > 0 (checked with _GLIBCXX_ASSERTIONS); unused when 0.
    std::normal_distribution<double> noise(0.0, o.jitter > 0.0 ? o.jitter * o.spacing : 1.0);
    const double c = std::cos(o.angle_rad);
    const double s = std::sin(o.angle_rad);
    for (int j = 0; j < o.n; ++j) {
        for (int i = 0; i < o.n; ++i) {
            double x = i * o.spacing;
            double y = j * o.spacing;
            if (o.jitter > 0.0) {
                x += noise(rng);
                y += noise(rng);
            }
            g.add_vertex({c * x - s * y, s * x + c * y});
        }
    }
    for (int j = 0; j < o.n; ++j) {
        for (int i = 0; i < o.n; ++i) {
            const VertexId v = j * o.n + i;
            if (i + 1 < o.n) g.add_edge(v, v + 1, street());
            if (j + 1 < o.n) g.add_edge(v, v + o.n, street());
        }
    }
    return g;
}

std::set<std::vector<VertexId>> grid_squares(int n) {
    std::set<std::vector<VertexId>> out;
    for (int j = 0; j + 1 < n; ++j) {
        for (int i = 0; i + 1 < n; ++i) {
            const VertexId v = j * n + i;
            out.insert({v, v + 1, v + n, v + n + 1});
        }
    }
    return out;
}

std::set<std::vector<VertexId>> occurrence_sets(const Isogroup& group) {
    std::set<std::vector<VertexId>> out;
    for (std::size_t i = 0; i < group.frequency(); ++i) {
        std::vector<VertexId> v(group.occurrence(i).begin(), group.occurrence(i).end());
        std::sort(v.begin(), v.end());
        out.insert(std::move(v));
    }
    return out;
}

PlantedMotif plant_motif(const std::vector<double>& scales, std::uint64_t seed) {
    // A house with a tail: a square, a roof triangle on top, a short street off one corner.
    // Street grids have no triangles, so nothing in the host looks like it.
    const std::vector<Vec2> shape{{-0.5, -0.5}, {0.5, -0.5}, {0.5, 0.5}, {-0.5, 0.5}, {0.0, 1.1}, {1.2, -0.2}};
    const std::vector<std::array<int, 2>> links{{0, 1}, {1, 2}, {2, 3}, {0, 3}, {3, 4}, {2, 4}, {1, 5}};

    PlantedMotif out;
    out.motif.positions = shape;
    out.motif.symbols.assign(shape.size(), 0);
    out.motif.edges = links;
    std::sort(out.motif.edges.begin(), out.motif.edges.end());

    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::normal_distribution<double> noise(0.0, 0.2);
    const int n = 24;
    const double spacing = 100.0;
    // Hole centres on a coarse lattice inside the grid, one per copy.
    std::vector<Vec2> centres;
    for (int b = 0; b < 5 && centres.size() < scales.size(); ++b) {
        for (int a = 0; a < 5 && centres.size() < scales.size(); ++a) {
            centres.emplace_back((2.5 + 4.5 * a) * spacing, (2.5 + 4.5 * b) * spacing);
        }
    }
    // The host: a jittered grid with a fifth of its streets removed, minus the holes.
    std::vector<VertexId> id(static_cast<std::size_t>(n * n), -1);
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            const Vec2 p{(i + noise(rng)) * spacing, (j + noise(rng)) * spacing};
            bool in_hole = false;
            for (const Vec2& c : centres) in_hole = in_hole || (p - c).norm() < 170.0;
            if (!in_hole) id[static_cast<std::size_t>(j * n + i)] = out.graph.add_vertex(p);
        }
    }
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            const VertexId v = id[static_cast<std::size_t>(j * n + i)];
            if (v < 0) continue;
            if (i + 1 < n && id[static_cast<std::size_t>(j * n + i + 1)] >= 0 && unit(rng) > 0.2) {
                out.graph.add_edge(v, id[static_cast<std::size_t>(j * n + i + 1)], street());
            }
            if (j + 1 < n && id[static_cast<std::size_t>((j + 1) * n + i)] >= 0 && unit(rng) > 0.2) {
                out.graph.add_edge(v, id[static_cast<std::size_t>((j + 1) * n + i)], street());
            }
        }
    }
    const Spread spread = spread_of(shape);
    for (std::size_t m = 0; m < scales.size(); ++m) {
        const double angle = 2.0 * std::numbers::pi * unit(rng);
        const Similarity2 t = Similarity2::from(scales[m] / spread.rms, angle, centres[m] - Similarity2::from(scales[m] / spread.rms, angle, Vec2::Zero()).apply(spread.centroid));
        std::vector<VertexId> copy;
        for (const Vec2& p : shape) copy.push_back(out.graph.add_vertex(t.apply(p)));
        for (const auto& [a, b] : links) out.graph.add_edge(copy[static_cast<std::size_t>(a)], copy[static_cast<std::size_t>(b)], street());
        // Tie the copy into the host at its first corner and the tail's end.
        for (int tie : {0, 5}) {
            const Vec2 p = out.graph.positions[static_cast<std::size_t>(copy[static_cast<std::size_t>(tie)])];
            VertexId nearest = -1;
            double best = 1e300;
            for (int j = 0; j < n * n; ++j) {
                const VertexId h = id[static_cast<std::size_t>(j)];
                if (h < 0) continue;
                const double d = (out.graph.positions[static_cast<std::size_t>(h)] - p).norm();
                if (d < best) {
                    best = d;
                    nearest = h;
                }
            }
            out.graph.add_edge(copy[static_cast<std::size_t>(tie)], nearest, street());
        }
        std::sort(copy.begin(), copy.end());
        out.copies.push_back(copy);
    }
    return out;
}

} // namespace ggg::test
