// The isogroup detection's patterns, fitted to their occurrences (detection_stages.hpp).
#include "detection_stages.hpp"

#include <cmath>

#include <boost/geometry.hpp>
#include <boost/geometry/geometries/multi_point.hpp>
#include <boost/geometry/geometries/point_xy.hpp>
#include <boost/geometry/geometries/polygon.hpp>

namespace ggg::detection_detail {

namespace {

// Brings `positions` to the canonical frame (centroid 0, RMS radius 1); false when they
// all coincide.
bool canonicalise(std::vector<Vec2>& positions) {
    const Spread s = spread_of(positions);
    if (s.degenerate) return false;
    for (Vec2& p : positions) p = (p - s.centroid) / s.rms;
    return true;
}

} // namespace

double hull_area(std::span<const Vec2> points) {
    namespace bg = boost::geometry;
    using Point = bg::model::d2::point_xy<double>;
    if (points.size() < 3) return 0.0;
    bg::model::multi_point<Point> cloud;
    cloud.reserve(points.size());
    for (const Vec2& p : points) cloud.emplace_back(p.x(), p.y());
    bg::model::polygon<Point> hull;
    bg::convex_hull(cloud, hull);
    return std::abs(bg::area(hull));
}

Similarity2 fit_canonical(const std::vector<Vec2>& p, const Vec2* y, std::size_t k) {
    Vec2 centroid = Vec2::Zero();
    for (std::size_t j = 0; j < k; ++j) centroid += y[j];
    centroid /= static_cast<double>(k);
    double re = 0.0;
    double im = 0.0;
    double norm = 0.0;
    for (std::size_t j = 0; j < k; ++j) {
        const Vec2 d = y[j] - centroid;
        re += p[j].x() * d.x() + p[j].y() * d.y();
        im += p[j].x() * d.y() - p[j].y() * d.x();
        norm += p[j].squaredNorm();
    }
    Similarity2 t;
    if (norm > 0.0) {
        t.a = re / norm;
        t.b = im / norm;
    }
    t.t = centroid;
    return t;
}

void refine(Isogroup& group, const GeometricGraph& g, int rounds) {
    const std::size_t k = group.order();
    const std::size_t n = group.frequency();
    if (!canonicalise(group.pattern.positions)) return;
    // The occurrences' positions, gathered once: the rounds then read them in order.
    std::vector<Vec2> ys(n * k);
    for (std::size_t i = 0; i < n * k; ++i) ys[i] = g.positions[static_cast<std::size_t>(group.vertices[i])];
    for (int round = 0; round <= rounds; ++round) {
        std::vector<Vec2> mean(k, Vec2::Zero());
        double scale_sum = 0.0;
        for (std::size_t i = 0; i < n; ++i) {
            const Vec2* y = ys.data() + i * k;
            Similarity2& t = group.transforms[i];
            t = fit_canonical(group.pattern.positions, y, k);
            const double s = std::sqrt(t.a * t.a + t.b * t.b);
            scale_sum += s;
            if (round == rounds || !(s > 0.0)) continue;
            const Similarity2 inverse = t.inverse();
            for (std::size_t j = 0; j < k; ++j) mean[j] += inverse.apply(y[j]);
        }
        group.pattern.metres_per_unit = n > 0 && scale_sum > 0.0 ? scale_sum / static_cast<double>(n) : 1.0;
        if (round == rounds) break;
        for (Vec2& m : mean) m /= static_cast<double>(n);
        if (!canonicalise(mean)) break;
        group.pattern.positions = std::move(mean);
    }
}

} // namespace ggg::detection_detail
