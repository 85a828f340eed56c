// Growth of a street network into a region; see growth.hpp.
#include "ggg/synthesis/growth.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <random>
#include <optional>
#include <tuple>
#include <set>
#include <string>
#include <unordered_map>


#include "ggg/encoding/decoding.hpp"
#include "ggg/error.hpp"
#include "ggg/graph/plane_geometry.hpp"
#include "ggg/graph/spatial_index.hpp"
#include "ggg/measures/network_comparison.hpp"
#include "ggg/grammar/rewriting.hpp"
#include "ggg/synthesis/street_hierarchy.hpp"
#include "street_cleanup.hpp"
#include "street_tracing.hpp"

namespace ggg {
namespace {

using namespace spatial; // bg, bgi, Point, Box, point, RTree, VertexEntry, EdgeEntry

// A rule derived all the way to streets, at unit size: what one placement adds.
struct Prototype {
    Symbol symbol = 0;
    double size_m = 1.0;
    double weight = 1.0;
    std::vector<Vec2> positions;
    std::vector<std::array<int, 2>> edges;
    std::vector<int> attach; // vertices that can sit on a frontier vertex: the ends and corners
    Vec2 centroid = Vec2::Zero();
    double radius = 0.0;    // farthest vertex from the centroid
    double edge_length = 0.0; // median
    // Its streets' directions modulo 90 degrees (length-weighted four-fold mean): how square
    // the rule is (1: every street along one of two perpendicular directions), and which way.
    double squareness = 0.0;
    double square_angle = 0.0; // radians, in [-pi/4, pi/4)
};

// Length-weighted four-fold mean of segment directions: (squareness, angle modulo 90 degrees).
std::pair<double, double> four_fold(const std::vector<std::pair<Vec2, Vec2>>& segments) {
    std::complex<double> z = 0.0;
    double total = 0.0;
    for (const auto& [a, b] : segments) {
        const Vec2 d = b - a;
        const double l = d.norm();
        if (l <= 0) continue;
        z += l * std::polar(1.0, 4.0 * std::atan2(d.y(), d.x()));
        total += l;
    }
    if (total <= 0) return {0.0, 0.0};
    return {std::abs(z) / total, std::arg(z) / 4.0};
}

double wrap_quarter(double a) { // into [-pi/4, pi/4)
    return a - M_PI / 2 * std::floor((a + M_PI / 4) / (M_PI / 2));
}

Prototype prototype_of(const Grammar& grammar, const Rule& rule, int depth, const GrowOptions& o) {
    Prototype p;
    p.symbol = rule.symbol;
    p.size_m = rule.size_m > 0 ? rule.size_m : o.default_size_m;
    p.weight = rule.uses > 0 ? static_cast<double>(rule.uses) : 1.0; // times its edges, below
    GeometricGraph g;
    place_nonterminal(g, rule.symbol, Vec2::Zero(), Frame{});
    DeriveOptions d;
    d.max_steps = depth + 1;
    d.max_vertices = 20'000;
    d.grammar_validated = true; // by grow_region
    derive(g, grammar, d);
    std::vector<int> index(g.vertex_count(), -1);
    for (std::size_t v = 0; v < g.vertex_count(); ++v) {
        if (g.symbols[v] != 0) continue; // a nonterminal without a rule stays out
        index[v] = static_cast<int>(p.positions.size());
        p.positions.push_back(g.positions[v]);
    }
    std::vector<int> degree(p.positions.size(), 0);
    std::vector<double> lengths;
    for (const auto& [a, b] : g.edges) {
        const int x = index[static_cast<std::size_t>(a)], y = index[static_cast<std::size_t>(b)];
        if (x < 0 || y < 0) continue;
        p.edges.push_back({x, y});
        ++degree[static_cast<std::size_t>(x)];
        ++degree[static_cast<std::size_t>(y)];
        lengths.push_back((p.positions[static_cast<std::size_t>(x)] - p.positions[static_cast<std::size_t>(y)]).norm());
    }
    if (p.positions.empty() || p.edges.empty()) return p;
    for (const Vec2& v : p.positions) p.centroid += v;
    p.centroid /= static_cast<double>(p.positions.size());
    for (const Vec2& v : p.positions) p.radius = std::max(p.radius, (v - p.centroid).norm());
    std::nth_element(lengths.begin(), lengths.begin() + static_cast<long>(lengths.size() / 2), lengths.end());
    p.edge_length = lengths[lengths.size() / 2];
    std::vector<std::pair<Vec2, Vec2>> segments;
    for (const auto& [a, b] : p.edges) segments.emplace_back(p.positions[static_cast<std::size_t>(a)], p.positions[static_cast<std::size_t>(b)]);
    std::tie(p.squareness, p.square_angle) = four_fold(segments);
    // A rule is chosen as often as its streets occur in the city it was learned from: a
    // block of eight streets used 10 times weighs as much as a street used 80 times.
    p.weight *= static_cast<double>(p.edges.size());
    // Blocks make a street network; a rule with c independent cycles (E - V + 1, for a
    // connected rule) counts 1 + c times, so that tree-shaped pieces do not crowd blocks out.
    const double cycles = std::max(0.0, static_cast<double>(p.edges.size()) - static_cast<double>(p.positions.size()) + 1.0);
    p.weight *= 1.0 + o.block_preference * cycles;
    for (std::size_t v = 0; v < p.positions.size(); ++v) {
        if (degree[v] < 3) p.attach.push_back(static_cast<int>(v));
    }
    if (p.attach.empty()) {
        for (std::size_t v = 0; v < p.positions.size(); ++v) p.attach.push_back(static_cast<int>(v));
    }
    return p;
}

// A street a rule can be glued onto: one of the rule's edges is laid on it (the rule's two
// vertices merge with its ends), on the side the placement chooses.
struct FrontierEdge {
    VertexId a = -1;
    VertexId b = -1;
    int failures = 0;
};

class Grower {
public:
    Grower(const GeometricGraph& base, const Grammar& grammar, const std::vector<Vec2>& region, const GrowOptions& o,
           const ProgressCallback& progress)
        : g_(base), grammar_(grammar), region_(region), o_(o), progress_(progress), rng_(o.seed) {}

    GeometricGraph run(GrowReport& report) {
        report_ = &report;
        const std::vector<int> levels = rule_levels(grammar_);
        const int depth = levels.empty() ? 1 : *std::max_element(levels.begin(), levels.end());
        for (const Rule& r : grammar_.rules) {
            Prototype p = prototype_of(grammar_, r, depth, o_);
            if (p.edges.empty()) continue;
            weights_.push_back(p.weight);
            prototypes_.push_back(std::move(p));
        }
        if (prototypes_.empty()) throw UsageError("the grammar has no rule that derives to streets: nothing to grow with");
        // Whether the grammar's city is a grid: then square rules keep to a grid as they grow
        // (a learned grammar decodes to its city; a hand-written one is judged by its rules).
        std::vector<std::pair<Vec2, Vec2>> streets;
        if (!grammar_.encoding.empty()) {
            style_city_ = decode_grammar(grammar_);
            const GeometricGraph& city = style_city_;
            for (const auto& [a, b] : city.edges) streets.emplace_back(city.positions[static_cast<std::size_t>(a)], city.positions[static_cast<std::size_t>(b)]);
            // No block much smaller than the city's small ones: the smallest tenth of a city's
            // blocks are mostly slivers (turn lanes, traffic islands), which growth would
            // otherwise multiply, as rules with blocks are preferred and rules glued side by
            // side close slivers between them. Six tenths of that quantile leave room for
            // the placements' size jitter.
            const std::vector<double> blocks = street_statistics(city).block_areas_m2; // sorted
            if (o_.smallest_block > 0 && !blocks.empty()) {
                const auto at = static_cast<std::size_t>(std::min(1.0, o_.smallest_block) * static_cast<double>(blocks.size() - 1));
                min_block_m2_ = 0.6 * blocks[at];
                // A dead end joined to the street ahead splits a block in two: both halves
                // must be of the city's usual size (its lower quartile at least).
                split_block_m2_ = std::max(min_block_m2_, blocks[(blocks.size() - 1) / 4]);
            }
        } else {
            for (const Prototype& p : prototypes_) {
                for (const auto& [a, b] : p.edges) streets.emplace_back(p.positions[static_cast<std::size_t>(a)], p.positions[static_cast<std::size_t>(b)]);
            }
        }
        grid_city_ = four_fold(streets).first >= 0.5;
        report.grid = grid_city_;
        depth_ = depth;
        index_graph();
        for (const Vec2& p : region_) centre_ += p;
        centre_ /= static_cast<double>(region_.size());
        double size = 0.0;
        for (const Vec2& p : region_) size = std::max(size, (p - centre_).norm());
        const double border = o_.border_m >= 0 ? o_.border_m : 0.05 * size;

        for (const RulePlacement& placed : o_.placements) place_by_hand(placed);
        for (std::size_t e = 0; e < base_edges_; ++e) {
            const auto [u, v] = g_.edges[e];
            if (near_region(g_.positions[static_cast<std::size_t>(u)], border) || near_region(g_.positions[static_cast<std::size_t>(v)], border)) {
                frontier_.push_back({u, v, 0});
            }
        }
        {
            std::vector<std::pair<Vec2, Vec2>> near;
            for (const FrontierEdge& f : frontier_) near.emplace_back(g_.positions[static_cast<std::size_t>(f.a)], g_.positions[static_cast<std::size_t>(f.b)]);
            const auto [squareness, angle] = four_fold(near);
            if (squareness >= 0.7) grid_angle_ = angle; // the streets around run on a grid: keep it
        }
        if (o_.trace_streets) {
            // The streets that reach the region are traced on into it first, after the
            // junctions of the grammar's city (or, for a hand-written grammar, of the base).
            growth_detail::TracingSettings tracing;
            tracing.border_m = border;
            tracing.max_vertices = o_.max_vertices;
            tracing.min_block_m2 = split_block_m2_;
            const GeometricGraph& style = grammar_.encoding.empty() ? base_copy_for_style() : style_city_;
            const growth_detail::TracingReport traced = growth_detail::trace_streets(g_, base_vertices_, style, region_, tracing, rng_, progress_);
            report.traced_seeds = traced.seeds;
            report.traced_streets = traced.streets;
            report.traced_joined = traced.joined;
            report.traced_t_junctions = traced.t_junctions;
            if (traced.streets > 0) reindex();
            if (g_.vertex_count() >= o_.max_vertices) report.stopped_by_budget = true;
        }
        if (frontier_.empty()) seed_at_centre();

        std::size_t in_a_row = 0;
        while (!frontier_.empty()) {
            if (report.placements >= o_.max_placements || g_.vertex_count() >= o_.max_vertices) {
                report.stopped_by_budget = true;
                break;
            }
            if (in_a_row >= o_.patience) break;
            ggg::report(progress_, static_cast<double>(report.placements) / static_cast<double>(std::max<std::size_t>(1, o_.max_placements)),
                        "placing rules");
            std::uniform_int_distribution<std::size_t> pick(0, frontier_.size() - 1);
            const std::size_t f = pick(rng_);
            if (glue(frontier_[f])) {
                in_a_row = 0;
            } else {
                ++in_a_row;
                if (++frontier_[f].failures >= 8) {
                    frontier_[f] = frontier_.back();
                    frontier_.pop_back();
                }
            }
        }
        report.filled = !report.stopped_by_budget;
        close_dead_ends();
        prune_stubs();
        report.dissolved_vertices = growth_detail::dissolve_bends(g_, base_vertices_, base_edges_);
        report.removed_crossing_streets = growth_detail::remove_crossing_streets(g_, base_vertices_, base_edges_);
        if (o_.continue_hierarchy) {
            HierarchyOptions h_options;
            h_options.region = region_;
            h_options.border_m = border;
            const HierarchyReport h = continue_hierarchy(g_, static_cast<EdgeId>(base_edges_), h_options);
            report.main_road_routes = h.routes;
            report.raised_streets = h.raised_streets;
            report.main_road_connectors = h.connectors;
            report.intersections = h.intersections;
        }
        report.added_vertices = g_.vertex_count() - base_vertices_;
        report.added_edges = g_.edge_count() - base_edges_;
        ggg::report(progress_, 1.0, "done");
        return std::move(g_);
    }

private:
    const GeometricGraph& base_copy_for_style() {
        style_city_ = g_;
        return style_city_;
    }

    // The indexes again, after the streets were traced (the base stays the base).
    void reindex() {
        vertices_.clear();
        segments_.clear();
        adjacency_.assign(g_.vertex_count(), {});
        for (std::size_t e = 0; e < g_.edge_count(); ++e) {
            const auto [a, b] = g_.edges[e];
            adjacency_[static_cast<std::size_t>(a)].push_back(b);
            adjacency_[static_cast<std::size_t>(b)].push_back(a);
            index_edge(static_cast<EdgeId>(e));
        }
        for (std::size_t v = 0; v < g_.vertex_count(); ++v) vertices_.insert({point(g_.positions[v]), static_cast<VertexId>(v)});
    }

    void index_graph() {
        base_vertices_ = g_.vertex_count();
        base_edges_ = g_.edge_count();
        adjacency_.assign(g_.vertex_count(), {});
        for (std::size_t e = 0; e < g_.edge_count(); ++e) {
            const auto [a, b] = g_.edges[e];
            adjacency_[static_cast<std::size_t>(a)].push_back(b);
            adjacency_[static_cast<std::size_t>(b)].push_back(a);
            index_edge(static_cast<EdgeId>(e));
        }
        for (std::size_t v = 0; v < g_.vertex_count(); ++v) vertices_.insert({point(g_.positions[v]), static_cast<VertexId>(v)});
    }

    void index_edge(EdgeId e) { segments_.insert({edge_box(g_, e), e}); }

    bool near_region(const Vec2& p, double border) const { return inside(region_, p) || distance_to_ring(region_, p) <= border; }

    Vec2 principal_axis() const {
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

    // One try at the street ab: a rule chosen by its frequency, one of its edges of about
    // the street's length laid on ab, on one side or the other.
    bool glue(const FrontierEdge& at) {
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

    // Where no edge of the rule fits the street: one of the rule's ends or corners is put on
    // an end of the street, the rule turned to lie beyond it, along the grid if there is one.
    bool attach(const Prototype& p, const FrontierEdge& at) {
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

    // No street reaches the region: the most frequent rule that fits goes in its middle,
    // along the region's long axis.
    void seed_at_centre() {
        std::vector<std::size_t> order(prototypes_.size());
        for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
        std::stable_sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) { return prototypes_[x].weight > prototypes_[y].weight; });
        const Vec2 axis = principal_axis();
        const double angle = std::atan2(axis.y(), axis.x());
        for (std::size_t i : order) {
            const Prototype& p = prototypes_[i];
            const Vec2 origin = centre_ - Similarity2::from(p.size_m, angle, Vec2::Zero()).apply_linear(p.centroid);
            ++report_->attempts;
            if (!place(p, Frame{p.size_m, angle * 180.0 / M_PI}, origin, -1)) continue;
            if (p.squareness >= 0.6) grid_angle_ = wrap_quarter(p.square_angle + angle);
            return;
        }
    }

    void place_by_hand(const RulePlacement& placed) {
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

    // Counts a placement refused for `why` and remembers it (for the rules placed by hand).
    bool reject(PlacementOutcome why) {
        last_outcome_ = why;
        switch (why) {
        case PlacementOutcome::outside: ++report_->rejected_outside; break;
        case PlacementOutcome::crossing: ++report_->rejected_crossing; break;
        case PlacementOutcome::crowded: ++report_->rejected_crowded; break;
        case PlacementOutcome::star: ++report_->rejected_star; break;
        case PlacementOutcome::small_block: ++report_->rejected_small_block; break;
        case PlacementOutcome::placed:
        case PlacementOutcome::nothing_new: break;
        }
        return false;
    }

    // Derives the rule at `origin` in a copy of the streets around it and keeps the result
    // if it fits. True when it was kept.
    bool place(const Prototype& p, const Frame& frame, const Vec2& origin, VertexId anchor, bool by_hand = false) {
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

    // Whether a street from v to w would close a block smaller than the city's small ones.
    bool closes_small_block(VertexId v, VertexId w) {
        adjacency_[static_cast<std::size_t>(v)].push_back(w);
        adjacency_[static_cast<std::size_t>(w)].push_back(v);
        auto neighbours = [&](VertexId x) -> const std::vector<VertexId>& { return adjacency_[static_cast<std::size_t>(x)]; };
        const double left = block_left_of(g_.positions, neighbours, v, w);
        const double right = block_left_of(g_.positions, neighbours, w, v);
        adjacency_[static_cast<std::size_t>(v)].pop_back();
        adjacency_[static_cast<std::size_t>(w)].pop_back();
        return (left > 0 && left < min_block_m2_) || (right > 0 && right < min_block_m2_);
    }

    bool crosses(const Vec2& a, const Vec2& b) const {
        Box box(point(a), point(a));
        bg::expand(box, point(b));
        for (auto it = segments_.qbegin(bgi::intersects(box)); it != segments_.qend(); ++it) {
            const EdgeId e = it->second;
            const Vec2* p = g_.geometry_begin(e);
            for (std::size_t i = 0; i + 1 < g_.geometry_size(e); ++i) {
                if (segments_meet(a, b, p[i], p[i + 1])) return true;
            }
        }
        return false;
    }

    // A new dead end is joined to the vertex ahead of it that is closest, where the joining
    // street crosses nothing: grown streets meet the ones around instead of stopping short.
    void close_dead_ends() {
        std::vector<double> lengths;
        for (std::size_t e = base_edges_; e < g_.edge_count(); ++e) lengths.push_back(g_.edge_length(static_cast<EdgeId>(e)));
        if (lengths.empty() || o_.close_dead_ends <= 0) return;
        std::nth_element(lengths.begin(), lengths.begin() + static_cast<long>(lengths.size() / 2), lengths.end());
        const double reach = o_.close_dead_ends * lengths[lengths.size() / 2];
        for (std::size_t v = base_vertices_; v < g_.vertex_count(); ++v) {
            if (adjacency_[v].size() != 1) continue;
            const Vec2 p = g_.positions[v];
            const Vec2 ahead = (p - g_.positions[static_cast<std::size_t>(adjacency_[v][0])]).normalized();
            VertexId best = -1;
            double best_d = reach;
            const Box window = spatial::around(p, reach);
            for (auto it = vertices_.qbegin(bgi::intersects(window)); it != vertices_.qend(); ++it) {
                const VertexId w = it->second;
                if (static_cast<std::size_t>(w) == v || adjacency_[static_cast<std::size_t>(w)].size() >= 4) continue;
                const Vec2 d = g_.positions[static_cast<std::size_t>(w)] - p;
                const double length = d.norm();
                const auto& n = adjacency_[v];
                if (length >= best_d || d.dot(ahead) < 0.7 * length || std::find(n.begin(), n.end(), w) != n.end()) continue;
                if (!inside(region_, 0.5 * (p + g_.positions[static_cast<std::size_t>(w)]))) continue; // stays in the region
                if (crosses(p, g_.positions[static_cast<std::size_t>(w)])) continue;
                if (min_block_m2_ > 0 && closes_small_block(static_cast<VertexId>(v), w)) continue;
                best = w;
                best_d = length;
            }
            EdgeAttributes attributes;
            attributes.highway = g_.edge_highway[g_.edge_count() - 1];
            for (std::size_t e = base_edges_; e < g_.edge_count(); ++e) {
                if (g_.edges[e][0] == static_cast<VertexId>(v) || g_.edges[e][1] == static_cast<VertexId>(v)) attributes.highway = g_.edge_highway[e];
            }
            if (best < 0) {
                // No vertex ahead: the grown street ahead, if there is one, gets a T-junction.
                if (join_street_ahead(static_cast<VertexId>(v), ahead, reach, attributes)) ++report_->t_junctions;
                continue;
            }
            const EdgeId e = g_.add_edge(static_cast<VertexId>(v), best, attributes);
            adjacency_[v].push_back(best);
            adjacency_[static_cast<std::size_t>(best)].push_back(static_cast<VertexId>(v));
            index_edge(e);
            ++report_->closing_edges;
        }
    }

    // Grown dead ends shorter than o_.prune_stubs times the typical grown street are cut off:
    // they are the ends of rules' streets that led on to a neighbouring block in the city and
    // that nothing was grown onto. One pass, so that a street is shortened by one stub at most.
    void prune_stubs() {
        if (o_.prune_stubs <= 0 || g_.edge_count() == base_edges_) return;
        std::vector<double> lengths;
        for (std::size_t e = base_edges_; e < g_.edge_count(); ++e) lengths.push_back(g_.edge_length(static_cast<EdgeId>(e)));
        std::nth_element(lengths.begin(), lengths.begin() + static_cast<long>(lengths.size() / 2), lengths.end());
        const double shortest = o_.prune_stubs * lengths[lengths.size() / 2];
        std::vector<char> drop_vertex(g_.vertex_count(), 0), drop_edge(g_.edge_count(), 0);
        std::size_t dropped = 0;
        for (std::size_t e = base_edges_; e < g_.edge_count(); ++e) {
            const auto [a, b] = g_.edges[e];
            for (const VertexId end : {a, b}) {
                const VertexId other = end == a ? b : a;
                if (static_cast<std::size_t>(end) < base_vertices_ || adjacency_[static_cast<std::size_t>(end)].size() != 1) continue;
                // Not a street of its own (both ends loose), and not the last street of a vertex.
                if (adjacency_[static_cast<std::size_t>(other)].size() < 3) continue;
                if (g_.edge_length(static_cast<EdgeId>(e)) >= shortest) continue;
                drop_vertex[static_cast<std::size_t>(end)] = 1;
                drop_edge[e] = 1;
                ++dropped;
                break;
            }
        }
        if (dropped == 0) return;
        std::vector<growth_detail::Street> streets;
        for (std::size_t e = 0; e < g_.edge_count(); ++e) {
            if (drop_edge[e]) continue;
            const Vec2* p = g_.geometry_begin(static_cast<EdgeId>(e));
            streets.push_back({g_.edges[e][0], g_.edges[e][1], g_.edge_attributes(static_cast<EdgeId>(e)),
                               std::vector<Vec2>(p, p + g_.geometry_size(static_cast<EdgeId>(e)))});
        }
        GeometricGraph kept = growth_detail::rebuilt(g_, drop_vertex, streets);
        g_ = std::move(kept);
        report_->pruned_stubs = dropped;
        // The indexes, for what comes after (the main roads).
        std::vector<std::vector<VertexId>> around(g_.vertex_count());
        for (const auto& [a, b] : g_.edges) {
            around[static_cast<std::size_t>(a)].push_back(b);
            around[static_cast<std::size_t>(b)].push_back(a);
        }
        adjacency_ = std::move(around);
    }

    // The dead end v continued straight ahead onto the first street it meets within reach,
    // when that is a grown street and the meeting point keeps its distance from the street's
    // ends: the street is split there into a T-junction. False when nothing was joined.
    bool join_street_ahead(VertexId v, const Vec2& ahead, double reach, const EdgeAttributes& attributes) {
        const Vec2 p = g_.positions[static_cast<std::size_t>(v)];
        const Vec2 end = p + reach * ahead;
        Box box(point(p), point(p));
        bg::expand(box, point(end));
        double first_t = 2.0;
        EdgeId hit = -1;
        double hit_u = 0.0;
        for (auto it = segments_.qbegin(bgi::intersects(box)); it != segments_.qend(); ++it) {
            const EdgeId e = it->second;
            const auto [a, b] = g_.edges[static_cast<std::size_t>(e)];
            if (a == v || b == v) continue;
            const Vec2* q = g_.geometry_begin(e);
            for (std::size_t i = 0; i + 1 < g_.geometry_size(e); ++i) {
                const auto m = segment_meeting(p, end, q[i], q[i + 1]);
                if (m && m->first > 1e-9 && m->first < first_t) {
                    first_t = m->first;
                    hit = g_.geometry_size(e) == 2 ? e : -1; // only a straight street is split
                    hit_u = m->second;
                }
            }
        }
        if (hit < 0 || static_cast<std::size_t>(hit) < base_edges_) return false;
        const auto e = static_cast<std::size_t>(hit);
        const auto [a, b] = g_.edges[e];
        const double length = g_.edge_length(hit);
        const double keep = o_.spacing * length;
        if (hit_u * length < std::max(keep, 1e-6) || (1.0 - hit_u) * length < std::max(keep, 1e-6)) return false;
        const Vec2 x = p + first_t * (end - p);
        if (!inside(region_, 0.5 * (p + x))) return false;
        // The blocks on either side of the new street, with the junction in place.
        const auto x_id = static_cast<VertexId>(g_.vertex_count());
        auto around = [&](VertexId w) -> std::vector<VertexId>& { return adjacency_[static_cast<std::size_t>(w)]; };
        g_.positions.push_back(x);
        adjacency_.push_back({a, b, v}); // (may move the lists: they are looked up afresh below)
        std::replace(around(a).begin(), around(a).end(), b, x_id);
        std::replace(around(b).begin(), around(b).end(), a, x_id);
        around(v).push_back(x_id);
        bool small = false;
        if (split_block_m2_ > 0) {
            auto neighbours = [&](VertexId w) -> const std::vector<VertexId>& { return around(w); };
            const double left = block_left_of(g_.positions, neighbours, v, x_id);
            const double right = block_left_of(g_.positions, neighbours, x_id, v);
            small = (left > 0 && left < split_block_m2_) || (right > 0 && right < split_block_m2_);
        }
        // Undone, then (if it fits) made for good.
        around(v).pop_back();
        std::replace(around(a).begin(), around(a).end(), x_id, b);
        std::replace(around(b).begin(), around(b).end(), x_id, a);
        adjacency_.pop_back();
        g_.positions.pop_back();
        if (small) return false;

        const VertexId junction = g_.split_edge(hit, x);
        adjacency_.push_back({a, b, v});
        vertices_.insert({point(x), junction});
        std::replace(around(a).begin(), around(a).end(), b, junction);
        std::replace(around(b).begin(), around(b).end(), a, junction);
        around(v).push_back(junction);
        index_edge(static_cast<EdgeId>(g_.edge_count() - 1)); // its second half (the first stays indexed by the whole street's box)
        const EdgeId joining = g_.add_edge(v, junction, attributes);
        index_edge(joining);
        return true;
    }

    GeometricGraph g_;
    GeometricGraph style_city_; // the city whose junctions traced streets copy
    const Grammar& grammar_;
    const std::vector<Vec2>& region_;
    const GrowOptions& o_;
    const ProgressCallback& progress_;
    std::mt19937_64 rng_;
    GrowReport* report_ = nullptr;
    PlacementOutcome last_outcome_ = PlacementOutcome::nothing_new;
    std::vector<Prototype> prototypes_;
    std::vector<double> weights_;
    int depth_ = 1;
    std::size_t base_vertices_ = 0, base_edges_ = 0;
    std::vector<std::vector<VertexId>> adjacency_;
    RTree<VertexEntry> vertices_;
    RTree<EdgeEntry> segments_;
    std::vector<FrontierEdge> frontier_;
    Vec2 centre_ = Vec2::Zero();
    bool grid_city_ = false;
    double min_block_m2_ = 0.0;   // smallest block a placement may close (0: any)
    double split_block_m2_ = 0.0; // smallest half of a block that a T-junction may leave
    std::optional<double> grid_angle_; // the grid the growth keeps to (modulo 90 degrees), once there is one
};

} // namespace

std::string_view outcome_name(PlacementOutcome outcome) {
    switch (outcome) {
    case PlacementOutcome::placed: return "placed";
    case PlacementOutcome::outside: return "outside";
    case PlacementOutcome::crossing: return "crossing";
    case PlacementOutcome::crowded: return "crowded";
    case PlacementOutcome::star: return "star";
    case PlacementOutcome::small_block: return "small_block";
    case PlacementOutcome::nothing_new: return "nothing_new";
    }
    return "unknown";
}

void check_options(const GrowOptions& o) {
    auto fail = [](const char* name, const std::string& what) { throw UsageError(std::string(name) + ": must be " + what); };
    auto finite_at_least = [&](const char* name, double value, double lo) {
        if (!(std::isfinite(value) && value >= lo)) fail(name, "a number >= " + std::to_string(static_cast<int>(lo)) + ", got " + std::to_string(value));
    };
    if (o.max_placements < 1) fail("max_placements", "at least 1");
    if (o.max_vertices < 1) fail("max_vertices", "at least 1");
    if (!std::isfinite(o.border_m)) fail("border_m", "a finite number of metres (< 0: 5 % of the region's size)");
    finite_at_least("snap", o.snap, 0);
    finite_at_least("spacing", o.spacing, 0);
    finite_at_least("turn_deg", o.turn_deg, 0);
    if (!(o.size_jitter >= 0 && o.size_jitter < 1)) fail("size_jitter", "a number from 0 to below 1");
    if (!(std::isfinite(o.default_size_m) && o.default_size_m > 0)) fail("default_size_m", "a number of metres > 0");
    finite_at_least("grid_tolerance_deg", o.grid_tolerance_deg, 0);
    finite_at_least("block_preference", o.block_preference, 0);
    if (!(o.smallest_block >= 0 && o.smallest_block <= 1)) fail("smallest_block", "a quantile from 0 to 1");
    finite_at_least("close_dead_ends", o.close_dead_ends, 0);
    finite_at_least("prune_stubs", o.prune_stubs, 0);
    for (const RulePlacement& p : o.placements) {
        if (!p.position.allFinite() || !std::isfinite(p.frame.scale) || !std::isfinite(p.frame.rotation_deg)) {
            fail("placements", "finite positions, scales and rotations");
        }
    }
}

GeometricGraph grow_region(const GeometricGraph& base, const Grammar& grammar, const std::vector<Vec2>& region,
                           const GrowOptions& options, GrowReport* report, const ProgressCallback& progress) {
    validate(grammar);
    if (grammar.rules.empty()) throw UsageError("the grammar has no rules to grow with");
    if (region.size() < 3) throw UsageError("a region needs at least three corners");
    double area = 0.0;
    for (std::size_t i = 0, j = region.size() - 1; i < region.size(); j = i++) {
        if (!region[i].allFinite()) throw UsageError("the region's corners must be finite numbers");
        area += cross(region[j], region[i]);
    }
    // No area: corners on a line, which a map projection bends by a hair (a region ten
    // thousand times as long as it is wide). A small region is not refused: nothing fits in it.
    double extent = 0.0;
    for (const Vec2& p : region) extent = std::max(extent, (p - region.front()).norm());
    const double region_area = std::abs(area) / 2.0;
    if (!(extent > 0) || !(region_area > 1e-4 * extent * extent)) {
        throw UsageError("the region has no area (its corners lie on a line)");
    }
    check_options(options);
    GrowReport r;
    GeometricGraph out = Grower(base, grammar, region, options, progress).run(r);
    if (report) *report = r;
    return out;
}

} // namespace ggg
