#pragma once
// A 2-D similarity transform x -> s R(theta) x + t, stored as the complex-number form
// (a, b) = s (cos theta, sin theta). Rules and nonterminal vertices carry one as their
// local frame; composing frames through levels is a product of these.
#include <cmath>

#include <Eigen/Core>

namespace ggg {

using Vec2 = Eigen::Vector2d;

struct Similarity2 {
    double a = 1.0; // s cos(theta)
    double b = 0.0; // s sin(theta)
    Vec2 t = Vec2::Zero();

    static Similarity2 identity() { return {}; }
    static Similarity2 from(double scale, double angle_rad, const Vec2& translation) {
        return {scale * std::cos(angle_rad), scale * std::sin(angle_rad), translation};
    }

    double scale() const { return std::hypot(a, b); }
    double angle() const { return std::atan2(b, a); }

    Vec2 apply(const Vec2& p) const { return {a * p.x() - b * p.y() + t.x(), b * p.x() + a * p.y() + t.y()}; }
    Vec2 apply_linear(const Vec2& v) const { return {a * v.x() - b * v.y(), b * v.x() + a * v.y()}; }

    // (*this) after `inner`: x -> this(inner(x)).
    Similarity2 operator*(const Similarity2& inner) const {
        return {a * inner.a - b * inner.b, a * inner.b + b * inner.a, apply(inner.t)};
    }

    Similarity2 inverse() const {
        const double n = a * a + b * b;
        const double ia = a / n;
        const double ib = -b / n;
        const Vec2 it{-(ia * t.x() - ib * t.y()), -(ib * t.x() + ia * t.y())};
        return {ia, ib, it};
    }
};

} // namespace ggg
