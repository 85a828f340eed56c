#pragma once
// Plane geometry that the synthesis stages share. A region is a simple polygon in a graph's
// metres, its corners in order (either direction), not closed (the last corner is not a copy
// of the first).
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

#include "ggg/similarity.hpp"

namespace ggg {

inline double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

// Even-odd rule: a point on the border may count either way.
inline bool inside(const std::vector<Vec2>& ring, const Vec2& p) {
    bool in = false;
    for (std::size_t i = 0, j = ring.size() - 1; i < ring.size(); j = i++) {
        const Vec2& a = ring[i];
        const Vec2& b = ring[j];
        if ((a.y() > p.y()) != (b.y() > p.y()) && p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x()) in = !in;
    }
    return in;
}

// Distance from p to the polygon's border (not 0 inside).
inline double distance_to_ring(const std::vector<Vec2>& ring, const Vec2& p) {
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0, j = ring.size() - 1; i < ring.size(); j = i++) {
        const Vec2 d = ring[i] - ring[j];
        const double t = std::clamp((p - ring[j]).dot(d) / std::max(d.squaredNorm(), 1e-300), 0.0, 1.0);
        best = std::min(best, (ring[j] + t * d - p).norm());
    }
    return best;
}

inline double distance_to_segment(const Vec2& x, const Vec2& p, const Vec2& q) {
    const Vec2 d = q - p;
    const double t = std::clamp((x - p).dot(d) / std::max(d.squaredNorm(), 1e-300), 0.0, 1.0);
    return (p + t * d - x).norm();
}

// Where segment pq meets segment ab: (t along pq, u along ab), both in [0, 1], or nothing
// when they are parallel or miss each other.
inline std::optional<std::pair<double, double>> segment_meeting(const Vec2& p, const Vec2& q, const Vec2& a, const Vec2& b) {
    const Vec2 r = q - p, s = b - a;
    const double d = cross(r, s);
    if (std::abs(d) <= 1e-12 * r.norm() * s.norm()) return std::nullopt;
    const double t = cross(a - p, s) / d;
    const double u = cross(a - p, r) / d;
    if (t < 0.0 || t > 1.0 || u < 0.0 || u > 1.0) return std::nullopt;
    return std::pair{t, u};
}

} // namespace ggg
