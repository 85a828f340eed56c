// The second stage of tracing: the streets of the base that reach the region, where tracing
// starts. A dead end or a junction with an open side that points into the region goes on into
// it, straight, with a street of the city that goes on about straight (tracing_stages.hpp).
#include "tracing_stages.hpp"

#include <algorithm>
#include <limits>

#include "ggg/graph/plane_geometry.hpp"

namespace ggg::growth_detail::tracing {

void Tracer::seed() {
    const double reach = s_.border_m + std::max(3.0 * typical_, long_);
    // A new side street (below) starts only next to the region: further out it would add a
    // street to the city around the region rather than continue one into it.
    const double near = s_.border_m + 0.5 * typical_;
    // (enters, whether it is a new side street, the street)
    std::vector<std::tuple<double, bool, Street>> seeds;
    for (std::size_t v = 0; v < base_vertices_; ++v) {
        const auto id = static_cast<VertexId>(v);
        if (degree(id) >= 4 || across_[v]) continue;
        const Vec2 p = g_.positions[v];
        const bool in = inside(region_, p);
        const double away = in ? 0.0 : distance_to_ring(region_, p);
        if (away > reach) continue;
        // Straight on from each street at v, where that leaves room and enters the region.
        std::optional<std::pair<double, Street>> best;
        bool side = false;
        for (const EdgeId e : adjacency_[v]) {
            if (!traced_class(g_.edge_highway[static_cast<std::size_t>(e)])) continue;
            const Vec2 back = leaving(g_, e, id) - p;
            if (back.norm() < 1e-9) continue;
            const Vec2 ahead = -back.normalized();
            if (clearance(id, ahead) < M_PI / 3) continue;
            const double enters = entry_distance(p, ahead, reach);
            if (enters < 0) continue;
            Street s;
            s.from = id;
            s.heading = angle_of(ahead);
            s.highway = g_.edge_highway[static_cast<std::size_t>(e)];
            s.main = main_class(s.highway);
            if (!best || enters < best->first) best = std::pair{enters, s};
        }
        // A junction whose streets leave one side open towards the region (a street of it
        // was cut there): a street across that side, down the middle of the gap.
        if (!best && degree(id) >= 2 && away <= near) {
            std::vector<double> angles;
            for (const EdgeId e : adjacency_[v]) angles.push_back(angle_of(leaving(g_, e, id) - p));
            std::sort(angles.begin(), angles.end());
            double gap = 0.0, middle = 0.0;
            for (std::size_t i = 0; i < angles.size(); ++i) {
                const double next = i + 1 < angles.size() ? angles[i + 1] : angles[0] + 2 * M_PI;
                if (next - angles[i] > gap) gap = next - angles[i], middle = angles[i] + 0.5 * (next - angles[i]);
            }
            const double enters = gap >= 0.8 * M_PI ? entry_distance(p, unit(middle), reach) : -1.0;
            if (enters >= 0) {
                Street s;
                s.from = id;
                s.heading = wrap(middle);
                s.highway = common_class_;
                s.main = false;
                best = std::pair{enters, s};
                side = true;
            }
        }
        // Else straight to the region, where that leaves room at v (a vertex whose streets
        // all ran into the region has none left to go on from).
        if (!best && !in && away <= near) {
            const Vec2 towards = nearest_on_ring(p) - p;
            const double enters = towards.norm();
            if (enters > 1e-9 && clearance(id, towards) >= M_PI / 3) {
                Street s;
                s.from = id;
                s.heading = angle_of(towards);
                s.highway = common_class_;
                s.main = false;
                best = std::pair{enters, s};
                side = true;
            }
        }
        if (!best) continue;
        seeds.emplace_back(best->first, side, best->second);
    }
    if (seeds.empty() && s_.no_street_reaches) {
        if (auto access = access_seed(region_size_)) seeds.emplace_back(access->first, false, access->second);
    }
    // The streets that go on first, then new side streets, each as far from the seeds before
    // it and from the base's junctions as the city's junctions are apart: a street along the
    // region, split by its map into many short edges, gets side streets at the city's spacing,
    // not one at every split.
    std::sort(seeds.begin(), seeds.end(), [](const auto& a, const auto& b) {
        return std::tie(std::get<1>(a), std::get<0>(a), std::get<2>(a).from) < std::tie(std::get<1>(b), std::get<0>(b), std::get<2>(b).from);
    });
    const double apart = crowd_ * typical_;
    std::vector<Vec2> starts;
    for (auto& [enters, side, s] : seeds) {
        const Vec2 p = g_.positions[static_cast<std::size_t>(s.from)];
        if (side) {
            bool crowded = std::any_of(starts.begin(), starts.end(), [&](const Vec2& q) { return (q - p).norm() < apart; });
            for (auto it = vertices_.qbegin(spatial::bgi::intersects(spatial::around(p, apart))); !crowded && it != vertices_.qend(); ++it) {
                const VertexId w = it->second;
                crowded = w != s.from && degree(w) >= 3 && (g_.positions[static_cast<std::size_t>(w)] - p).norm() < apart;
            }
            if (crowded) continue;
        }
        // Each seed continues with a street of the city that goes on about straight.
        const Branch* through = nullptr;
        for (int attempt = 0; attempt < 64 && !through; ++attempt) {
            const Example& example = example_for(s.main);
            for (const Branch& b : example.branches) {
                if (std::abs(b.turn) < M_PI / 6) through = &b;
            }
        }
        if (!through) continue;
        starts.push_back(p);
        // Straight until it is in the region: the base's street goes on as it ran.
        s.min_length = enters + 0.25 * typical_;
        s.length = std::max(through->length, s.min_length);
        s.shape = {Vec2(0, 0), Vec2(1, 0)};
        s.order = order_++;
        queue_.push(s);
        ++report_.seeds;
    }
}

std::optional<std::pair<double, Street>> Tracer::access_seed(double reach) const {
    // The city's vertices nearest the region first; a handful is enough (the nearest that
    // reach it straight are few streets apart).
    std::vector<std::pair<double, VertexId>> near;
    for (std::size_t v = 0; v < base_vertices_; ++v) {
        const auto id = static_cast<VertexId>(v);
        if (degree(id) == 0 || degree(id) >= 4) continue;
        const double away = distance_to_ring(region_, g_.positions[v]);
        if (away <= reach && !inside(region_, g_.positions[v])) near.emplace_back(away, id);
    }
    std::sort(near.begin(), near.end());
    if (near.size() > 64) near.resize(64);
    for (const auto& [away, id] : near) {
        const Vec2 p = g_.positions[static_cast<std::size_t>(id)];
        // To the region's nearest point, or a little inside it from there where that is a
        // corner (a street along the region's side would enter it nowhere).
        const Vec2 nearest = nearest_on_ring(p);
        Vec2 towards = nearest - p;
        if (towards.norm() < 1e-9) continue;
        if (entry_distance(p, towards.normalized(), reach) < 0 || !inside(region_, p + towards + 0.25 * typical_ * towards.normalized())) {
            Vec2 centre = Vec2::Zero();
            for (const Vec2& q : region_) centre += q;
            centre /= static_cast<double>(region_.size());
            towards = nearest + 0.25 * typical_ * (centre - nearest).normalized() - p;
        }
        if (s_.grid_angle) {
            // Along the grid: of its four ways, the one nearest the region's way that enters it.
            std::optional<Vec2> along;
            for (int k = 0; k < 4; ++k) {
                const Vec2 d = unit(*s_.grid_angle + k * M_PI / 2);
                const double enters = entry_distance(p, d, reach);
                // (Not a long way round along the region's side to where it enters.)
                if (enters >= 0 && enters <= 1.5 * away + typical_ && (!along || d.dot(towards) > along->normalized().dot(towards))) along = enters * d;
            }
            if (!along) continue;
            towards = *along;
        }
        if (clearance(id, towards) < M_PI / 3) continue;
        // Straight on a little into the region, across no street on the way.
        const Vec2 end = p + towards + 0.25 * typical_ * towards.normalized();
        if (first_hit({p, end}, id)) continue;
        Street s;
        s.from = id;
        s.heading = angle_of(towards);
        const auto& at = adjacency_[static_cast<std::size_t>(id)];
        // Of the class of the street it leaves from, where tracing lays such streets.
        s.highway = traced_class(g_.edge_highway[static_cast<std::size_t>(at.front())]) ? g_.edge_highway[static_cast<std::size_t>(at.front())]
                                                                                        : common_class_;
        s.main = main_class(s.highway);
        return std::pair{towards.norm(), s};
    }
    return std::nullopt;
}

void Tracer::join_close_ends() {
    const double snap = 0.3 * snap_scale();
    auto grown_street_at = [&](VertexId w) {
        const auto& at = adjacency_[static_cast<std::size_t>(w)];
        return std::any_of(at.begin(), at.end(), [&](EdgeId e) { return static_cast<std::size_t>(e) >= fixed_edges_; });
    };
    for (std::size_t v = 0; v < base_vertices_; ++v) {
        const auto id = static_cast<VertexId>(v);
        if (degree(id) != 1 || across_[v]) continue;
        const Vec2 p = g_.positions[v];
        if (!inside(region_, p) && distance_to_ring(region_, p) > s_.border_m) continue;
        std::optional<VertexId> best;
        double best_d = snap;
        for (auto it = vertices_.qbegin(spatial::bgi::intersects(spatial::around(p, snap))); it != vertices_.qend(); ++it) {
            const VertexId w = it->second;
            const double d = (g_.positions[static_cast<std::size_t>(w)] - p).norm();
            if (w == id || d >= best_d || degree(w) >= 4 || adjacent(id, w) || !grown_street_at(w)) continue;
            best = w, best_d = d;
        }
        if (!best) continue;
        const Vec2 q = g_.positions[static_cast<std::size_t>(*best)];
        const std::vector<Vec2> line{p, q};
        if (first_hit(line, id, *best) || clearance(*best, p - q) < min_angle_ || clearance(id, q - p) < min_angle_) continue;
        add_street(id, *best, line, g_.edge_highway[static_cast<std::size_t>(adjacency_[v].front())]);
        ++report_.joined;
    }
}

Vec2 Tracer::nearest_on_ring(const Vec2& p) const {
    Vec2 best = region_.front();
    double best_d = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0, j = region_.size() - 1; i < region_.size(); j = i++) {
        const Vec2 d = region_[i] - region_[j];
        const double t = std::clamp((p - region_[j]).dot(d) / std::max(d.squaredNorm(), 1e-300), 0.0, 1.0);
        const Vec2 q = region_[j] + t * d;
        if ((q - p).norm() < best_d) best = q, best_d = (q - p).norm();
    }
    return best;
}

double Tracer::entry_distance(const Vec2& p, const Vec2& d, double reach) const {
    if (inside(region_, p)) return 0.0;
    const Vec2 q = p + reach * d;
    double first = -1;
    for (std::size_t i = 0, j = region_.size() - 1; i < region_.size(); j = i++) {
        const auto m = segment_meeting(p, q, region_[j], region_[i]);
        if (m && (first < 0 || m->first < first)) first = m->first;
    }
    return first < 0 ? -1.0 : first * reach;
}

} // namespace ggg::growth_detail::tracing
