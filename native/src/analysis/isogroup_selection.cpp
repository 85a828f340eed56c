// Ranking isogroups by description-length gain, with shape constraints.
#include "ggg/analysis/isogroup_selection.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>

#include "ggg/error.hpp"

#include <Eigen/Eigenvalues>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

namespace ggg {

namespace {
// Groups that get the full selection after the quick ranking pass.
constexpr std::size_t thorough_count = 16;
} // namespace

PatternShape shape_of(const Pattern& p) {
    PatternShape s;
    const std::size_t k = p.size();
    if (k == 0) return s;
    Vec2 mean = Vec2::Zero();
    for (const Vec2& x : p.positions) mean += x;
    mean /= static_cast<double>(k);
    Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
    for (const Vec2& x : p.positions) cov += (x - mean) * (x - mean).transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(cov);
    const double lo = std::max(0.0, eig.eigenvalues()(0));
    const double hi = eig.eigenvalues()(1);
    s.aspect = hi > 0.0 ? std::sqrt(lo / hi) : 0.0;

    std::vector<int> degree(k, 0);
    for (const auto& [u, v] : p.edges) {
        ++degree[static_cast<std::size_t>(u)];
        ++degree[static_cast<std::size_t>(v)];
    }
    s.leaves = static_cast<std::size_t>(std::count(degree.begin(), degree.end(), 1));

    // Directions taken four times over: perpendicular directions coincide, so the mean of
    // e^{4i theta} points along the dominant grid.
    std::complex<double> sum = 0.0;
    double total = 0.0;
    std::vector<std::pair<double, double>> edges; // (angle, length)
    for (const auto& [u, v] : p.edges) {
        const Vec2 d = p.positions[static_cast<std::size_t>(v)] - p.positions[static_cast<std::size_t>(u)];
        const double l = d.norm();
        if (!(l > 0.0)) continue;
        const double angle = std::atan2(d.y(), d.x());
        sum += l * std::polar(1.0, 4.0 * angle);
        total += l;
        edges.emplace_back(angle, l);
    }
    if (total > 0.0) {
        const double axis = std::arg(sum) / 4.0;
        double deviation = 0.0;
        for (const auto& [angle, l] : edges) {
            double d = std::fmod(angle - axis, std::numbers::pi / 2.0);
            if (d < 0.0) d += std::numbers::pi / 2.0;
            deviation += l * std::min(d, std::numbers::pi / 2.0 - d);
        }
        s.irregularity_deg = deviation / total * 180.0 / std::numbers::pi;
    }
    return s;
}

std::string violated_constraint(const PatternShape& shape, const SelectionConstraints& c) {
    if (shape.aspect < c.min_aspect) return "aspect ratio below " + std::to_string(c.min_aspect);
    if (shape.leaves < c.min_leaves) return "fewer than " + std::to_string(c.min_leaves) + " leaves";
    if (shape.irregularity_deg < c.min_irregularity_deg) {
        return "more regular than " + std::to_string(c.min_irregularity_deg) + " degrees";
    }
    return {};
}

double description_gain(std::size_t order, std::size_t edges, std::size_t non_overlapping, std::size_t outside_edges) {
    const double k = static_cast<double>(order);
    const double e = static_cast<double>(edges);
    return static_cast<double>(non_overlapping) * (2.0 * k + 2.0 * e - 5.0) - static_cast<double>(outside_edges) -
           (2.0 * k + 2.0 * e);
}

namespace {

std::vector<std::uint32_t> degrees_of(const GeometricGraph& g) {
    std::vector<std::uint32_t> d(g.vertex_count(), 0);
    for (const auto& [u, v] : g.edges) {
        ++d[static_cast<std::size_t>(u)];
        ++d[static_cast<std::size_t>(v)];
    }
    return d;
}

double gain_of(const Isogroup& group, const std::vector<std::uint32_t>& chosen, const std::vector<std::uint32_t>& degree) {
    std::size_t outside = 0;
    for (std::uint32_t i : chosen) {
        std::size_t sum = 0;
        for (VertexId v : group.occurrence(i)) sum += degree[static_cast<std::size_t>(v)];
        outside += sum - 2 * group.pattern.edges.size();
    }
    return description_gain(group.order(), group.pattern.edges.size(), chosen.size(), outside);
}

// The quick pass: occurrences in increasing order of how many others share their vertices
// (a cheap stand-in for the overlap degree), each taken when its vertices are still free.
// O(n k log n), no overlap graph; `used` is a per-thread scratch array, one entry per
// graph vertex, left all zero again.
std::vector<std::uint32_t> quick_selection(const Isogroup& group, std::vector<std::uint32_t>& used) {
    const std::size_t k = group.order();
    const std::size_t n = group.frequency();
    for (VertexId v : group.vertices) {
        if (v < 0 || static_cast<std::size_t>(v) >= used.size()) throw UsageError("isogroup selection: a vertex id is not in the graph");
    }
    for (VertexId v : group.vertices) ++used[static_cast<std::size_t>(v)];
    std::vector<std::pair<std::uint64_t, std::uint32_t>> order(n);
    for (std::size_t i = 0; i < n; ++i) {
        std::uint64_t crowd = 0;
        for (std::size_t j = 0; j < k; ++j) crowd += used[static_cast<std::size_t>(group.vertices[i * k + j])];
        order[i] = {crowd, static_cast<std::uint32_t>(i)};
    }
    for (VertexId v : group.vertices) used[static_cast<std::size_t>(v)] = 0;
    std::sort(order.begin(), order.end());
    std::vector<std::uint32_t> chosen;
    for (const auto& [crowd, i] : order) {
        const VertexId* occurrence = group.vertices.data() + static_cast<std::size_t>(i) * k;
        bool free = true;
        for (std::size_t j = 0; j < k && free; ++j) free = used[static_cast<std::size_t>(occurrence[j])] == 0;
        if (!free) continue;
        for (std::size_t j = 0; j < k; ++j) used[static_cast<std::size_t>(occurrence[j])] = 1;
        chosen.push_back(i);
    }
    for (std::uint32_t i : chosen) {
        for (std::size_t j = 0; j < k; ++j) used[static_cast<std::size_t>(group.vertices[static_cast<std::size_t>(i) * k + j])] = 0;
    }
    std::sort(chosen.begin(), chosen.end());
    return chosen;
}

} // namespace

std::vector<SelectedIsogroup> select_isogroups(const GeometricGraph& graph, const std::vector<Isogroup>& isogroups,
                                               const SelectionConstraints& constraints,
                                               const SelectionOptions& options, const ProgressCallback& progress) {
    report(progress, 0.0, "selecting non-overlapping occurrences");
    const std::vector<std::uint32_t> degree = degrees_of(graph);
    // First every group with a quick greedy selection (a few per cent below the best, which
    // is enough to rank thousands of groups), then the leading ones again with the full
    // search, so the groups that matter get the exact or locally searched answer.
    std::vector<SelectedIsogroup> all(isogroups.size());
    std::vector<char> keep(isogroups.size(), 0);
    auto evaluate = [&](std::size_t i, const SelectionOptions& how) {
        const Isogroup& g = isogroups[i];
        SelectedIsogroup& s = all[i];
        SelectionResult r = select_non_overlapping(g.vertices, g.order(), how);
        s.non_overlapping = std::move(r.chosen);
        s.exact = r.exact;
        s.method = std::move(r.method);
        s.gain = gain_of(g, s.non_overlapping, degree);
    };
    tbb::enumerable_thread_specific<std::vector<std::uint32_t>> scratch(
        [&] { return std::vector<std::uint32_t>(graph.vertex_count(), 0); });
    tbb::parallel_for(std::size_t{0}, isogroups.size(), [&](std::size_t i) {
        SelectedIsogroup& s = all[i];
        s.index = i;
        s.shape = shape_of(isogroups[i].pattern);
        if (!violated_constraint(s.shape, constraints).empty() || isogroups[i].frequency() == 0) return;
        keep[i] = 1;
        s.non_overlapping = quick_selection(isogroups[i], scratch.local());
        s.exact = s.non_overlapping.size() == isogroups[i].frequency();
        s.method = "greedy by least shared vertices, unproven";
        s.gain = gain_of(isogroups[i], s.non_overlapping, degree);
    });
    report(progress, 0.5, "selecting non-overlapping occurrences");
    std::vector<std::size_t> leading;
    for (std::size_t i = 0; i < all.size(); ++i) {
        if (keep[i]) leading.push_back(i);
    }
    const std::size_t refined = std::min(leading.size(), thorough_count);
    std::partial_sort(leading.begin(), leading.begin() + static_cast<std::ptrdiff_t>(refined), leading.end(),
                      [&](std::size_t a, std::size_t b) { return all[a].gain > all[b].gain || (all[a].gain == all[b].gain && a < b); });
    tbb::parallel_for(std::size_t{0}, refined, [&](std::size_t j) { evaluate(leading[j], options); });
    report(progress, 1.0, "selecting non-overlapping occurrences");
    std::vector<SelectedIsogroup> result;
    for (std::size_t i = 0; i < all.size(); ++i) {
        if (keep[i]) result.push_back(std::move(all[i]));
    }
    sort_by_gain(result, isogroups);
    return result;
}

void sort_by_gain(std::vector<SelectedIsogroup>& selected, const std::vector<Isogroup>& isogroups) {
    std::stable_sort(selected.begin(), selected.end(), [&](const SelectedIsogroup& a, const SelectedIsogroup& b) {
        if (a.gain != b.gain) return a.gain > b.gain;
        const auto fa = isogroups[a.index].frequency();
        const auto fb = isogroups[b.index].frequency();
        if (fa != fb) return fa > fb;
        if (isogroups[a.index].order() != isogroups[b.index].order()) {
            return isogroups[a.index].order() > isogroups[b.index].order();
        }
        return a.index < b.index;
    });
}

SelectedIsogroup select_one(const GeometricGraph& g, const Isogroup& group, std::size_t index, const SelectionOptions& options) {
    SelectedIsogroup s;
    s.index = index;
    s.shape = shape_of(group.pattern);
    if (group.frequency() == 0) return s;
    SelectionResult r = select_non_overlapping(group.vertices, group.order(), options);
    s.non_overlapping = std::move(r.chosen);
    s.exact = r.exact;
    s.method = std::move(r.method);
    s.gain = gain_of(group, s.non_overlapping, degrees_of(g));
    return s;
}

} // namespace ggg
