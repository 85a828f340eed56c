// Growth of a street network into a region; see growth.hpp. This file runs the stages
// (growth_stages.hpp) in order and holds the indexes they share, and the entry points: the
// options checked, and grow_region.
#include "ggg/synthesis/growth.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include "ggg/encoding/decoding.hpp"
#include "ggg/error.hpp"
#include "ggg/grammar/rewriting.hpp"
#include "ggg/graph/plane_geometry.hpp"
#include "ggg/graph/spatial_index.hpp"
#include "ggg/measures/network_comparison.hpp"
#include "ggg/synthesis/street_hierarchy.hpp"
#include "growth_stages.hpp"
#include "street_cleanup.hpp"
#include "street_tracing.hpp"

namespace ggg {
namespace growth_detail {

using namespace spatial; // bg, bgi, Point, Box, point, RTree, VertexEntry, EdgeEntry

GeometricGraph Grower::run(GrowReport& report) {
    report_ = &report;
    // The base's dead-end streets and roundabouts, which growth makes as often (a learned
    // grammar keeps no one-way streets, by which roundabouts are told from small squares).
    const growth_detail::CityCulDeSacs base_cul_de_sacs = o_.cul_de_sacs ? growth_detail::cul_de_sacs_of(g_, region_) : growth_detail::CityCulDeSacs{};
    const growth_detail::CityRoundabouts base_roundabouts = o_.roundabouts ? growth_detail::roundabouts_of(g_, region_) : growth_detail::CityRoundabouts{};
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
            // Of the blocks above the sliver floor, the share below that size.
            const auto from = std::lower_bound(blocks.begin(), blocks.end(), min_block_m2_);
            const auto to = std::lower_bound(blocks.begin(), blocks.end(), split_block_m2_);
            if (from != blocks.end()) small_block_share_ = static_cast<double>(to - from) / static_cast<double>(blocks.end() - from);
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
    // Measured on the base before anything is grown on it.
    const growth_detail::CityBends city_bends = growth_detail::bends_of(g_, centre_, 2.0 * size);
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
        grid_around_ = squareness >= 0.5;
    }
    std::optional<double> access_angle;
    if (frontier_.empty()) {
        // No street reaches the region: the city's streets nearest it say whether a grid runs
        // there, and which way.
        std::vector<std::pair<Vec2, Vec2>> near;
        for (std::size_t e = 0; e < base_edges_; ++e) {
            const Vec2 a = g_.positions[static_cast<std::size_t>(g_.edges[e][0])], b = g_.positions[static_cast<std::size_t>(g_.edges[e][1])];
            if (near_region(a, size) || near_region(b, size)) near.emplace_back(a, b);
        }
        const auto [squareness, angle] = four_fold(near);
        if (squareness >= 0.7) grid_angle_ = angle;
        // The street that reaches the district runs the way most of them do (Washington's
        // grid, its diagonal avenues aside, is square to 0.5 to 0.7).
        if (squareness >= 0.5) access_angle = angle;
    }
    if (o_.trace_streets) {
        // The streets that reach the region are traced on into it first, after the
        // junctions of the grammar's city (or, for a hand-written grammar, of the base).
        growth_detail::TracingSettings tracing;
        tracing.border_m = border;
        tracing.max_vertices = o_.max_vertices;
        tracing.min_block_m2 = min_block_m2_;
        tracing.usual_block_m2 = split_block_m2_;
        tracing.small_block_share = small_block_share_;
        tracing.grid_city = grid_city_ || grid_around_;
        tracing.no_street_reaches = frontier_.empty();
        tracing.grid_angle = access_angle;
        const GeometricGraph& style = grammar_.encoding.empty() ? base_copy_for_style() : style_city_;
        const growth_detail::TracingReport traced = growth_detail::trace_streets(g_, base_vertices_, style, region_, tracing, rng_, progress_);
        report.traced_seeds = traced.seeds;
        report.traced_streets = traced.streets;
        report.traced_joined = traced.joined;
        report.traced_t_junctions = traced.t_junctions;
        report.traced_dense = traced.dense;
        report.traced_across = traced.across;
        report.traced_avenues = traced.avenues;
        report.traced_crossed = traced.crossed;
        report.traced_empty_ground = traced.empty_ground;
        report.traced_joined_offsets = traced.joined_offsets;
        report.traced_closed_corners = traced.closed_corners;
        report.traced_offset_crossings = traced.offset_crossings;
        report.traced_junction_islands = traced.junction_islands;
        street_density_ = traced.density;
        junction_density_ = traced.junction_density;
        density_radius_ = 2.0 * traced.typical_m;
        if (traced.streets > 0) reindex();
        if (g_.vertex_count() >= o_.max_vertices) report.stopped_by_budget = true;
    }
    if (frontier_.empty() && report.traced_streets == 0) seed_at_centre();

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
    report.thinned_streets = growth_detail::thin_junctions(g_, base_vertices_, base_edges_, region_, junction_density_, density_radius_);
    report.dissolved_vertices = growth_detail::dissolve_bends(g_, base_vertices_, base_edges_);
    report.squared_junctions = growth_detail::square_junctions(g_, base_vertices_, base_edges_, region_);
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
        report.main_road_extensions = h.extensions;
    }
    // The last guard again, for what the main roads laid across what was there.
    if (o_.continue_hierarchy) report.removed_crossing_streets += growth_detail::remove_crossing_streets(g_, base_vertices_, base_edges_);
    // A district grown where no street of the base reached gets a street to the city.
    report.island_streets = growth_detail::join_grown_islands(g_, base_vertices_, base_edges_, size);
    // Last, once the main roads are continued: roundabouts are mostly where they meet.
    if (o_.roundabouts) {
        report.roundabouts = growth_detail::make_roundabouts(g_, base_vertices_, base_edges_, region_, base_roundabouts, rng_);
    }
    // Then the blocks get the city's dead-end streets (their junctions are no roundabouts).
    if (o_.cul_de_sacs) report.cul_de_sacs = growth_detail::make_cul_de_sacs(g_, base_vertices_, base_edges_, region_, base_cul_de_sacs, rng_);
    // Last of all, the grown streets split as often as the base's streets around the region are.
    if (o_.split_streets) report.split_vertices = growth_detail::split_streets(g_, base_vertices_, base_edges_, city_bends, rng_);
    report.added_vertices = g_.vertex_count() - base_vertices_;
    report.added_edges = g_.edge_count() - base_edges_;
    ggg::report(progress_, 1.0, "done");
    return std::move(g_);
}

const GeometricGraph& Grower::base_copy_for_style() {
    style_city_ = g_;
    return style_city_;
}

void Grower::reindex() {
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

void Grower::index_graph() {
    base_vertices_ = g_.vertex_count();
    base_edges_ = g_.edge_count();
    reindex();
}

bool Grower::crosses(const Vec2& a, const Vec2& b) const {
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

} // namespace growth_detail

std::string_view outcome_name(PlacementOutcome outcome) {
    switch (outcome) {
    case PlacementOutcome::placed: return "placed";
    case PlacementOutcome::outside: return "outside";
    case PlacementOutcome::crossing: return "crossing";
    case PlacementOutcome::crowded: return "crowded";
    case PlacementOutcome::star: return "star";
    case PlacementOutcome::sharp: return "sharp";
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
    // Asked first of the corners, then of the outline: a bow tie has no area either, but
    // because it crosses itself.
    std::size_t farthest = 0;
    for (std::size_t i = 1; i < region.size(); ++i) {
        if ((region[i] - region.front()).norm() > (region[farthest] - region.front()).norm()) farthest = i;
    }
    const Vec2 axis = region[farthest] - region.front();
    const double extent = axis.norm();
    double width = 0.0;
    for (const Vec2& p : region) width = std::max(width, extent > 0 ? std::abs(cross(axis, p - region.front())) / extent : 0.0);
    auto no_area = [] { return UsageError("the region has no area (its corners lie on a line)"); };
    if (!(extent > 0) || !(width > 1e-4 * extent)) throw no_area();
    if (const auto sides = first_self_crossing(region)) {
        throw UsageError("the region crosses itself (its sides from corners " + std::to_string(sides->first + 1) + " and " +
                         std::to_string(sides->second + 1) + " meet): a region is one outline that does not cross itself");
    }
    if (!(std::abs(area) / 2.0 > 1e-4 * extent * extent)) throw no_area();
    // A region this far from every street of the base is not next to its city: most often
    // coordinates of another place, or swapped. (The gap between the two boxes: never more than
    // the distance to the nearest street.)
    if (base.vertex_count() > 0) {
        const auto city = bounds(base.positions.begin(), base.positions.end());
        const auto box = bounds(region.begin(), region.end());
        const Vec2 gap = (city.min() - box.max()).cwiseMax(box.min() - city.max()).cwiseMax(0.0);
        if (gap.norm() > max_distance_from_base_m) {
            char text[160];
            std::snprintf(text, sizeof text, "the region is %.0f km from the streets of the base (at most %.0f km): check its coordinates",
                          gap.norm() / 1000.0, max_distance_from_base_m / 1000.0);
            throw UsageError(text);
        }
    }
    check_options(options);
    GrowReport r;
    GeometricGraph out = growth_detail::Grower(base, grammar, region, options, progress).run(r);
    if (report) *report = r;
    return out;
}

} // namespace ggg
