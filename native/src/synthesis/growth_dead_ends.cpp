// The stage of growth after the rules: once the region is full, the dead ends (the grown ones,
// and those of the base that point into the region with nothing grown on) are joined to a
// vertex or a grown street ahead of them, and the short stubs that nothing was grown onto are
// cut (growth_stages.hpp).
#include "growth_stages.hpp"

#include <algorithm>
#include <tuple>

#include "street_cleanup.hpp"

namespace ggg::growth_detail {

using namespace spatial; // bg, bgi, Point, Box, point, RTree, VertexEntry, EdgeEntry

namespace {

// A street that joins a dead end to a vertex or a street meets the streets there at this
// angle at least, as traced streets do (tracing_stages.hpp): a narrower one leaves a sliver
// of a block, or two streets running on side by side (Helsinki grew junctions of 1 to 17
// degrees where carriageways and stubs were joined). Less where the city's own junctions are
// narrower (city_narrow_angle: Monaco's hairpins, Washington's avenues).
constexpr double kMinJoinAngle = M_PI / 6;
// But a street of the base the region cut is continued wherever it can be, and a carriageway
// merges into the street beside it as roads do, at a narrow angle (Helsinki's dual
// carriageways at 10 to 17 degrees).
constexpr double kMinMergeAngle = M_PI / 18;

} // namespace

std::vector<Vec2> Grower::first_pieces_at(VertexId v) const {
    std::vector<Vec2> pieces;
    const Vec2 pv = g_.positions[static_cast<std::size_t>(v)];
    for (auto it = segments_.qbegin(bgi::intersects(point(pv))); it != segments_.qend(); ++it) {
        const EdgeId e = it->second;
        const auto [a, b] = g_.edges[static_cast<std::size_t>(e)];
        if (a != v && b != v) continue;
        const Vec2 d = (a == v ? g_.geometry_begin(e)[1] : g_.geometry_begin(e)[g_.geometry_size(e) - 2]) - pv;
        if (d.norm() > 1e-9) pieces.push_back(d);
    }
    return pieces;
}

double Grower::clearance_at(VertexId w, const Vec2& d) const {
    double smallest = M_PI;
    if (d.norm() < 1e-9) return smallest;
    for (const Vec2& other : first_pieces_at(w)) {
        smallest = std::min(smallest, std::acos(std::clamp(other.normalized().dot(d.normalized()), -1.0, 1.0)));
    }
    return smallest;
}

bool Grower::closes_small_block(VertexId v, VertexId w) {
    adjacency_[static_cast<std::size_t>(v)].push_back(w);
    adjacency_[static_cast<std::size_t>(w)].push_back(v);
    auto neighbours = [&](VertexId x) -> const std::vector<VertexId>& { return adjacency_[static_cast<std::size_t>(x)]; };
    const double left = block_left_of(g_.positions, neighbours, v, w);
    const double right = block_left_of(g_.positions, neighbours, w, v);
    adjacency_[static_cast<std::size_t>(v)].pop_back();
    adjacency_[static_cast<std::size_t>(w)].pop_back();
    return (left > 0 && left < min_block_m2_) || (right > 0 && right < min_block_m2_);
}

void Grower::close_dead_ends() {
    std::vector<double> lengths;
    for (std::size_t e = base_edges_; e < g_.edge_count(); ++e) lengths.push_back(g_.edge_length(static_cast<EdgeId>(e)));
    if (lengths.empty() || o_.close_dead_ends <= 0) return;
    std::nth_element(lengths.begin(), lengths.begin() + static_cast<long>(lengths.size() / 2), lengths.end());
    const double reach = o_.close_dead_ends * lengths[lengths.size() / 2];
    const double narrow = city_narrow_angle(2.0 * lengths[lengths.size() / 2]);
    // The dead ends to join: the grown ones, and those of the base that reach the region
    // (a street cut at its border, pointing in) where nothing was grown on: a street that
    // reaches the region is joined to what grew there, even where tracing could not carry
    // it on (two carriageways side by side, a street too close to another).
    std::vector<VertexId> loose;
    // The class of the (last) street at each vertex of the base, for the street that joins it.
    std::vector<HighwayClass> base_class(base_vertices_, g_.edge_highway[g_.edge_count() - 1]);
    for (std::size_t e = 0; e < g_.edge_count(); ++e) {
        for (const VertexId x : g_.edges[e]) {
            if (static_cast<std::size_t>(x) < base_vertices_) base_class[static_cast<std::size_t>(x)] = g_.edge_highway[e];
        }
    }
    for (std::size_t v = 0; v < base_vertices_; ++v) {
        // Of every class: a motorway the region cut goes on into what grew there too.
        if (adjacency_[v].size() != 1) continue;
        const Vec2 p = g_.positions[v];
        const Vec2 ahead = (p - g_.positions[static_cast<std::size_t>(adjacency_[v][0])]).normalized();
        // Into the region, not along its border.
        const Vec2 in = p + 0.5 * reach * ahead;
        if (near_region(p, 0.25 * reach) && inside(region_, in) && distance_to_ring(region_, in) >= 0.15 * reach) {
            loose.push_back(static_cast<VertexId>(v));
        }
    }
    for (std::size_t v = base_vertices_; v < g_.vertex_count(); ++v) {
        if (adjacency_[v].size() == 1) loose.push_back(static_cast<VertexId>(v));
    }
    std::vector<char> joined_from_base(g_.vertex_count(), 0);
    for (const VertexId loose_end : loose) {
        const auto v = static_cast<std::size_t>(loose_end);
        if (adjacency_[v].size() != 1) continue;
        const bool from_base = v < base_vertices_;

        const Vec2 p = g_.positions[v];
        const Vec2 ahead = (p - g_.positions[static_cast<std::size_t>(adjacency_[v][0])]).normalized();
        VertexId best = -1;
        double best_d = reach;
        const Box window = spatial::around(p, reach);
        for (auto it = vertices_.qbegin(bgi::intersects(window)); it != vertices_.qend(); ++it) {
            const VertexId w = it->second;
            if (static_cast<std::size_t>(w) == v || adjacency_[static_cast<std::size_t>(w)].size() >= 4) continue;
            // One street of the base to a vertex: several would fan out from it.
            if (from_base && (static_cast<std::size_t>(w) < base_vertices_ ||
                              (static_cast<std::size_t>(w) < joined_from_base.size() && joined_from_base[static_cast<std::size_t>(w)]))) {
                continue;
            }
            const Vec2 d = g_.positions[static_cast<std::size_t>(w)] - p;
            const double length = d.norm();
            const auto& n = adjacency_[v];
            if (length >= best_d || d.dot(ahead) < 0.7 * length || std::find(n.begin(), n.end(), w) != n.end()) continue;
            if (!inside(region_, 0.5 * (p + g_.positions[static_cast<std::size_t>(w)]))) continue; // stays in the region
            if (crosses(p, g_.positions[static_cast<std::size_t>(w)])) continue;
            if (clearance_at(w, -d) < (from_base ? kMinMergeAngle : narrow)) continue;
            if (min_block_m2_ > 0 && closes_small_block(static_cast<VertexId>(v), w)) continue;
            best = w;
            best_d = length;
        }
        EdgeAttributes attributes;
        attributes.highway = g_.edge_highway[g_.edge_count() - 1];
        if (from_base) {
            attributes.highway = base_class[v];
        } else {
            for (std::size_t e = base_edges_; e < g_.edge_count(); ++e) {
                if (g_.edges[e][0] == static_cast<VertexId>(v) || g_.edges[e][1] == static_cast<VertexId>(v)) attributes.highway = g_.edge_highway[e];
            }
        }
        if (best < 0) {
            // No vertex ahead: the grown street ahead, if there is one, gets a T-junction; a
            // street of the base, where none is straight ahead, merges into the one beside it.
            if (join_street_ahead(static_cast<VertexId>(v), ahead, reach, attributes, narrow) ||
                (from_base && join_street_beside(static_cast<VertexId>(v), ahead, reach, attributes))) {
                ++report_->t_junctions;
            }
            continue;
        }
        if (from_base) {
            // (T-junctions made on the way add vertices after the first.)
            joined_from_base.resize(std::max(joined_from_base.size(), g_.vertex_count()), 0);
            joined_from_base[static_cast<std::size_t>(best)] = 1;
        }
        const EdgeId e = g_.add_edge(static_cast<VertexId>(v), best, attributes);
        adjacency_[v].push_back(best);
        adjacency_[static_cast<std::size_t>(best)].push_back(static_cast<VertexId>(v));
        index_edge(e);
        ++report_->closing_edges;
    }
}

void Grower::prune_stubs() {
    if (o_.prune_stubs <= 0 || g_.edge_count() == base_edges_) return;
    std::vector<double> lengths;
    for (std::size_t e = base_edges_; e < g_.edge_count(); ++e) lengths.push_back(g_.edge_length(static_cast<EdgeId>(e)));
    std::nth_element(lengths.begin(), lengths.begin() + static_cast<long>(lengths.size() / 2), lengths.end());
    const double typical = lengths[lengths.size() / 2];
    const double shortest = o_.prune_stubs * typical;
    // The grown dead-end streets that could go: from a grown dead end along grown bends (the
    // vertices of two streets) to a junction of three streets or more, by length.
    struct Stub {
        double length = 0.0;
        std::vector<VertexId> vertices; // the dead end and the bends
        std::vector<EdgeId> edges;
        VertexId junction = -1;
    };
    std::vector<std::vector<EdgeId>> edges_at(g_.vertex_count());
    for (std::size_t e = 0; e < g_.edge_count(); ++e) {
        for (const VertexId x : g_.edges[e]) edges_at[static_cast<std::size_t>(x)].push_back(static_cast<EdgeId>(e));
    }
    std::vector<Stub> stubs;
    for (std::size_t v = base_vertices_; v < g_.vertex_count(); ++v) {
        if (edges_at[v].size() != 1) continue;
        Stub stub;
        VertexId at = static_cast<VertexId>(v);
        EdgeId along = edges_at[v][0];
        for (;;) {
            stub.vertices.push_back(at);
            stub.edges.push_back(along);
            stub.length += g_.edge_length(along);
            const auto [a, b] = g_.edges[static_cast<std::size_t>(along)];
            const VertexId next = a == at ? b : a;
            const auto& next_edges = edges_at[static_cast<std::size_t>(next)];
            if (next_edges.size() >= 3) {
                stub.junction = next;
                break;
            }
            // Not a street of its own (both ends loose), and not through the base.
            if (next_edges.size() != 2 || static_cast<std::size_t>(next) < base_vertices_ || stub.edges.size() > 64) break;
            at = next;
            along = next_edges[0] == along ? next_edges[1] : next_edges[0];
        }
        if (stub.junction >= 0) stubs.push_back(std::move(stub));
    }
    std::sort(stubs.begin(), stubs.end(), [](const Stub& x, const Stub& y) { return x.length < y.length; });
    // The short ones go. So do longer ones, up to two typical streets, while the grown streets
    // have more dead ends than the city has around the region: a district that ends in the
    // open more often than its city does not look like it.
    // Counted among the ends and junctions only: the bends are dissolved and the streets split
    // again later (dissolve_bends, split_streets), as often as the city's are, so a share of all
    // vertices here would not be the share of the district grown (Krems: 0.15 here, 0.24 grown).
    std::size_t grown_vertices = 0, grown_dead_ends = 0;
    for (std::size_t v = base_vertices_; v < g_.vertex_count(); ++v) {
        grown_vertices += !edges_at[v].empty() && edges_at[v].size() != 2;
        grown_dead_ends += edges_at[v].size() == 1;
    }
    // (Where there is too little city to say, only the short ones go.)
    const double allowed = city_dead_end_share(2.0 * typical).value_or(1.0);
    std::vector<char> drop_vertex(g_.vertex_count(), 0), drop_edge(g_.edge_count(), 0);
    std::vector<std::size_t> lost(g_.vertex_count(), 0); // streets a junction lost
    std::size_t dropped = 0;
    for (const Stub& stub : stubs) {
        // A junction that lost a stub already may have become a bend.
        if (edges_at[static_cast<std::size_t>(stub.junction)].size() - lost[static_cast<std::size_t>(stub.junction)] < 3) continue;
        const bool too_many = static_cast<double>(grown_dead_ends) > allowed * static_cast<double>(grown_vertices);
        if (stub.length >= shortest && !(too_many && stub.length < 2.0 * typical)) break;
        for (const VertexId x : stub.vertices) drop_vertex[static_cast<std::size_t>(x)] = 1;
        for (const EdgeId e : stub.edges) drop_edge[static_cast<std::size_t>(e)] = 1;
        ++lost[static_cast<std::size_t>(stub.junction)];
        --grown_dead_ends;
        --grown_vertices; // (its bends were not counted)
        // A grown junction of three streets left with two is a bend now.
        if (static_cast<std::size_t>(stub.junction) >= base_vertices_ &&
            edges_at[static_cast<std::size_t>(stub.junction)].size() - lost[static_cast<std::size_t>(stub.junction)] == 2) {
            --grown_vertices;
        }
        ++dropped;
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

std::vector<VertexId> Grower::city_around(double margin) const {
    // The base's vertices near the region (within half its size beyond `margin`),
    // away from its border, where the cut left the severed streets' ends, and from the
    // extract's edges, where the map was cut.
    const auto base_end = g_.positions.begin() + static_cast<std::ptrdiff_t>(base_vertices_);
    const Eigen::AlignedBox2d extent = bounds(g_.positions.begin(), base_end);
    const double reach = margin + 0.5 * bounds(region_.begin(), region_.end()).sizes().maxCoeff();
    std::vector<VertexId> around;
    for (std::size_t v = 0; v < base_vertices_; ++v) {
        const Vec2 p = g_.positions[v];
        if (adjacency_[v].empty() || (p - extent.min()).minCoeff() < margin || (extent.max() - p).minCoeff() < margin) continue;
        if (inside(region_, p) || adjacency_[v].size() == 2) continue; // (ends and junctions only)
        const double d = distance_to_ring(region_, p);
        if (d < margin || d > reach) continue;
        around.push_back(static_cast<VertexId>(v));
    }
    return around;
}

std::optional<double> Grower::city_dead_end_share(double margin) const {
    const std::vector<VertexId> around = city_around(margin);
    if (around.size() < 20) return std::nullopt; // too few to say
    const auto dead_ends = std::count_if(around.begin(), around.end(), [&](VertexId v) { return adjacency_[static_cast<std::size_t>(v)].size() == 1; });
    return static_cast<double>(dead_ends) / static_cast<double>(around.size());
}

double Grower::city_narrow_angle(double margin) const {
    std::vector<double> angles, bearings;
    for (const VertexId v : city_around(margin)) {
        if (adjacency_[static_cast<std::size_t>(v)].size() < 3) continue;
        bearings.clear();
        for (const Vec2& d : first_pieces_at(v)) bearings.push_back(std::atan2(d.y(), d.x()));
        std::sort(bearings.begin(), bearings.end());
        for (std::size_t i = 0; i < bearings.size(); ++i) {
            angles.push_back((i + 1 < bearings.size() ? bearings[i + 1] : bearings.front() + 2 * M_PI) - bearings[i]);
        }
    }
    if (angles.size() < 50) return kMinJoinAngle; // too few to say
    auto narrow = angles.begin() + static_cast<std::ptrdiff_t>(0.03 * static_cast<double>(angles.size()));
    std::nth_element(angles.begin(), narrow, angles.end());
    return std::clamp(*narrow, kMinMergeAngle, kMinJoinAngle);
}

bool Grower::join_street_ahead(VertexId v, const Vec2& ahead, double reach, const EdgeAttributes& attributes, double min_angle) {
    const Vec2 p = g_.positions[static_cast<std::size_t>(v)];
    const Vec2 end = p + reach * ahead;
    Box box(point(p), point(p));
    bg::expand(box, point(end));
    double first_t = 2.0;
    EdgeId hit = -1;
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
            }
        }
    }
    if (hit < 0 || static_cast<std::size_t>(hit) < base_edges_) return false;
    return t_junction(v, hit, p + first_t * (end - p), attributes, min_angle);
}

bool Grower::join_street_beside(VertexId v, const Vec2& ahead, double reach, const EdgeAttributes& attributes) {
    const Vec2 p = g_.positions[static_cast<std::size_t>(v)];
    // Points of the grown streets near by, nearest first: the foot of the perpendicular and
    // the quarters of each street, where they lie ahead and the joining street crosses nothing.
    std::vector<std::tuple<double, EdgeId, Vec2>> candidates;
    for (auto it = segments_.qbegin(bgi::intersects(spatial::around(p, reach))); it != segments_.qend(); ++it) {
        const EdgeId e = it->second;
        const auto [a, b] = g_.edges[static_cast<std::size_t>(e)];
        if (static_cast<std::size_t>(e) < base_edges_ || g_.geometry_size(e) != 2 || a == v || b == v) continue;
        const Vec2 pa = g_.positions[static_cast<std::size_t>(a)], pb = g_.positions[static_cast<std::size_t>(b)];
        const Vec2 d = pb - pa;
        for (const double t : {std::clamp((p - pa).dot(d) / std::max(d.squaredNorm(), 1e-300), 0.0, 1.0), 0.25, 0.5, 0.75}) {
            const Vec2 x = pa + t * d;
            const Vec2 to = x - p;
            const double length = to.norm();
            if (length < 1e-9 || length >= reach || to.dot(ahead) < 0.7 * length) continue;
            candidates.emplace_back(length, e, x);
        }
    }
    std::sort(candidates.begin(), candidates.end(), [](const auto& x, const auto& y) { return std::get<0>(x) < std::get<0>(y); });
    // Whether p-x crosses a street other than the one it ends on (it touches that one at x).
    auto crosses_another = [&](const Vec2& x, EdgeId target) {
        Box box(point(p), point(p));
        bg::expand(box, point(x));
        for (auto it = segments_.qbegin(bgi::intersects(box)); it != segments_.qend(); ++it) {
            if (it->second == target) continue;
            const Vec2* q = g_.geometry_begin(it->second);
            for (std::size_t i = 0; i + 1 < g_.geometry_size(it->second); ++i) {
                if (segments_meet(p, x, q[i], q[i + 1])) return true;
            }
        }
        return false;
    };
    for (const auto& [length, e, x] : candidates) {
        if (!crosses_another(x, e) && t_junction(v, e, x, attributes, kMinMergeAngle)) return true;
    }
    return false;
}

bool Grower::t_junction(VertexId v, EdgeId hit, const Vec2& x, const EdgeAttributes& attributes, double min_angle) {
    const Vec2 p = g_.positions[static_cast<std::size_t>(v)];
    const auto e = static_cast<std::size_t>(hit);
    const auto [a, b] = g_.edges[e];
    const double length = g_.edge_length(hit);
    const double keep = std::max(o_.spacing * length, 1e-6);
    if ((x - g_.positions[static_cast<std::size_t>(a)]).norm() < keep || (x - g_.positions[static_cast<std::size_t>(b)]).norm() < keep) return false;
    {
        // Across the street, not along it.
        const Vec2* q = g_.geometry_begin(hit);
        for (std::size_t i = 0; i + 1 < g_.geometry_size(hit); ++i) {
            if (distance_to_segment(x, q[i], q[i + 1]) > 1e-6) continue;
            const Vec2 along = q[i + 1] - q[i], in = x - p;
            if (along.norm() > 1e-9 && in.norm() > 1e-9 && std::abs(cross(along.normalized(), in.normalized())) < std::sin(min_angle)) return false;
            break;
        }
    }
    // The junction in the region too: a grown street may leave it to join one of the base.
    if (!inside(region_, x) || !inside(region_, 0.5 * (p + x))) return false;
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

} // namespace ggg::growth_detail
