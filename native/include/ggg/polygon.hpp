#pragma once
// A region as the synthesis stages take it: a simple polygon in a graph's metres, its corners
// in order (either direction), not closed (the last corner is not a copy of the first).
#include <algorithm>
#include <cmath>
#include <limits>
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

} // namespace ggg
