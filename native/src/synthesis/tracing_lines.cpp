// A street's line, as tracing lays it: from its start along its heading (kept to the grid
// of the streets around, where they run on one), its length and the bends of the example it
// copies; and bent to end where the street joins (tracing_stages.hpp).
#include "tracing_stages.hpp"

namespace ggg::growth_detail::tracing {

using namespace spatial; // bg, bgi, Point, Box, point, RTree, VertexEntry, EdgeEntry

std::optional<double> Tracer::local_grid(const Vec2& p) const {
    const double r = 3.0 * typical_;
    const Box window = spatial::around(p, r);
    double c = 0.0, sn = 0.0, total = 0.0;
    for (auto it = segments_.qbegin(bgi::intersects(window)); it != segments_.qend(); ++it) {
        const EdgeId e = it->second;
        const Vec2* q = g_.geometry_begin(e);
        for (std::size_t i = 0; i + 1 < g_.geometry_size(e); ++i) {
            if ((0.5 * (q[i] + q[i + 1]) - p).squaredNorm() > r * r) continue;
            const Vec2 d = q[i + 1] - q[i];
            const double length = d.norm();
            const double a = 4.0 * angle_of(d);
            c += length * std::cos(a);
            sn += length * std::sin(a);
            total += length;
        }
    }
    if (total < 2.0 * typical_ || std::hypot(c, sn) / total < 0.5) return std::nullopt;
    return std::atan2(sn, c) / 4.0;
}

double Tracer::on_grid(double heading, const Vec2& p) const {
    const std::optional<double> grid = local_grid(p);
    if (!grid) return heading;
    const double quarter = M_PI / 2;
    const double k = std::round((heading - *grid) / quarter);
    const double snapped = *grid + k * quarter;
    return std::abs(wrap(heading - snapped)) <= grid_tolerance_ ? snapped : heading;
}

std::vector<Vec2> Tracer::lay_from(const Vec2& p, const Street& s) const {
    // A street from the base tried again keeps the heading it is tried at: turned back onto the
    // grid, each retry, turned a little further, would be the heading that failed again. A
    // street going on straight across a corner keeps the line of the street it continues.
    const Vec2 x = s.length * unit(s.retries > 0 || s.closes_corner ? s.heading : on_grid(s.heading, p));
    std::vector<Vec2> line;
    for (const Vec2& q : s.shape) line.push_back(p + Vec2(x.x() * q.x() - x.y() * q.y(), x.y() * q.x() + x.x() * q.y()));
    return line;
}

std::vector<Vec2> Tracer::warped(std::vector<Vec2> line, const Vec2& to) {
    const Vec2 start = line.front(), end = line.back();
    const Vec2 old_chord = end - start, new_chord = to - start;
    const double old_length = old_chord.norm(), new_length = new_chord.norm();
    if (old_length < 1e-9 || new_length < 1e-9) return {start, to};
    const double turn = angle_of(new_chord) - angle_of(old_chord);
    const double scale = new_length / old_length;
    const Vec2 r = unit(turn) * scale;
    for (Vec2& q : line) {
        const Vec2 d = q - start;
        q = start + Vec2(r.x() * d.x() - r.y() * d.y(), r.y() * d.x() + r.x() * d.y());
    }
    line.back() = to;
    return line;
}

} // namespace ggg::growth_detail::tracing
