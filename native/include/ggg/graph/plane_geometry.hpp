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

#include <Eigen/Geometry>

#include "ggg/graph/geometric_graph.hpp"
#include "ggg/graph/similarity.hpp"

namespace ggg {

inline double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

// v turned anticlockwise by `angle` radians.
inline Vec2 rotated(const Vec2& v, double angle) {
    const double c = std::cos(angle), s = std::sin(angle);
    return {c * v.x() - s * v.y(), s * v.x() + c * v.y()};
}

// The smallest box holding the points from `first` to `last` (empty for none).
template <typename It>
Eigen::AlignedBox2d bounds(It first, It last) {
    Eigen::AlignedBox2d box;
    for (; first != last; ++first) box.extend(*first);
    return box;
}

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

// The polyline of edge e of g read from its end v (its first point at v).
inline std::vector<Vec2> polyline_from(const GeometricGraph& g, EdgeId e, VertexId v) {
    std::vector<Vec2> line(g.geometry_begin(e), g.geometry_begin(e) + static_cast<std::ptrdiff_t>(g.geometry_size(e)));
    if (g.edges[static_cast<std::size_t>(e)][0] != v) std::reverse(line.begin(), line.end());
    return line;
}

// The first piece of edge e of g from its end v: from v to the next point of its polyline.
inline Vec2 first_piece(const GeometricGraph& g, EdgeId e, VertexId v) {
    const Vec2* p = g.geometry_begin(e);
    const std::size_t n = g.geometry_size(e);
    return g.edges[static_cast<std::size_t>(e)][0] == v ? p[1] - p[0] : p[n - 2] - p[n - 1];
}

// The point `distance` along the polyline from its first point; none beyond its end.
inline std::optional<Vec2> point_along(const std::vector<Vec2>& line, double distance) {
    double walked = 0.0;
    for (std::size_t i = 0; i + 1 < line.size(); ++i) {
        const double step = (line[i + 1] - line[i]).norm();
        if (step > 0 && walked + step >= distance) return line[i] + (line[i + 1] - line[i]) * ((distance - walked) / step);
        walked += step;
    }
    return std::nullopt;
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

// True when segments ab and cd cross or touch anywhere but at an end they share.
inline bool segments_meet(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
    const double eps = 1e-9 * std::max({(b - a).norm(), (d - c).norm(), 1.0});
    auto same = [&](const Vec2& p, const Vec2& q) { return (p - q).norm() <= eps; };
    const bool shared = same(a, c) || same(a, d) || same(b, c) || same(b, d);
    const double d1 = cross(b - a, c - a), d2 = cross(b - a, d - a);
    const double d3 = cross(d - c, a - c), d4 = cross(d - c, b - c);
    if (((d1 > eps && d2 < -eps) || (d1 < -eps && d2 > eps)) && ((d3 > eps && d4 < -eps) || (d3 < -eps && d4 > eps))) return true;
    if (shared) return false; // touching at a common end is how streets meet
    auto on = [&](const Vec2& p, const Vec2& q, const Vec2& r) { // r on segment pq
        return std::abs(cross(q - p, r - p)) <= eps * (q - p).norm() && (r - p).dot(r - q) <= 0;
    };
    return on(a, b, c) || on(a, b, d) || on(c, d, a) || on(c, d, b);
}

// Two sides of the polygon that cross or touch, other than neighbours at their shared corner
// (indices of their first corners, the smaller first), or nothing for a simple polygon. Sides
// are tested against those whose boxes overlap theirs, in order of their left ends, so a
// region of many corners is checked in about n log n.
inline std::optional<std::pair<std::size_t, std::size_t>> first_self_crossing(const std::vector<Vec2>& ring) {
    const std::size_t n = ring.size();
    if (n < 4) return std::nullopt; // a triangle cannot cross itself
    auto a = [&](std::size_t i) -> const Vec2& { return ring[i]; };
    auto b = [&](std::size_t i) -> const Vec2& { return ring[(i + 1) % n]; };
    std::vector<std::size_t> order(n);
    for (std::size_t i = 0; i < n; ++i) order[i] = i;
    auto left = [&](std::size_t i) { return std::min(a(i).x(), b(i).x()); };
    std::sort(order.begin(), order.end(), [&](std::size_t i, std::size_t j) { return left(i) < left(j); });
    std::optional<std::pair<std::size_t, std::size_t>> found;
    for (std::size_t k = 0; k < n; ++k) {
        const std::size_t i = order[k];
        const double right = std::max(a(i).x(), b(i).x());
        const double low = std::min(a(i).y(), b(i).y()), high = std::max(a(i).y(), b(i).y());
        for (std::size_t m = k + 1; m < n && left(order[m]) <= right; ++m) {
            const std::size_t j = order[m];
            if (std::min(a(j).y(), b(j).y()) > high || std::max(a(j).y(), b(j).y()) < low) continue;
            if ((i + 1) % n == j || (j + 1) % n == i) continue; // neighbours share a corner
            if (!segments_meet(a(i), b(i), a(j), b(j))) continue;
            const std::pair<std::size_t, std::size_t> sides{std::min(i, j), std::max(i, j)};
            if (!found || sides < *found) found = sides;
        }
    }
    return found;
}

// The area of the block to the left of the street u -> v, walking round it by always taking
// the sharpest left turn; 0 when the walk does not come back within `max_steps` streets (a
// block too large to matter, or one that the streets known here do not close) or goes
// round the outside (clockwise). `neighbours(w)` lists the streets at w.
template <class Neighbours>
double block_left_of(const std::vector<Vec2>& positions, Neighbours&& neighbours, VertexId u, VertexId v, std::size_t max_steps = 64) {
    const VertexId start_u = u, start_v = v;
    double twice_area = 0.0;
    for (std::size_t step = 0; step < max_steps; ++step) {
        const Vec2& pu = positions[static_cast<std::size_t>(u)];
        const Vec2& pv = positions[static_cast<std::size_t>(v)];
        twice_area += cross(pu, pv);
        // At v, the street that turns most to the left, i.e. the first clockwise from v -> u.
        const Vec2 back = pu - pv;
        const double back_angle = std::atan2(back.y(), back.x());
        VertexId next = -1;
        double best = 0.0;
        for (VertexId w : neighbours(v)) {
            const Vec2 d = positions[static_cast<std::size_t>(w)] - pv;
            double turn = back_angle - std::atan2(d.y(), d.x());
            while (turn <= 1e-12) turn += 2.0 * M_PI;
            while (turn > 2.0 * M_PI + 1e-12) turn -= 2.0 * M_PI;
            if (next < 0 || turn < best) {
                next = w;
                best = turn;
            }
        }
        if (next < 0) return 0.0;
        u = v;
        v = next;
        if (u == start_u && v == start_v) return twice_area > 0 ? 0.5 * twice_area : 0.0;
    }
    return 0.0;
}

} // namespace ggg
