// Street-network statistics and their distances; see network_comparison.hpp.
#include "ggg/measures/network_comparison.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>

#include "ggg/graph/planar_faces.hpp"
#include "ggg/graph/plane_geometry.hpp"

namespace ggg {

namespace {

constexpr int kDegreeBins = 9;       // 0 .. 7, and 8 or more
constexpr int kOrientationBins = 36; // 10 degrees each

double entropy(const std::vector<double>& shares) {
    double h = 0.0;
    for (double p : shares) {
        if (p > 0) h -= p * std::log(p);
    }
    return h;
}

double total_variation(const std::vector<double>& p, const std::vector<double>& q, std::size_t shift = 0) {
    double sum = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i) sum += std::abs(p[i] - q[(i + shift) % q.size()]);
    return 0.5 * sum;
}

// Largest gap between the empirical cumulative distributions of two sorted samples; 1
// when exactly one of them is empty, 0 when both are.
double kolmogorov_smirnov(const std::vector<double>& a, const std::vector<double>& b) {
    if (a.empty() || b.empty()) return a.empty() == b.empty() ? 0.0 : 1.0;
    std::size_t i = 0, j = 0;
    double gap = 0.0;
    while (i < a.size() && j < b.size()) {
        const double x = std::min(a[i], b[j]);
        while (i < a.size() && a[i] <= x) ++i;
        while (j < b.size() && b[j] <= x) ++j;
        gap = std::max(gap, std::abs(static_cast<double>(i) / static_cast<double>(a.size()) - static_cast<double>(j) / static_cast<double>(b.size())));
    }
    return gap;
}


void junction_structure(const GeometricGraph& g, const Adjacency& adj, StreetStatistics& s) {
    std::size_t through = 0, right = 0;
    std::vector<double> bearings;
    for (std::size_t v = 0; v < g.vertex_count(); ++v) {
        const auto id = static_cast<VertexId>(v);
        if (adj.degree(id) < 3) continue;
        ++s.junctions;
        bearings.clear();
        for (auto i = static_cast<std::size_t>(adj.offsets[v]); i < static_cast<std::size_t>(adj.offsets[v + 1]); ++i) {
            const Vec2 d = leaving_direction(g, adj.edge_ids[i], id);
            bearings.push_back(std::atan2(d.y(), d.x()) * 180.0 / M_PI);
        }
        std::sort(bearings.begin(), bearings.end());
        bool straight = false;
        for (std::size_t i = 0; i < bearings.size(); ++i) {
            const double next = i + 1 < bearings.size() ? bearings[i + 1] : bearings[0] + 360.0;
            const double angle = next - bearings[i];
            s.junction_angles_deg.push_back(angle);
            if (std::abs(angle - 90.0) <= 15.0) ++right;
            for (std::size_t j = i + 1; j < bearings.size(); ++j) {
                const double turn = std::abs(std::remainder(bearings[j] - bearings[i], 360.0));
                if (turn >= 155.0) straight = true;
            }
        }
        if (straight) ++through;
    }
    std::sort(s.junction_angles_deg.begin(), s.junction_angles_deg.end());
    if (!s.junction_angles_deg.empty()) s.right_angle_share = static_cast<double>(right) / static_cast<double>(s.junction_angles_deg.size());
    if (s.junctions) s.through_share = static_cast<double>(through) / static_cast<double>(s.junctions);
}

// Network over straight distance, summed over pairs (Boeing's average circuity).
double circuity(const GeometricGraph& g, const Adjacency& adj) {
    const std::size_t n = g.vertex_count();
    if (n < 2) return std::nan("");
    constexpr std::size_t sources = 24;
    const std::size_t step = std::max<std::size_t>(1, n / sources);
    double network = 0.0, straight = 0.0;
    std::vector<double> dist(n);
    using Item = std::pair<double, VertexId>;
    for (std::size_t s = (step / 2) % n, count = 0; count < sources && s < n; s += step, ++count) {
        std::fill(dist.begin(), dist.end(), std::numeric_limits<double>::infinity());
        std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
        dist[s] = 0.0;
        queue.emplace(0.0, static_cast<VertexId>(s));
        while (!queue.empty()) {
            const auto [d, v] = queue.top();
            queue.pop();
            if (d > dist[static_cast<std::size_t>(v)]) continue;
            for (auto i = static_cast<std::size_t>(adj.offsets[static_cast<std::size_t>(v)]); i < static_cast<std::size_t>(adj.offsets[static_cast<std::size_t>(v) + 1]); ++i) {
                const VertexId w = adj.neighbors[i];
                const double nd = d + g.edge_length(adj.edge_ids[i]);
                if (nd < dist[static_cast<std::size_t>(w)]) {
                    dist[static_cast<std::size_t>(w)] = nd;
                    queue.emplace(nd, w);
                }
            }
        }
        for (std::size_t t = 0; t < n; ++t) {
            if (t == s || !std::isfinite(dist[t])) continue;
            const double line = (g.positions[t] - g.positions[s]).norm();
            if (line <= 0) continue;
            network += dist[t];
            straight += line;
        }
    }
    return straight > 0 ? network / straight : std::nan("");
}

} // namespace

Vec2 leaving_direction(const GeometricGraph& g, EdgeId e, VertexId v) {
    const std::vector<Vec2> line = polyline_from(g, e, v);
    const double reach = std::min(20.0, 0.5 * g.edge_length(e));
    if (const auto at = point_along(line, reach)) return *at - line[0];
    return line.back() - line.front();
}

StreetStatistics street_statistics(const GeometricGraph& g) {
    StreetStatistics s;
    s.vertices = g.vertex_count();
    s.edges = g.edge_count();
    s.degree_histogram.assign(kDegreeBins, 0.0);
    if (g.vertex_count()) {
        const Adjacency adj(g);
        for (std::size_t v = 0; v < g.vertex_count(); ++v) {
            ++s.degree_histogram[std::min<std::size_t>(kDegreeBins - 1, adj.degree(static_cast<VertexId>(v)))];
        }
        for (double& share : s.degree_histogram) share /= static_cast<double>(g.vertex_count());
        junction_structure(g, adj, s);
        s.circuity = circuity(g, adj);
    }
    s.orientation_histogram.assign(kOrientationBins, 0.0);
    double total = 0.0;
    for (std::size_t e = 0; e < g.edge_count(); ++e) {
        const auto id = static_cast<EdgeId>(e);
        s.edge_lengths_m.push_back(g.edge_length(id));
        // Every piece of the polyline, by length, in both directions (a street runs both ways).
        const Vec2* p = g.geometry_begin(id);
        for (std::size_t i = 0; i + 1 < g.geometry_size(id); ++i) {
            const Vec2 d = p[i + 1] - p[i];
            const double length = d.norm();
            if (length <= 0) continue;
            double bearing = std::atan2(d.x(), d.y()) * 180.0 / M_PI; // from north, clockwise
            if (bearing < 0) bearing += 360.0;
            for (double b : {bearing, std::fmod(bearing + 180.0, 360.0)}) {
                s.orientation_histogram[std::min<std::size_t>(kOrientationBins - 1, static_cast<std::size_t>(b / 10.0))] += length;
            }
            total += 2 * length;
        }
    }
    if (total > 0) {
        for (double& share : s.orientation_histogram) share /= total;
    }
    std::sort(s.edge_lengths_m.begin(), s.edge_lengths_m.end());
    s.orientation_entropy = total > 0 ? entropy(s.orientation_histogram) : 0.0;
    const double grid = std::log(4.0), most = std::log(static_cast<double>(kOrientationBins));
    const double x = (s.orientation_entropy - grid) / (most - grid);
    s.orientation_order = total > 0 ? 1.0 - std::clamp(x, 0.0, 1.0) * std::clamp(x, 0.0, 1.0) : 0.0;
    if (g.edge_count()) {
        const PlanarFaces faces = planar_faces(g);
        for (double area : faces.face_area) {
            if (area > 0) s.block_areas_m2.push_back(area);
        }
        std::sort(s.block_areas_m2.begin(), s.block_areas_m2.end());
    }
    return s;
}

NetworkDistances network_distances(const StreetStatistics& a, const StreetStatistics& b) {
    NetworkDistances d;
    d.degree = total_variation(a.degree_histogram, b.degree_histogram);
    d.edge_length = kolmogorov_smirnov(a.edge_lengths_m, b.edge_lengths_m);
    d.orientation = 1.0;
    for (std::size_t shift = 0; shift < kOrientationBins; ++shift) {
        d.orientation = std::min(d.orientation, total_variation(a.orientation_histogram, b.orientation_histogram, shift));
    }
    d.block_area = kolmogorov_smirnov(a.block_areas_m2, b.block_areas_m2);
    d.junction_angle = kolmogorov_smirnov(a.junction_angles_deg, b.junction_angles_deg);
    return d;
}

} // namespace ggg
