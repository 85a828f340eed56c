// Patterns cut from a graph, their canonical frame, and least-squares similarity fits.
#include "ggg/analysis/pattern.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <string>

#include "ggg/error.hpp"

namespace ggg {

namespace {

using Complex = std::complex<double>;

Complex to_complex(const Vec2& v) { return {v.x(), v.y()}; }

Pattern canonical_pattern(const GeometricGraph& g, std::span<const VertexId> vertices,
                          std::vector<std::array<int, 2>> edges, Similarity2* frame) {
    Pattern p;
    p.positions.reserve(vertices.size());
    p.symbols.reserve(vertices.size());
    for (VertexId v : vertices) {
        p.positions.push_back(g.positions[static_cast<std::size_t>(v)]);
        p.symbols.push_back(g.symbols.empty() ? 0 : g.symbols[static_cast<std::size_t>(v)]);
    }
    const Spread s = spread_of(p.positions);
    Similarity2 canonical_to_graph = Similarity2::from(1.0, 0.0, s.centroid);
    if (s.degenerate) {
        std::fill(p.positions.begin(), p.positions.end(), Vec2::Zero());
    } else {
        for (Vec2& q : p.positions) q = (q - s.centroid) / s.rms;
        canonical_to_graph = Similarity2::from(s.rms, 0.0, s.centroid);
        p.metres_per_unit = s.rms;
    }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    p.edges = std::move(edges);
    if (frame) *frame = canonical_to_graph;
    return p;
}

// Graph vertex -> pattern index, sorted by graph vertex; validates the list on the way.
std::vector<std::pair<VertexId, int>> index_vertices(const GeometricGraph& g, std::span<const VertexId> vertices) {
    if (vertices.empty()) throw UsageError("induced_pattern: no vertices");
    if (vertices.size() > static_cast<std::size_t>(std::numeric_limits<int>::max())) {
        throw UsageError("induced_pattern: too many vertices");
    }
    if (!g.symbols.empty() && g.symbols.size() != g.vertex_count()) {
        throw UsageError("induced_pattern: the graph has " + std::to_string(g.symbols.size()) + " symbols for " +
                         std::to_string(g.vertex_count()) + " vertices");
    }
    std::vector<std::pair<VertexId, int>> index;
    index.reserve(vertices.size());
    for (std::size_t i = 0; i < vertices.size(); ++i) {
        const VertexId v = vertices[i];
        if (v < 0 || static_cast<std::size_t>(v) >= g.vertex_count()) {
            throw UsageError("induced_pattern: vertex " + std::to_string(v) + " is not in the graph (" +
                             std::to_string(g.vertex_count()) + " vertices)");
        }
        index.emplace_back(v, static_cast<int>(i));
    }
    std::sort(index.begin(), index.end());
    for (std::size_t i = 1; i < index.size(); ++i) {
        if (index[i].first == index[i - 1].first) {
            throw UsageError("induced_pattern: vertex " + std::to_string(index[i].first) + " is listed twice");
        }
    }
    return index;
}

int local_index(const std::vector<std::pair<VertexId, int>>& index, VertexId v) {
    const auto it = std::lower_bound(index.begin(), index.end(), std::pair<VertexId, int>{v, -1});
    return it != index.end() && it->first == v ? it->second : -1;
}

} // namespace

Spread spread_of(std::span<const Vec2> points) {
    Spread s;
    if (points.empty()) return s;
    Vec2 sum = Vec2::Zero();
    double magnitude = 0.0;
    for (const Vec2& p : points) {
        sum += p;
        magnitude = std::max(magnitude, p.cwiseAbs().maxCoeff());
    }
    s.centroid = sum / static_cast<double>(points.size());
    double squares = 0.0;
    for (const Vec2& p : points) squares += (p - s.centroid).squaredNorm();
    s.rms = std::sqrt(squares / static_cast<double>(points.size()));
    s.degenerate = !(s.rms > 1e-12 * magnitude);
    return s;
}


std::string check_pattern(const Pattern& p) {
    const std::size_t k = p.positions.size();
    if (k == 0) return "a pattern needs at least one vertex";
    if (k > static_cast<std::size_t>(std::numeric_limits<int>::max())) return "too many vertices";
    if (p.symbols.size() != k) {
        return std::to_string(p.symbols.size()) + " symbols for " + std::to_string(k) + " vertices";
    }
    for (std::size_t i = 0; i < k; ++i) {
        if (!p.positions[i].allFinite()) return "vertex " + std::to_string(i) + " has a coordinate that is not finite";
    }
    if (!(std::isfinite(p.metres_per_unit) && p.metres_per_unit > 0.0)) {
        return "metres_per_unit must be a finite number > 0";
    }
    const auto n = static_cast<long long>(k);
    for (std::size_t e = 0; e < p.edges.size(); ++e) {
        const auto [u, v] = p.edges[e];
        const char* problem = nullptr;
        if (u < 0 || v < 0 || u >= n || v >= n) {
            problem = " has an end out of range";
        } else if (u >= v) {
            problem = " must have its smaller end first (and no loop)";
        } else if (e > 0 && !(p.edges[e - 1] < p.edges[e])) {
            problem = " is out of order or repeated";
        }
        if (problem) return "edge " + std::to_string(e) + " (" + std::to_string(u) + ", " + std::to_string(v) + ")" + problem;
    }
    return {};
}

Pattern induced_pattern(const GeometricGraph& g, std::span<const VertexId> vertices, Similarity2* frame) {
    const auto index = index_vertices(g, vertices);
    std::vector<std::array<int, 2>> edges;
    for (const auto& [u, v] : g.edges) {
        const int i = local_index(index, u);
        if (i < 0) continue;
        const int j = local_index(index, v);
        if (j < 0 || i == j) continue;
        edges.push_back({std::min(i, j), std::max(i, j)});
    }
    return canonical_pattern(g, vertices, std::move(edges), frame);
}

Pattern induced_pattern(const GeometricGraph& g, const Adjacency& adjacency, std::span<const VertexId> vertices,
                        Similarity2* frame) {
    const auto index = index_vertices(g, vertices);
    if (adjacency.offsets.size() != g.vertex_count() + 1) {
        throw UsageError("induced_pattern: the adjacency was built for another graph");
    }
    std::vector<std::array<int, 2>> edges;
    for (std::size_t i = 0; i < vertices.size(); ++i) {
        const auto v = static_cast<std::size_t>(vertices[i]);
        for (auto n = adjacency.offsets[v]; n < adjacency.offsets[v + 1]; ++n) {
            const int j = local_index(index, adjacency.neighbors[static_cast<std::size_t>(n)]);
            if (j > static_cast<int>(i)) edges.push_back({static_cast<int>(i), j}); // each edge once, from its smaller end
        }
    }
    return canonical_pattern(g, vertices, std::move(edges), frame);
}

SimilarityFit fit_similarity(std::span<const Vec2> from, std::span<const Vec2> to) {
    if (from.empty()) throw UsageError("fit_similarity: no points");
    if (from.size() != to.size()) {
        throw UsageError("fit_similarity: " + std::to_string(from.size()) + " points to map onto " +
                         std::to_string(to.size()));
    }
    const Spread source = spread_of(from);
    Vec2 target_centroid = Vec2::Zero();
    for (const Vec2& p : to) target_centroid += p;
    target_centroid /= static_cast<double>(to.size());

    SimilarityFit fit;
    if (!source.degenerate) {
        // a + ib = sum conj(x) y / sum |x|^2 over the centred points.
        Complex numerator = 0.0;
        double denominator = 0.0;
        for (std::size_t i = 0; i < from.size(); ++i) {
            const Complex x = to_complex(from[i] - source.centroid);
            numerator += std::conj(x) * to_complex(to[i] - target_centroid);
            denominator += std::norm(x);
        }
        fit.transform.a = numerator.real() / denominator;
        fit.transform.b = numerator.imag() / denominator;
    }
    fit.transform.t = target_centroid - fit.transform.apply_linear(source.centroid);
    double squares = 0.0;
    for (std::size_t i = 0; i < from.size(); ++i) squares += (fit.transform.apply(from[i]) - to[i]).squaredNorm();
    fit.rms_residual = std::sqrt(squares / static_cast<double>(from.size()));
    return fit;
}

std::string check_isogroup(const GeometricGraph& g, const Adjacency& adjacency, const Isogroup& group,
                           double max_residual) {
    if (std::string problem = check_pattern(group.pattern); !problem.empty()) return "pattern: " + problem;
    const std::size_t k = group.order();
    if (group.vertices.size() != k * group.transforms.size()) {
        return std::to_string(group.vertices.size()) + " occurrence vertices for " +
               std::to_string(group.transforms.size()) + " occurrences of order " + std::to_string(k);
    }
    if (adjacency.offsets.size() != g.vertex_count() + 1) return "the adjacency was built for another graph";
    std::vector<std::vector<VertexId>> seen;
    seen.reserve(group.frequency());
    for (std::size_t i = 0; i < group.frequency(); ++i) {
        const auto occurrence = group.occurrence(i);
        const std::string where = "occurrence " + std::to_string(i) + ": ";
        for (VertexId v : occurrence) {
            if (v < 0 || static_cast<std::size_t>(v) >= g.vertex_count()) return where + "vertex out of range";
        }
        std::vector<VertexId> sorted(occurrence.begin(), occurrence.end());
        std::sort(sorted.begin(), sorted.end());
        if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) return where + "a vertex repeats";
        seen.push_back(std::move(sorted));
        Similarity2 frame;
        const Pattern induced = induced_pattern(g, adjacency, occurrence, &frame);
        if (induced.edges != group.pattern.edges) return where + "its induced edges differ from the pattern's";
        if (induced.symbols != group.pattern.symbols) return where + "its symbols differ from the pattern's";
        const Similarity2& t = group.transforms[i];
        const double scale = t.scale();
        if (!(std::isfinite(scale) && scale > 0.0) || !t.t.allFinite()) return where + "transform is degenerate";
        for (std::size_t j = 0; j < k; ++j) {
            const double residual = (t.apply(group.pattern.positions[j]) - g.positions[static_cast<std::size_t>(occurrence[j])]).norm();
            if (!(residual <= max_residual * scale)) {
                return where + "vertex " + std::to_string(j) + " lies " + std::to_string(residual / scale) +
                       " pattern units from its place (allowed " + std::to_string(max_residual) + ")";
            }
        }
    }
    std::sort(seen.begin(), seen.end());
    if (std::adjacent_find(seen.begin(), seen.end()) != seen.end()) return "two occurrences share a vertex set";
    return {};
}

} // namespace ggg
