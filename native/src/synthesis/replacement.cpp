// Terminal replacement by one derivation step; see replacement.hpp.
#include "ggg/synthesis/replacement.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <boost/geometry/algorithms/centroid.hpp>
#include <boost/geometry/algorithms/convex_hull.hpp>
#include <boost/geometry/geometries/multi_point.hpp>
#include <boost/geometry/geometries/polygon.hpp>

#include "ggg/error.hpp"
#include "ggg/grammar/grammar.hpp"
#include "ggg/grammar/rewriting.hpp"
#include "ggg/graph/plane_geometry.hpp"
#include "ggg/graph/spatial_index.hpp"

namespace ggg {

namespace {

// How much of the room an occurrence leaves its piece takes: the rest is the margin between
// the piece and the streets around it.
constexpr double kFill = 0.8;

// The frame that puts the piece into one occurrence: the occurrence's own transform, then
// centred on the occurrence's area and scaled so that every vertex of the piece lies within
// its convex hull, the hull shrunk to kFill, and smaller while the piece would cross a street
// that stays (`crosses`; twelve steps of 0.8 at most, then the smallest). A plaza for a block stays inside the block, whatever size it was
// drawn at and however the block differs from the pattern's mean shape. An occurrence with
// no area (a path, a fork) keeps its transform.
template <class Crosses>
Similarity2 fitted_frame(const Similarity2& transform, const std::vector<Vec2>& occurrence, const ReplacementGraph& drawn,
                         Crosses&& crosses) {
    const std::vector<Vec2>& piece = drawn.positions;
    namespace bg = spatial::bg;
    bg::model::multi_point<spatial::Point> points;
    for (const Vec2& p : occurrence) points.push_back(spatial::point(p));
    bg::model::polygon<spatial::Point, false> hull; // counter-clockwise
    bg::convex_hull(points, hull);
    const auto& ring = hull.outer();
    const double area = std::abs(bg::area(hull));
    double span = 0.0;
    for (const Vec2& p : occurrence) {
        for (const Vec2& q : occurrence) span = std::max(span, (p - q).norm());
    }
    if (ring.size() < 4 || area < 0.05 * span * span) return transform;
    spatial::Point c{0.0, 0.0};
    bg::centroid(hull, c);
    const Vec2 centre(bg::get<0>(c), bg::get<1>(c));
    Vec2 mean = Vec2::Zero();
    for (const Vec2& p : piece) mean += transform.apply(p);
    mean /= static_cast<double>(piece.size());
    // The largest s with centre + s (q - mean) inside every side of the hull, for every q.
    double largest = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i + 1 < ring.size(); ++i) {
        const Vec2 a(bg::get<0>(ring[i]), bg::get<1>(ring[i])), b(bg::get<0>(ring[i + 1]), bg::get<1>(ring[i + 1]));
        Vec2 normal(b.y() - a.y(), a.x() - b.x()); // outward for either orientation, below
        if (normal.dot(centre - a) > 0) normal = -normal;
        const double room = normal.dot(a - centre);
        for (const Vec2& p : piece) {
            const double out = normal.dot(transform.apply(p) - mean);
            if (out > 1e-12 * normal.norm()) largest = std::min(largest, room / out);
        }
    }
    if (!std::isfinite(largest) || largest <= 0) return transform;
    // The hull of an occurrence that is not one block (two blocks and a street) reaches over
    // streets around it: smaller, until the piece crosses none of them.
    double s = kFill * largest;
    for (int tries = 0; tries < 12; ++tries, s *= 0.8) {
        const Similarity2 frame = Similarity2{s, 0.0, centre - s * mean} * transform;
        bool crossing = false;
        for (const auto& [a, b] : drawn.edges) {
            crossing = crossing || crosses(frame.apply(piece[static_cast<std::size_t>(a)]), frame.apply(piece[static_cast<std::size_t>(b)]));
        }
        if (!crossing) return frame;
    }
    // Crossing at every size: the smallest tried, whose crossings become intersections.
    s /= 0.8;
    return Similarity2{s, 0.0, centre - s * mean} * transform;
}

// Where an edge that a replacement added crosses another street, both get an intersection
// there (one vertex, splitting both), as streets meet in a city. Edges from `first_new` on
// are the added ones (edges a split appends are checked too). Returns the intersections made.
std::size_t join_crossings(GeometricGraph& g, std::size_t first_new) {
    using spatial::EdgeEntry;
    // Every street by its box; a street split here keeps its id and its old (larger) box, and
    // its second half is added.
    spatial::IncrementalRTree<EdgeEntry> streets;
    for (std::size_t e = 0; e < g.edge_count(); ++e) streets.insert({spatial::edge_box(g, static_cast<EdgeId>(e)), static_cast<EdgeId>(e)});
    // The streets to check: those the replacement added and the pieces split off them (not
    // the pieces of the streets that stay, which may pass over others on a bridge).
    std::vector<char> added(g.edge_count(), 0);
    std::vector<EdgeId> work;
    for (std::size_t e = first_new; e < g.edge_count(); ++e) {
        added[e] = 1;
        work.push_back(static_cast<EdgeId>(e));
    }
    std::size_t made = 0;
    std::vector<EdgeEntry> near;
    for (std::size_t next = 0; next < work.size(); ++next) {
        const EdgeId id = work[next];
        const auto e = static_cast<std::size_t>(id);
        for (bool again = true; again;) {
            again = false;
            const Vec2 p = g.positions[static_cast<std::size_t>(g.edges[e][0])], q = g.positions[static_cast<std::size_t>(g.edges[e][1])];
            const double eps = 1e-9 * std::max(1.0, (q - p).norm());
            // The first crossing along e, over every other street's pieces (a street that shares
            // an end with e may still cross it further on, if it bends).
            double best_t = 1.0;
            EdgeId best_f = -1;
            Vec2 where = Vec2::Zero();
            near.clear();
            streets.query(spatial::bgi::intersects(spatial::around(p, q)), std::back_inserter(near));
            for (const auto& [box, f] : near) {
                if (f == id) continue;
                const Vec2* line = g.geometry_begin(f);
                for (std::size_t k = 0; k + 1 < g.geometry_size(f); ++k) {
                    const auto m = segment_meeting(p, q, line[k], line[k + 1]);
                    if (!m) continue;
                    const double u_eps = 1e-9 * std::max(1.0, (line[k + 1] - line[k]).norm());
                    const bool inner_u = (k > 0 || m->second > u_eps) && (k + 2 < g.geometry_size(f) || m->second < 1.0 - u_eps);
                    if (m->first > eps && m->first < best_t - eps && inner_u) {
                        best_t = m->first;
                        best_f = f;
                        where = p + m->first * (q - p);
                    }
                }
            }
            if (best_f < 0 || best_t >= 1.0 - eps) continue;
            // Split e, then f at the same point, and let f's two halves end at e's new vertex.
            const VertexId x = g.split_edge(id, where);
            const auto tail = static_cast<EdgeId>(g.edge_count() - 1);
            streets.insert({spatial::edge_box(g, tail), tail});
            added.push_back(1);
            work.push_back(tail);
            g.split_edge(best_f, where);
            g.edges[static_cast<std::size_t>(best_f)][1] = x;
            g.edges.back()[0] = x;
            const auto f_tail = static_cast<EdgeId>(g.edge_count() - 1);
            streets.insert({spatial::edge_box(g, f_tail), f_tail});
            added.push_back(added[static_cast<std::size_t>(best_f)]);
            if (added[static_cast<std::size_t>(best_f)]) work.push_back(f_tail);
            // The vertex the second split made is the last, and nothing refers to it any more.
            g.positions.pop_back();
            g.vertex_osm_ids.pop_back();
            g.symbols.pop_back();
            g.frames.pop_back();
            if (g.instances.size() > g.vertex_count()) g.instances.pop_back();
            ++made;
            again = true;
        }
    }
    return made;
}

} // namespace

ReplacementGraph fit_replacement(const ReplacementGraph& drawn, const Pattern& pattern) {
    if (drawn.positions.empty()) throw UsageError("the replacement has no vertices");
    const Spread s = spread_of(drawn.positions);
    const Spread p = spread_of(pattern.positions);
    ReplacementGraph out = drawn;
    const double scale = s.degenerate || p.degenerate ? 1.0 : p.rms / s.rms;
    for (Vec2& v : out.positions) v = p.centroid + scale * (v - s.centroid);
    return out;
}

GeometricGraph replace_occurrences(const GeometricGraph& g, const Isogroup& group, std::span<const std::uint32_t> chosen,
                                   const ReplacementGraph& r, ReplaceReport* report_out) {
    if (r.positions.empty()) throw UsageError("the replacement has no vertices");
    if (!r.edge_highway.empty() && r.edge_highway.size() != r.edges.size()) throw UsageError("the replacement needs one road class per edge");
    for (const auto& [a, b] : r.edges) {
        if (a < 0 || b < 0 || static_cast<std::size_t>(a) >= r.positions.size() || static_cast<std::size_t>(b) >= r.positions.size() || a == b) {
            throw UsageError("a replacement edge joins vertices out of range");
        }
    }
    // Which occurrence each vertex belongs to.
    std::vector<std::int32_t> owner(g.vertex_count(), -1);
    for (std::size_t c = 0; c < chosen.size(); ++c) {
        if (chosen[c] >= group.frequency()) throw UsageError("occurrence " + std::to_string(chosen[c]) + " out of range");
        for (VertexId v : group.occurrence(chosen[c])) {
            if (v < 0 || static_cast<std::size_t>(v) >= g.vertex_count()) throw UsageError("an occurrence vertex is out of range");
            if (owner[static_cast<std::size_t>(v)] >= 0) throw UsageError("the occurrences to replace share vertices");
            owner[static_cast<std::size_t>(v)] = static_cast<std::int32_t>(c);
        }
    }
    // What an occurrence gives up: its own streets, and its vertices that no other street
    // reaches. A vertex where streets of the surroundings meet stays, so that the streets
    // around keep their course, and the piece is joined to it. Its class is the most
    // important of the occurrence's streets there.
    auto own_street = [&](std::size_t e) {
        const std::int32_t oa = owner[static_cast<std::size_t>(g.edges[e][0])];
        return oa >= 0 && oa == owner[static_cast<std::size_t>(g.edges[e][1])];
    };
    std::vector<char> junction(g.vertex_count(), 0);
    std::vector<HighwayClass> join_class(g.vertex_count(), HighwayClass::residential);
    std::vector<int> join_rank(g.vertex_count(), std::numeric_limits<int>::max());
    for (std::size_t e = 0; e < g.edge_count(); ++e) {
        for (const VertexId v : g.edges[e]) {
            const auto i = static_cast<std::size_t>(v);
            if (owner[i] < 0) continue;
            if (!own_street(e)) {
                junction[i] = 1;
            } else if (highway_rank(g.edge_highway[e]) < join_rank[i]) {
                join_rank[i] = highway_rank(g.edge_highway[e]);
                join_class[i] = g.edge_highway[e];
            }
        }
    }

    // The grammar: one rule, the replacement; one instance per occurrence.
    Grammar grammar;
    grammar.name = "replacement";
    grammar.symbol_names = {"replacement"};
    Rule rule;
    rule.symbol = 1;
    for (const Vec2& p : r.positions) rule.vertices.push_back({p, 0, Frame{}, {}});
    for (std::size_t e = 0; e < r.edges.size(); ++e) {
        rule.edges.push_back({r.edges[e][0], r.edges[e][1], r.edge_highway.empty() ? HighwayClass::residential : r.edge_highway[e]});
    }
    grammar.rules.push_back(rule);
    grammar.axiom_vertices.push_back({}); // unused: the host graph is given
    grammar.encoding.mode = "paper";
    grammar.encoding.levels = 1;

    // The host: the graph without what the occurrences give up, plus one nonterminal per
    // occurrence in the frame that fits the piece into it.
    GeometricGraph host;
    host.origin = g.origin;
    std::vector<VertexId> new_id(g.vertex_count(), -1);
    std::size_t removed = 0;
    for (std::size_t v = 0; v < g.vertex_count(); ++v) {
        if (owner[v] >= 0 && !junction[v]) {
            ++removed;
            continue;
        }
        new_id[v] = host.add_vertex(g.positions[v], g.vertex_osm_ids[v]);
        host.symbols.back() = g.symbols.empty() ? 0 : g.symbols[v];
        host.frames.back() = g.frames.empty() ? Similarity2::from(1, 0, g.positions[v]) : g.frames[v];
        copy_more_rewrites(g, static_cast<VertexId>(v), host, new_id[v]);
    }
    for (std::size_t e = 0; e < g.edge_count(); ++e) {
        if (own_street(e)) continue;
        const auto id = static_cast<EdgeId>(e);
        std::vector<Vec2> line(g.geometry_begin(id), g.geometry_begin(id) + g.geometry_size(id));
        host.add_edge(new_id[static_cast<std::size_t>(g.edges[e][0])], new_id[static_cast<std::size_t>(g.edges[e][1])], g.edge_attributes(id), line);
    }
    const std::size_t kept_vertices = host.vertex_count(), kept_edges = host.edge_count();
    // Whether a segment crosses a street that stays (touching one at a junction is no crossing).
    std::vector<spatial::EdgeEntry> entries;
    for (std::size_t e = 0; e < kept_edges; ++e) entries.emplace_back(spatial::edge_box(host, static_cast<EdgeId>(e)), static_cast<EdgeId>(e));
    const spatial::RTree<spatial::EdgeEntry> streets(entries.begin(), entries.end());
    auto crosses_a_street = [&](const Vec2& p, const Vec2& q) {
        for (auto it = streets.qbegin(spatial::bgi::intersects(spatial::around(p, q))); it != streets.qend(); ++it) {
            const Vec2* line = host.geometry_begin(it->second);
            for (std::size_t k = 0; k + 1 < host.geometry_size(it->second); ++k) {
                if (segments_meet(p, q, line[k], line[k + 1])) return true;
            }
        }
        return false;
    };
    host.instances.assign(host.vertex_count(), -1);
    double smallest = std::numeric_limits<double>::infinity();
    std::size_t joined = 0;
    for (std::size_t c = 0; c < chosen.size(); ++c) {
        std::vector<Vec2> occurrence;
        for (VertexId v : group.occurrence(chosen[c])) occurrence.push_back(g.positions[static_cast<std::size_t>(v)]);
        const Similarity2 frame = fitted_frame(group.transforms[chosen[c]], occurrence, r, crosses_a_street);
        host.add_vertex(frame.t);
        host.symbols.back() = 1;
        host.frames.back() = frame;
        host.instances.push_back(static_cast<std::int32_t>(c));
        smallest = std::min(smallest, frame.scale());
        // Each junction the occurrence kept is joined to the piece's vertex nearest to it: an
        // embedding point aimed at the junction.
        RuleInstance inst;
        inst.symbol = 1;
        std::vector<Vec2> placed;
        for (const Vec2& p : r.positions) placed.push_back(frame.apply(p));
        const Similarity2 back = frame.inverse();
        for (VertexId v : group.occurrence(chosen[c])) {
            const auto i = static_cast<std::size_t>(v);
            if (!junction[i]) continue;
            std::size_t best = 0;
            for (std::size_t k = 1; k < placed.size(); ++k) {
                if ((placed[k] - g.positions[i]).squaredNorm() < (placed[best] - g.positions[i]).squaredNorm()) best = k;
            }
            RuleInstance::Link link;
            link.vertex = static_cast<std::int32_t>(best);
            link.point.offset = back.apply_linear(g.positions[i] - placed[best]);
            link.point.highway = join_class[i];
            inst.embedding.push_back(link);
            ++joined;
        }
        grammar.encoding.instances.push_back(inst);
    }
    DeriveOptions o;
    o.max_steps = 1;
    o.tolerance = std::isfinite(smallest) ? 1e-6 * std::max(1.0, smallest) : 1e-6;
    o.tolerance_relative = false;
    o.max_vertices = host.vertex_count() + chosen.size() * r.positions.size() + 1;
    if (!chosen.empty()) derive(host, grammar, o);
    host.instances.clear();
    const std::size_t intersections = join_crossings(host, kept_edges);
    if (report_out) {
        report_out->replaced = chosen.size();
        report_out->removed_vertices = removed;
        report_out->added_vertices = host.vertex_count() - kept_vertices;
        report_out->joined_streets = joined;
        report_out->intersections = intersections;
    }
    return host;
}

} // namespace ggg
