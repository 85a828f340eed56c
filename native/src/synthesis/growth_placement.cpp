// The main stage of growth: rules placed one at a time on the streets of the frontier, by
// forward derivation in a copy of the streets around, each kept only where it fits (inside
// the region, crossing nothing, crowding nothing, closing no sliver); see growth_stages.hpp.
#include "growth_stages.hpp"

#include <algorithm>
#include <string>
#include <unordered_map>

#include "ggg/error.hpp"
#include "ggg/grammar/rewriting.hpp"
#include "street_tracing.hpp"

namespace ggg::growth_detail {

using namespace spatial; // bg, bgi, Point, Box, point, RTree, VertexEntry, EdgeEntry

Vec2 Grower::principal_axis() const {
    double sxx = 0, sxy = 0, syy = 0;
    for (const Vec2& p : region_) {
        const Vec2 d = p - centre_;
        sxx += d.x() * d.x();
        sxy += d.x() * d.y();
        syy += d.y() * d.y();
    }
    const double angle = 0.5 * std::atan2(2 * sxy, sxx - syy);
    return {std::cos(angle), std::sin(angle)};
}

bool Grower::glue(const FrontierEdge& at) {
    ++report_->attempts;
    std::discrete_distribution<std::size_t> rule(weights_.begin(), weights_.end());
    const Prototype& p = prototypes_[rule(rng_)];
    const Vec2 a = g_.positions[static_cast<std::size_t>(at.a)];
    const Vec2 b = g_.positions[static_cast<std::size_t>(at.b)];
    const double length = (b - a).norm();
    if (length <= 0) return false;
    // The rule's edges whose length, at about the rule's size, fits the street.
    std::vector<std::size_t> fitting;
    for (std::size_t e = 0; e < p.edges.size(); ++e) {
        const double l = (p.positions[static_cast<std::size_t>(p.edges[e][1])] - p.positions[static_cast<std::size_t>(p.edges[e][0])]).norm();
        const double size = length / l;
        if (l > 0 && size >= p.size_m / (1.0 + 2.0 * o_.size_jitter) && size <= p.size_m * (1.0 + 2.0 * o_.size_jitter)) {
            fitting.push_back(e);
        }
    }
    if (fitting.empty()) return attach(p, at);
    std::uniform_int_distribution<std::size_t> pick(0, fitting.size() - 1);
    auto [u, v] = p.edges[fitting[pick(rng_)]];
    if (std::bernoulli_distribution(0.5)(rng_)) std::swap(u, v); // the other side of the street
    const Vec2 pu = p.positions[static_cast<std::size_t>(u)];
    const Vec2 d = p.positions[static_cast<std::size_t>(v)] - pu;
    const double size = length / d.norm();
    const double angle = std::atan2((b - a).y(), (b - a).x()) - std::atan2(d.y(), d.x());
    const Vec2 origin = a - Similarity2::from(size, angle, Vec2::Zero()).apply_linear(pu);
    // A square rule stays on the grid of the streets around (or of the first square rule
    // placed): its streets must run along the grid's.
    const double tolerance = o_.grid_tolerance_deg * M_PI / 180.0;
    if (grid_city_ && o_.grid_tolerance_deg > 0 && p.squareness >= 0.6 && grid_angle_) {
        if (std::abs(wrap_quarter(p.square_angle + angle - *grid_angle_)) > tolerance) {
            // The streets around looked like a grid, but none of the rules fits it: the
            // first square rule that is placed sets the grid instead.
            if (++report_->rejected_off_grid >= 20 && report_->placements == 0) grid_angle_.reset();
            return false;
        }
    }
    if (!place(p, Frame{size, angle * 180.0 / M_PI}, origin, at.a)) return false;
    if (!grid_angle_ && p.squareness >= 0.6) grid_angle_ = wrap_quarter(p.square_angle + angle);
    return true;
}

bool Grower::attach(const Prototype& p, const FrontierEdge& at) {
    const bool first = std::bernoulli_distribution(0.5)(rng_);
    const VertexId v = first ? at.a : at.b;
    const Vec2 from_street = g_.positions[static_cast<std::size_t>(v)] - g_.positions[static_cast<std::size_t>(first ? at.b : at.a)];
    std::uniform_int_distribution<std::size_t> vertex(0, p.attach.size() - 1);
    const Vec2 pj = p.positions[static_cast<std::size_t>(p.attach[vertex(rng_)])];
    const Vec2 body = p.centroid - pj;
    double angle = std::atan2(from_street.y(), from_street.x()) - std::atan2(body.y(), body.x());
    if (grid_city_ && grid_angle_ && p.squareness >= 0.6) angle += wrap_quarter(*grid_angle_ - (p.square_angle + angle));
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    const double size = p.size_m * (1.0 + o_.size_jitter * unit(rng_));
    const Vec2 origin = g_.positions[static_cast<std::size_t>(v)] - Similarity2::from(size, angle, Vec2::Zero()).apply_linear(pj);
    if (!place(p, Frame{size, angle * 180.0 / M_PI}, origin, v)) return false;
    if (!grid_angle_ && p.squareness >= 0.6) grid_angle_ = wrap_quarter(p.square_angle + angle);
    return true;
}

void Grower::seed_at_centre() {
    std::vector<std::size_t> order(prototypes_.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) { return prototypes_[x].weight > prototypes_[y].weight; });
    const Vec2 axis = principal_axis();
    const double angle = std::atan2(axis.y(), axis.x());
    for (std::size_t i : order) {
        const Prototype& p = prototypes_[i];
        // A square rule turned onto the grid of the city's streets near the region, if they run on one.
        const double turn = grid_angle_ && p.squareness >= 0.6 ? angle + wrap_quarter(*grid_angle_ - (p.square_angle + angle)) : angle;
        const Vec2 origin = centre_ - Similarity2::from(p.size_m, turn, Vec2::Zero()).apply_linear(p.centroid);
        ++report_->attempts;
        if (!place(p, Frame{p.size_m, turn * 180.0 / M_PI}, origin, -1)) continue;
        if (p.squareness >= 0.6 && !grid_angle_) grid_angle_ = wrap_quarter(p.square_angle + turn);
        return;
    }
}

void Grower::place_by_hand(const RulePlacement& placed) {
    const auto it = std::find_if(prototypes_.begin(), prototypes_.end(), [&](const Prototype& p) { return p.symbol == placed.symbol; });
    if (it == prototypes_.end()) {
        throw UsageError("a placed rule has symbol " + std::to_string(placed.symbol) + ", which has no rule deriving to streets");
    }
    Frame frame = placed.frame;
    if (!(frame.scale > 0)) frame.scale = it->size_m;
    ++report_->attempts;
    place(*it, frame, placed.position, -1, /*by_hand=*/true);
    report_->hand_placements.push_back(last_outcome_);
}

bool Grower::reject(PlacementOutcome why) {
    last_outcome_ = why;
    switch (why) {
    case PlacementOutcome::outside: ++report_->rejected_outside; break;
    case PlacementOutcome::crossing: ++report_->rejected_crossing; break;
    case PlacementOutcome::crowded: ++report_->rejected_crowded; break;
    case PlacementOutcome::star: ++report_->rejected_star; break;
    case PlacementOutcome::sharp: ++report_->rejected_sharp; break;
    case PlacementOutcome::small_block: ++report_->rejected_small_block; break;
    case PlacementOutcome::placed:
    case PlacementOutcome::nothing_new: break;
    }
    return false;
}

bool Grower::place(const Prototype& p, const Frame& frame, const Vec2& origin, VertexId anchor, bool by_hand) {
    const Similarity2 f = frame.at(origin);
    const double reach = frame.scale * (p.radius + (p.centroid).norm()) + 2.0 * frame.scale * p.edge_length;
    const Vec2 middle = f.apply(p.centroid);
    // The streets around, as their own small graph.
    GeometricGraph local;
    local.origin = g_.origin;
    std::vector<VertexId> global_of;
    std::unordered_map<VertexId, VertexId> local_of;
    const Box window = spatial::around(middle, reach);
    for (auto it = vertices_.qbegin(bgi::intersects(window)); it != vertices_.qend(); ++it) {
        local_of.emplace(it->second, static_cast<VertexId>(local.vertex_count()));
        local.add_vertex(g_.positions[static_cast<std::size_t>(it->second)]);
        global_of.push_back(it->second);
    }
    for (std::size_t l = 0; l < global_of.size(); ++l) {
        for (VertexId w : adjacency_[static_cast<std::size_t>(global_of[l])]) {
            const auto it = local_of.find(w);
            if (it != local_of.end() && static_cast<std::size_t>(it->second) > l) {
                local.add_edge(static_cast<VertexId>(l), it->second, EdgeAttributes{});
            }
        }
    }
    const std::size_t old_edges = local.edge_count();
    place_nonterminal(local, p.symbol, origin, frame);
    DeriveOptions d;
    d.max_steps = depth_ + 1;
    d.max_vertices = local.vertex_count() + 20'000;
    d.tolerance = o_.snap; // relative to the rule's size: vertices this close become one
    d.grammar_validated = true;
    const DeriveReport derived = derive(local, grammar_, d);

    // What the placement adds: new vertices, and edges that were not there.
    const double typical = frame.scale * p.edge_length;
    std::vector<VertexId> global(local.vertex_count(), -1);
    std::vector<std::size_t> fresh;
    for (std::size_t v = 0; v < local.vertex_count(); ++v) {
        if (local.symbols[v] != 0) continue;
        const VertexId s = derived.source_vertex[v];
        if (s >= 0 && static_cast<std::size_t>(s) < global_of.size()) {
            global[v] = global_of[static_cast<std::size_t>(s)];
            continue;
        }
        const Vec2& q = local.positions[v];
        if (!inside(region_, q)) {
            return reject(PlacementOutcome::outside);
        }
        for (auto it = vertices_.qbegin(bgi::nearest(point(q), 1)); it != vertices_.qend(); ++it) {
            if ((g_.positions[static_cast<std::size_t>(it->second)] - q).norm() < o_.spacing * typical) {
                return reject(PlacementOutcome::crowded);
            }
        }
        fresh.push_back(v);
    }
    if (fresh.empty()) return reject(PlacementOutcome::nothing_new);
    std::vector<std::array<VertexId, 2>> added; // local ids
    std::vector<HighwayClass> classes;
    for (std::size_t e = 0; e < local.edge_count(); ++e) {
        const auto [a, b] = local.edges[e];
        if (local.symbols[static_cast<std::size_t>(a)] || local.symbols[static_cast<std::size_t>(b)]) continue;
        const VertexId ga = global[static_cast<std::size_t>(a)], gb = global[static_cast<std::size_t>(b)];
        if (ga >= 0 && gb >= 0) {
            const auto& n = adjacency_[static_cast<std::size_t>(ga)];
            if (e < old_edges || std::find(n.begin(), n.end(), gb) != n.end()) continue;
        }
        added.push_back({a, b});
        classes.push_back(local.edge_highway[e]);
    }
    // No junction of more than four streets (a star), which snapping would otherwise pile
    // up where several of the rule's vertices land on one street vertex.
    if (!by_hand) {
        std::unordered_map<VertexId, std::size_t> gained; // by global id, or -1 - local id when new
        for (const auto& [a, b] : added) {
            for (const VertexId x : {a, b}) {
                const VertexId key = global[static_cast<std::size_t>(x)] >= 0 ? global[static_cast<std::size_t>(x)] : -1 - x;
                const std::size_t before = key >= 0 ? adjacency_[static_cast<std::size_t>(key)].size() : 0;
                if (before + ++gained[key] > 4) {
                    return reject(PlacementOutcome::star);
                }
            }
        }
    }
    // No new street may meet another at a sharp corner (under 30 degrees, as tracing keeps
    // to): a rule turned to fit a frontier street can meet it, or the streets at the vertex it
    // snaps to, at any angle, and Helsinki grew thin wedges of streets crossing at 15 degrees.
    if (!by_hand) {
        std::unordered_map<VertexId, std::vector<Vec2>> leaving; // by global id, or -1 - local id when new
        auto key_of = [&](VertexId x) { return global[static_cast<std::size_t>(x)] >= 0 ? global[static_cast<std::size_t>(x)] : -1 - x; };
        for (const auto& [a, b] : added) {
            leaving[key_of(a)].push_back(local.positions[static_cast<std::size_t>(b)] - local.positions[static_cast<std::size_t>(a)]);
            leaving[key_of(b)].push_back(local.positions[static_cast<std::size_t>(a)] - local.positions[static_cast<std::size_t>(b)]);
        }
        const double cos_sharp = std::cos(M_PI / 6);
        for (const auto& [key, fresh_directions] : leaving) {
            std::vector<Vec2> all = fresh_directions;
            if (key >= 0) {
                const Vec2 at = g_.positions[static_cast<std::size_t>(key)];
                for (const VertexId w : adjacency_[static_cast<std::size_t>(key)]) all.push_back(g_.positions[static_cast<std::size_t>(w)] - at);
            }
            for (std::size_t i = 0; i < fresh_directions.size(); ++i) {
                for (std::size_t k = 0; k < all.size(); ++k) {
                    const double ni = all[i].norm(), nk = all[k].norm();
                    if (k == i || ni < 1e-9 || nk < 1e-9) continue;
                    if (all[i].dot(all[k]) > cos_sharp * ni * nk) return reject(PlacementOutcome::sharp);
                }
            }
        }
    }
    // No new street may cross a street or another new one.
    for (std::size_t i = 0; i < added.size(); ++i) {
        const Vec2& a = local.positions[static_cast<std::size_t>(added[i][0])];
        const Vec2& b = local.positions[static_cast<std::size_t>(added[i][1])];
        if (crosses(a, b)) {
            return reject(PlacementOutcome::crossing);
        }
        for (std::size_t k = 0; k < i; ++k) {
            if (segments_meet(a, b, local.positions[static_cast<std::size_t>(added[k][0])], local.positions[static_cast<std::size_t>(added[k][1])])) {
                return reject(PlacementOutcome::crossing);
            }
        }
    }
    // No new street may run alongside a street closer than new vertices may come to one
    // (within 15 degrees of parallel, beside each other): the thin slivers between two such
    // streets are no blocks.
    if (!by_hand) {
        const double near = o_.spacing * typical;
        for (const auto& [ia, ib] : added) {
            const Vec2& a = local.positions[static_cast<std::size_t>(ia)];
            const Vec2& b = local.positions[static_cast<std::size_t>(ib)];
            const Vec2 along = b - a;
            const double length = along.norm();
            if (length < 1e-9) continue;
            for (auto it = segments_.qbegin(bgi::intersects(spatial::around(a, b, near))); it != segments_.qend(); ++it) {
                const Vec2* q = g_.geometry_begin(it->second);
                for (std::size_t k = 0; k + 1 < g_.geometry_size(it->second); ++k) {
                    const Vec2 r = q[k + 1] - q[k];
                    const double rl = r.norm();
                    if (rl < 1e-9 || std::abs(cross(along, r)) > std::sin(M_PI / 12) * length * rl) continue;
                    // Beside each other: the middle of the shorter within the other's span, and close.
                    const Vec2 mid = length < rl ? 0.5 * (a + b) : 0.5 * (q[k] + q[k + 1]);
                    const Vec2 s0 = length < rl ? q[k] : a, s1 = length < rl ? q[k + 1] : b;
                    const double t = (mid - s0).dot(s1 - s0) / (s1 - s0).squaredNorm();
                    if (t > 0.0 && t < 1.0 && distance_to_segment(mid, s0, s1) < near) return reject(PlacementOutcome::crowded);
                }
            }
        }
    }
    // No placement may make the streets around it denser than the city's next to the region
    // (as tracing holds its streets to it): where tracing left ground open, rules fill it as
    // densely as the city, not as densely as they fit.
    if (street_density_ > 0.0 && density_radius_ > 0.0 && !by_hand) {
        Vec2 centre = Vec2::Zero();
        for (std::size_t v : fresh) centre += local.positions[v];
        centre /= static_cast<double>(fresh.size());
        const double r = density_radius_;
        double length = 0.0;
        for (const auto& [ia, ib] : added) length += piece_within(local.positions[static_cast<std::size_t>(ia)], local.positions[static_cast<std::size_t>(ib)], centre, r);
        length += street_length_within(g_, segments_, centre, r);
        if (length > street_density_ * M_PI * r * r) return reject(PlacementOutcome::crowded);
        // ... nor more junctions than the city's there: a rule's small blocks, side by side,
        // would make many short streets where the city has fewer, longer ones.
        if (junction_density_ > 0.0) {
            std::vector<int> degree(local.vertex_count(), 0);
            for (const auto& [ia, ib] : added) ++degree[static_cast<std::size_t>(ia)], ++degree[static_cast<std::size_t>(ib)];
            std::size_t junctions = junctions_within(g_, vertices_, adjacency_, centre, r);
            for (std::size_t v : fresh) junctions += degree[v] >= 3 && (local.positions[v] - centre).norm() <= r;
            if (static_cast<double>(junctions) > junction_density_ * M_PI * r * r) return reject(PlacementOutcome::crowded);
        }
    }
    // No new street may close a block smaller than the city's small ones (a rule placed
    // by hand has the size its user gave it).
    if (min_block_m2_ > 0 && !by_hand) {
        std::vector<std::vector<VertexId>> around(local.vertex_count());
        for (const auto& [a, b] : local.edges) {
            if (local.symbols[static_cast<std::size_t>(a)] || local.symbols[static_cast<std::size_t>(b)]) continue;
            around[static_cast<std::size_t>(a)].push_back(b);
            around[static_cast<std::size_t>(b)].push_back(a);
        }
        auto neighbours = [&](VertexId w) -> const std::vector<VertexId>& { return around[static_cast<std::size_t>(w)]; };
        for (const auto& [a, b] : added) {
            const double left = block_left_of(local.positions, neighbours, a, b);
            const double right = block_left_of(local.positions, neighbours, b, a);
            if ((left > 0 && left < min_block_m2_) || (right > 0 && right < min_block_m2_)) {
                return reject(PlacementOutcome::small_block);
            }
        }
    }
    // Kept: the new vertices and edges join the graph and the frontier.
    for (std::size_t v : fresh) {
        global[v] = g_.add_vertex(local.positions[v]);
        adjacency_.emplace_back();
        vertices_.insert({point(local.positions[v]), global[v]});
    }
    for (std::size_t i = 0; i < added.size(); ++i) {
        const VertexId a = global[static_cast<std::size_t>(added[i][0])], b = global[static_cast<std::size_t>(added[i][1])];
        EdgeAttributes attributes;
        attributes.highway = classes[i];
        const EdgeId e = g_.add_edge(a, b, attributes);
        adjacency_[static_cast<std::size_t>(a)].push_back(b);
        adjacency_[static_cast<std::size_t>(b)].push_back(a);
        index_edge(e);
    }
    for (std::size_t i = 0; i < added.size(); ++i) {
        frontier_.push_back({global[static_cast<std::size_t>(added[i][0])], global[static_cast<std::size_t>(added[i][1])], 0});
    }
    ++report_->placements;
    last_outcome_ = PlacementOutcome::placed;
    if (anchor >= 0 && static_cast<std::size_t>(anchor) < base_vertices_) ++report_->border_connections;
    return true;
}

} // namespace ggg::growth_detail
