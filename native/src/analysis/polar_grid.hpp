#pragma once
// The polar grid of the isogroup detection's expansion (analysis/isogroup_detection.hpp),
// private to it, and the peak clustering of its counts: header-only, since the expansion
// bins every candidate through it.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

#include "ggg/graph/geometric_graph.hpp"

namespace ggg::detection_detail {

class PolarGrid {
public:
    PolarGrid(int angles, int distances) : angles_(angles), distances_(distances) {
        log_lo_ = std::log(1.0 / 8.0);
        const double log_hi = std::log(8.0);
        lo2_ = std::exp(2.0 * log_lo_);
        hi2_ = std::exp(2.0 * log_hi);
        per_log_ = distances / (log_hi - log_lo_);
        per_radian_ = angles / (2.0 * std::numbers::pi);
    }
    int size() const { return angles_ * distances_; }
    int angles() const { return angles_; }
    int distances() const { return distances_; }

    // Cell of offset d, or -1 outside the ring.
    int cell(const Vec2& d) const {
        const double r2 = d.squaredNorm();
        if (!(r2 >= lo2_ && r2 < hi2_)) return -1;
        int ring = static_cast<int>((0.5 * std::log(r2) - log_lo_) * per_log_);
        ring = std::clamp(ring, 0, distances_ - 1);
        int sector = static_cast<int>((std::atan2(d.y(), d.x()) + std::numbers::pi) * per_radian_);
        if (sector >= angles_) sector = 0;
        if (sector < 0) sector = 0;
        return ring * angles_ + sector;
    }

    // Chebyshev neighbours (angle wraps around, distance does not) of `cell`, itself excluded.
    template <class F>
    void for_each_neighbour(int cell, F&& f) const {
        const int ring = cell / angles_;
        const int sector = cell % angles_;
        for (int dr = -1; dr <= 1; ++dr) {
            const int r = ring + dr;
            if (r < 0 || r >= distances_) continue;
            for (int ds = -1; ds <= 1; ++ds) {
                if (dr == 0 && ds == 0) continue;
                if (angles_ <= 2 && ds != 0) continue;
                const int s = (sector + ds + angles_) % angles_;
                f(r * angles_ + s);
            }
        }
    }

private:
    int angles_;
    int distances_;
    double log_lo_;
    double lo2_;
    double hi2_;
    double per_log_;
    double per_radian_;
};

// Greedy peak clustering of a histogram: cells in decreasing count (ties: lower index) each
// become a peak unless already claimed, and claim their unclaimed non-empty neighbours.
// Returns the cluster of every cell (-1 for empty cells) and the number of clusters.
template <class Neighbours>
int cluster_histogram(const std::vector<std::uint32_t>& counts, std::vector<int>& cluster, Neighbours&& neighbours) {
    const int size = static_cast<int>(counts.size());
    cluster.assign(counts.size(), -1);
    std::vector<int> order;
    for (int c = 0; c < size; ++c) {
        if (counts[static_cast<std::size_t>(c)] > 0) order.push_back(c);
    }
    std::sort(order.begin(), order.end(), [&](int a, int b) {
        const auto ca = counts[static_cast<std::size_t>(a)];
        const auto cb = counts[static_cast<std::size_t>(b)];
        return ca > cb || (ca == cb && a < b);
    });
    int clusters = 0;
    for (int c : order) {
        if (cluster[static_cast<std::size_t>(c)] >= 0) continue;
        const int id = clusters++;
        cluster[static_cast<std::size_t>(c)] = id;
        neighbours(c, [&](int n) {
            if (counts[static_cast<std::size_t>(n)] > 0 && cluster[static_cast<std::size_t>(n)] < 0) {
                cluster[static_cast<std::size_t>(n)] = id;
            }
        });
    }
    return clusters;
}

} // namespace ggg::detection_detail
