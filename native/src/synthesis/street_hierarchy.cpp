// Main roads continued through grown streets; see street_hierarchy.hpp.
#include "ggg/synthesis/street_hierarchy.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <tuple>
#include <queue>
#include <unordered_map>
#include <vector>


#include "ggg/error.hpp"
#include "ggg/graph/plane_geometry.hpp"
#include "ggg/graph/road_class.hpp"
#include "ggg/graph/spatial_index.hpp"

namespace ggg {

namespace {

namespace bg = spatial::bg;
namespace bgi = spatial::bgi;

bool main_road_class(HighwayClass c) {
    return highway_rank(c) <= highway_rank(HighwayClass::unclassified) && c != HighwayClass::motorway_link &&
           c != HighwayClass::trunk_link && c != HighwayClass::primary_link && c != HighwayClass::secondary_link &&
           c != HighwayClass::tertiary_link;
}

struct MainRoad {
    VertexId vertex = -1;
    HighwayClass highway = HighwayClass::other;
    int local = -1; // index among the grown streets' vertices
    std::vector<Vec2> headings; // unit directions in which its main streets arrive at it
};

// A straight main road from s to t, made of the pieces between the grown streets it crosses
// (each crossing becomes an intersection). Nothing when it would cross a street that the
// growth started from, or pass too close to a vertex that it does not go through.
struct Connector {
    std::vector<std::pair<double, VertexId>> through; // grown vertices it passes, by t
    std::vector<std::tuple<double, std::size_t, Vec2>> splits; // (t, grown edge, where)
};

// Where the streets are, for the connectors' searches: the vertices and the polyline
// segments of the graph in R-trees, and which vertices belong to the streets before the
// grown ones. Built again after each connector (which adds and splits streets).
class StreetIndex {
public:
    StreetIndex(const GeometricGraph& g, std::size_t first) : g_(g), first_(first) { build(); }

    void build() {
        in_base_.assign(g_.vertex_count(), 0);
        for (std::size_t e = 0; e < first_; ++e) {
            in_base_[static_cast<std::size_t>(g_.edges[e][0])] = in_base_[static_cast<std::size_t>(g_.edges[e][1])] = 1;
        }
        std::vector<PointEntry> points;
        points.reserve(g_.vertex_count());
        for (std::size_t v = 0; v < g_.vertex_count(); ++v) points.push_back({point(g_.positions[v]), static_cast<VertexId>(v)});
        vertices_ = VertexTree(points.begin(), points.end());
        std::vector<SegmentEntry> segments;
        for (std::size_t e = 0; e < g_.edge_count(); ++e) {
            const Vec2* p = g_.geometry_begin(static_cast<EdgeId>(e));
            for (std::size_t k = 0; k + 1 < g_.geometry_size(static_cast<EdgeId>(e)); ++k) {
                segments.push_back({around(p[k], p[k + 1], 0.0), {e, k}});
            }
        }
        segments_ = SegmentTree(segments.begin(), segments.end());
    }

    bool in_base(VertexId v) const { return in_base_[static_cast<std::size_t>(v)] != 0; }

    // Vertices within `margin` of the box of pq.
    template <class F>
    void vertices_near(const Vec2& p, const Vec2& q, double margin, F&& f) const {
        for (auto it = vertices_.qbegin(bgi::intersects(around(p, q, margin))); it != vertices_.qend(); ++it) f(it->second);
    }
    // Polyline segments (edge, index) whose box meets the box of pq.
    template <class F>
    void segments_near(const Vec2& p, const Vec2& q, F&& f) const {
        for (auto it = segments_.qbegin(bgi::intersects(around(p, q, 0.0))); it != segments_.qend(); ++it) {
            f(it->second.first, it->second.second);
        }
    }

private:
    using Box = spatial::Box;
    using PointEntry = spatial::VertexEntry;
    using SegmentEntry = std::pair<Box, std::pair<std::size_t, std::size_t>>; // (edge, piece of its polyline)
    using VertexTree = spatial::RTree<PointEntry>;
    using SegmentTree = spatial::RTree<SegmentEntry>;

    static spatial::Point point(const Vec2& p) { return spatial::point(p); }
    static Box around(const Vec2& p, const Vec2& q, double margin) { return spatial::around(p, q, margin); }

    const GeometricGraph& g_;
    std::size_t first_;
    std::vector<char> in_base_;
    VertexTree vertices_;
    SegmentTree segments_;
};

std::optional<Connector> plan_connector(const GeometricGraph& g, const StreetIndex& index, std::size_t first, VertexId s,
                                        VertexId t, double clearance) {
    const Vec2 p = g.positions[static_cast<std::size_t>(s)];
    const Vec2 q = g.positions[static_cast<std::size_t>(t)];
    const Vec2 d = q - p;
    Connector c;
    // Grown vertices close beside it: it goes through them (a street of a city: not at all),
    // rather than leave a sliver between them and it.
    bool blocked = false;
    index.vertices_near(p, q, clearance, [&](VertexId v) {
        if (v == s || v == t || blocked) return;
        if (distance_to_segment(g.positions[static_cast<std::size_t>(v)], p, q) >= clearance) return;
        if (index.in_base(v)) blocked = true;
        c.through.push_back({std::clamp((g.positions[static_cast<std::size_t>(v)] - p).dot(d) / d.squaredNorm(), 0.0, 1.0), v});
    });
    if (blocked) return std::nullopt;
    auto on_chain = [&](VertexId v) {
        return v == s || v == t ||
               std::any_of(c.through.begin(), c.through.end(), [&](const auto& x) { return x.second == v; });
    };
    // No junction of more than four streets: the connector goes through a vertex only where the
    // two pieces it brings there (less those along a street already there) leave it at most four.
    if (!c.through.empty()) {
        std::unordered_map<VertexId, int> degree, along;
        for (const auto& [at, v] : c.through) degree[v] = 0, along[v] = 0;
        for (const auto& [a, b] : g.edges) {
            for (const auto& [x, y] : {std::pair{a, b}, std::pair{b, a}}) {
                if (const auto it = degree.find(x); it != degree.end()) {
                    ++it->second;
                    if (on_chain(y)) ++along[x];
                }
            }
        }
        for (const auto& [v, streets] : degree) {
            if (streets + 2 - std::min(2, along[v]) > 4) return std::nullopt;
        }
    }
    // The grown streets it crosses away from those vertices are split where it crosses.
    index.segments_near(p, q, [&](std::size_t e, std::size_t k) {
        if (blocked) return;
        const auto [a, b] = g.edges[e];
        if (on_chain(a) || on_chain(b)) return;
        const Vec2* points = g.geometry_begin(static_cast<EdgeId>(e));
        const auto m = segment_meeting(p, q, points[k], points[k + 1]);
        if (!m) return;
        // Through a street of a city, or a grown one that is not straight: no connector.
        if (e < first || g.geometry_size(static_cast<EdgeId>(e)) != 2) {
            blocked = true;
            return;
        }
        c.splits.push_back({m->first, e, p + m->first * d});
    });
    if (blocked) return std::nullopt;
    // The pieces between its vertices, as they will be (bent through the vertices beside the
    // line), may cross nothing but at their own ends.
    std::vector<std::tuple<double, Vec2, VertexId, long>> chain; // (t, where, vertex or -1, split edge or -1)
    chain.push_back({0.0, p, s, -1});
    chain.push_back({1.0, q, t, -1});
    for (const auto& [at, v] : c.through) chain.push_back({at, g.positions[static_cast<std::size_t>(v)], v, -1});
    for (const auto& [at, e, where] : c.splits) chain.push_back({at, where, -1, static_cast<long>(e)});
    std::sort(chain.begin(), chain.end(), [](const auto& x, const auto& y) { return std::get<0>(x) < std::get<0>(y); });
    for (std::size_t i = 0; i + 1 < chain.size() && !blocked; ++i) {
        // Named variables rather than structured bindings, which the lambda below could not
        // capture before clang 16 (the fuzz build, native/fuzz/, uses clang 14).
        const Vec2& x0 = std::get<1>(chain[i]);
        const Vec2& x1 = std::get<1>(chain[i + 1]);
        const VertexId v0 = std::get<2>(chain[i]), v1 = std::get<2>(chain[i + 1]);
        const long e0 = std::get<3>(chain[i]), e1 = std::get<3>(chain[i + 1]);
        if ((x1 - x0).norm() < 1e-9) return std::nullopt; // two crossings at one point
        index.segments_near(x0, x1, [&](std::size_t e, std::size_t k) {
            const auto [a, b] = g.edges[e];
            if (static_cast<long>(e) == e0 || static_cast<long>(e) == e1) return;
            if ((v0 >= 0 && (a == v0 || b == v0)) || (v1 >= 0 && (a == v1 || b == v1))) return;
            const Vec2* points = g.geometry_begin(static_cast<EdgeId>(e));
            if (segment_meeting(x0, x1, points[k], points[k + 1])) blocked = true;
        });
    }
    if (blocked) return std::nullopt;
    return c;
}

// A main road's end continued straight ahead to the first grown street it meets: a T-junction
// on that street (split there), or the grown vertex it passes within the clearance.
struct Extension {
    long split_edge = -1; // the grown street split at `where`, else -1
    Vec2 where = Vec2::Zero();
    VertexId vertex = -1; // or the grown vertex it ends at
};

std::optional<Extension> plan_extension(const GeometricGraph& g, const StreetIndex& index, std::size_t first, VertexId s,
                                        const Vec2& heading, const HierarchyOptions& o) {
    const Vec2 p = g.positions[static_cast<std::size_t>(s)];
    const Vec2 far = p + o.max_connector_m * heading;
    // The first street ahead: where the ray meets a polyline piece, by distance along it.
    double hit = std::numeric_limits<double>::infinity();
    std::size_t hit_edge = 0;
    index.segments_near(p, far, [&](std::size_t e, std::size_t k) {
        const auto [a, b] = g.edges[e];
        if (a == s || b == s) return;
        const Vec2* points = g.geometry_begin(static_cast<EdgeId>(e));
        const auto m = segment_meeting(p, far, points[k], points[k + 1]);
        if (m && m->first * o.max_connector_m < hit) {
            hit = m->first * o.max_connector_m;
            hit_edge = e;
        }
    });
    if (!std::isfinite(hit) || hit_edge < first) return std::nullopt; // nothing ahead, or a street of the city first
    // A grown vertex within the clearance of the way there: the road ends at it instead.
    Extension x;
    double nearest = hit;
    const Vec2 at = p + hit * heading;
    index.vertices_near(p, at, o.clearance_m, [&](VertexId v) {
        if (v == s || index.in_base(v)) return;
        const Vec2 q = g.positions[static_cast<std::size_t>(v)];
        const double along = (q - p).dot(heading);
        if (along <= 0.0 || along > hit + o.clearance_m || distance_to_segment(q, p, at) >= o.clearance_m) return;
        if (along < nearest || x.vertex < 0) {
            nearest = along;
            x.vertex = v;
        }
    });
    Vec2 target = at;
    if (x.vertex >= 0) {
        target = g.positions[static_cast<std::size_t>(x.vertex)];
        // At most four streets there, and the road meets them at 30 degrees or more: a
        // narrower angle leaves a sliver of a block between it and a street beside it.
        int degree = 0;
        const Vec2 back = p - target;
        for (std::size_t e = 0; e < g.edge_count(); ++e) {
            const auto [a, b] = g.edges[e];
            if (a != x.vertex && b != x.vertex) continue;
            ++degree;
            const Vec2 leaving = (a == x.vertex ? g.geometry_begin(static_cast<EdgeId>(e))[1]
                                                : g.geometry_begin(static_cast<EdgeId>(e))[g.geometry_size(static_cast<EdgeId>(e)) - 2]) - target;
            if (leaving.norm() > 1e-9 && back.norm() > 1e-9 && leaving.normalized().dot(back.normalized()) > std::cos(M_PI / 6)) return std::nullopt;
        }
        if (degree >= 4) return std::nullopt;
    } else {
        // On a street, well clear of its ends, and across it rather than along it.
        const auto [a, b] = g.edges[hit_edge];
        for (VertexId v : {a, b}) {
            if ((g.positions[static_cast<std::size_t>(v)] - at).norm() < o.clearance_m) return std::nullopt;
        }
        const Vec2* points = g.geometry_begin(static_cast<EdgeId>(hit_edge));
        for (std::size_t k = 0; k + 1 < g.geometry_size(static_cast<EdgeId>(hit_edge)); ++k) {
            if (distance_to_segment(at, points[k], points[k + 1]) > 1e-6) continue;
            const Vec2 along = (points[k + 1] - points[k]).normalized();
            if (std::abs(along.dot(heading)) > std::cos(M_PI / 6)) return std::nullopt;
            break;
        }
        x.split_edge = static_cast<long>(hit_edge);
        x.where = at;
    }
    // The new street crosses nothing on its way.
    bool blocked = false;
    index.segments_near(p, target, [&](std::size_t e, std::size_t k) {
        if (blocked) return;
        const auto [a, b] = g.edges[e];
        if (a == s || b == s || static_cast<long>(e) == x.split_edge || a == x.vertex || b == x.vertex) return;
        const Vec2* points = g.geometry_begin(static_cast<EdgeId>(e));
        if (segment_meeting(p, target, points[k], points[k + 1])) blocked = true;
    });
    if (blocked) return std::nullopt;
    return x;
}

} // namespace

HierarchyReport continue_hierarchy(GeometricGraph& g, EdgeId first_new_edge, const HierarchyOptions& o) {
    if (first_new_edge < 0 || static_cast<std::size_t>(first_new_edge) > g.edge_count()) {
        throw UsageError("continue_hierarchy: the first grown street " + std::to_string(first_new_edge) +
                         " is not an edge of the graph (" + std::to_string(g.edge_count()) + " edges)");
    }
    if (!(o.max_detour >= 1.0)) throw UsageError("continue_hierarchy: the largest detour must be at least 1");
    HierarchyReport report;
    const auto first = static_cast<std::size_t>(first_new_edge);
    if (first == g.edge_count()) return report;
    // Raised streets are counted at the end against these: a street on two routes, or split
    // by a connector after it was raised, is one raised street.
    const std::vector<HighwayClass> classes_before(g.edge_highway.begin(), g.edge_highway.end());
    auto finished = [&] {
        for (std::size_t e = first; e < classes_before.size(); ++e) report.raised_streets += g.edge_highway[e] != classes_before[e];
        return report;
    };

    // The grown streets as their own small graph.
    std::unordered_map<VertexId, int> local_of;
    std::vector<VertexId> global_of;
    auto local = [&](VertexId v) {
        const auto [it, added] = local_of.emplace(v, static_cast<int>(global_of.size()));
        if (added) global_of.push_back(v);
        return it->second;
    };
    std::vector<std::vector<std::pair<int, std::size_t>>> around; // (neighbour, edge)
    std::map<int, std::size_t> class_counts;                      // rank -> grown streets
    for (std::size_t e = first; e < g.edge_count(); ++e) {
        const int a = local(g.edges[e][0]);
        const int b = local(g.edges[e][1]);
        around.resize(global_of.size());
        around[static_cast<std::size_t>(a)].push_back({b, e});
        around[static_cast<std::size_t>(b)].push_back({a, e});
        ++class_counts[highway_rank(g.edge_highway[e])];
    }
    int usual_rank = 0;
    std::size_t most = 0;
    for (const auto& [rank, count] : class_counts) {
        if (count > most) {
            most = count;
            usual_rank = rank;
        }
    }

    // The main roads that reach the grown streets: their most important street there.
    std::vector<MainRoad> roads;
    std::unordered_map<VertexId, std::size_t> road_at;
    // Also, with a region, a main road that ends (a dead end of the streets before the grown
    // ones) in it or within border_m of it, though no grown street reaches it: it can only be
    // joined straight.
    std::vector<int> base_degree;
    if (!o.region.empty()) {
        base_degree.assign(g.vertex_count(), 0);
        for (std::size_t e = 0; e < first; ++e) {
            ++base_degree[static_cast<std::size_t>(g.edges[e][0])];
            ++base_degree[static_cast<std::size_t>(g.edges[e][1])];
        }
    }
    double border = o.border_m;
    if (!o.region.empty() && border < 0) {
        // As growth measures its border: 5 % of the largest distance of a corner from their mean.
        Vec2 centre = Vec2::Zero();
        for (const Vec2& c : o.region) centre += c;
        centre /= static_cast<double>(o.region.size());
        double size = 0.0;
        for (const Vec2& c : o.region) size = std::max(size, (c - centre).norm());
        border = 0.05 * size;
    }
    auto ends_in_region = [&](VertexId v) {
        if (base_degree.empty() || base_degree[static_cast<std::size_t>(v)] != 1) return false;
        const Vec2& p = g.positions[static_cast<std::size_t>(v)];
        return inside(o.region, p) || distance_to_ring(o.region, p) <= border;
    };
    for (std::size_t e = 0; e < first; ++e) {
        const HighwayClass c = g.edge_highway[e];
        if (!main_road_class(c) || highway_rank(c) >= usual_rank) continue;
        for (VertexId v : g.edges[e]) {
            const auto it = local_of.find(v);
            if (it == local_of.end() && !ends_in_region(v)) continue;
            const auto [at, added] = road_at.emplace(v, roads.size());
            if (added) {
                roads.push_back({v, c, it == local_of.end() ? -1 : it->second, {}});
            } else if (highway_rank(c) < highway_rank(roads[at->second].highway)) {
                roads[at->second].highway = c;
            }
            const VertexId other = g.edges[e][0] == v ? g.edges[e][1] : g.edges[e][0];
            const Vec2 heading = g.positions[static_cast<std::size_t>(v)] - g.positions[static_cast<std::size_t>(other)];
            if (heading.norm() > 0) roads[at->second].headings.push_back(heading.normalized());
        }
    }
    report.main_roads = roads.size();
    std::vector<char> used(roads.size(), 0);
    if (roads.empty()) return report;
    std::optional<StreetIndex> index; // built when first needed
    // Main roads that end at the region and were joined to nothing: straight on to the first
    // grown street ahead, a T-junction there (Parish and Mueller's local constraint), so that
    // every main road the region cut goes on into what grew there.
    auto extend_ends = [&] {
        if (o.max_connector_m <= 0) return;
        for (std::size_t s = 0; s < roads.size(); ++s) {
            if (used[s] || roads[s].local >= 0 || roads[s].headings.size() != 1) continue;
            if (!index) index.emplace(g, first);
            // Straight on first; where that meets the city, a street along it or nothing clear,
            // turned by up to 15 degrees either way, as a road bends (the nearest turn first).
            std::optional<Extension> plan;
            for (const double turn : {0.0, 5.0, -5.0, 10.0, -10.0, 15.0, -15.0}) {
                plan = plan_extension(g, *index, first, roads[s].vertex, rotated(roads[s].headings.front(), turn * M_PI / 180.0), o);
                if (plan) break;
            }
            if (!plan) continue;
            EdgeAttributes attributes;
            attributes.highway = roads[s].highway;
            const VertexId to = plan->split_edge >= 0 ? g.split_edge(static_cast<EdgeId>(plan->split_edge), plan->where) : plan->vertex;
            g.add_edge(roads[s].vertex, to, attributes);
            used[s] = 1;
            ++report.extensions;
            index->build();
        }
    };
    if (roads.size() < 2) {
        extend_ends();
        return finished();
    }
    std::stable_sort(roads.begin(), roads.end(), [](const MainRoad& x, const MainRoad& y) {
        if (highway_rank(x.highway) != highway_rank(y.highway)) return highway_rank(x.highway) < highway_rank(y.highway);
        return x.vertex < y.vertex;
    });
    std::vector<int> road_of_local(global_of.size(), -1);
    for (std::size_t r = 0; r < roads.size(); ++r) {
        if (roads[r].local >= 0) road_of_local[static_cast<std::size_t>(roads[r].local)] = static_cast<int>(r);
    }
    // Two main roads already joined by one street (the same road passing the region).
    std::vector<std::pair<VertexId, VertexId>> joined;
    for (std::size_t e = 0; e < first; ++e) {
        const auto [a, b] = g.edges[e];
        if (road_at.count(a) && road_at.count(b)) joined.push_back({std::min(a, b), std::max(a, b)});
    }
    std::sort(joined.begin(), joined.end());
    auto joined_already = [&](VertexId u, VertexId v) {
        return std::binary_search(joined.begin(), joined.end(), std::pair<VertexId, VertexId>{std::min(u, v), std::max(u, v)});
    };

    const std::size_t n = global_of.size();
    std::vector<double> distance(n);
    std::vector<std::size_t> via(n);
    for (std::size_t s = 0; s < roads.size(); ++s) {
        if (used[s] || roads[s].local < 0) continue;
        // Shortest routes through the grown streets from this main road.
        std::fill(distance.begin(), distance.end(), std::numeric_limits<double>::infinity());
        using Item = std::pair<double, int>;
        std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
        distance[static_cast<std::size_t>(roads[s].local)] = 0.0;
        queue.push({0.0, roads[s].local});
        while (!queue.empty()) {
            const auto [d, x] = queue.top();
            queue.pop();
            if (d > distance[static_cast<std::size_t>(x)]) continue;
            // A route ends at a main road: it does not run on through it.
            if (x != roads[s].local && road_of_local[static_cast<std::size_t>(x)] >= 0) continue;
            for (const auto& [y, e] : around[static_cast<std::size_t>(x)]) {
                const double nd = d + g.edge_length(static_cast<EdgeId>(e));
                if (nd < distance[static_cast<std::size_t>(y)]) {
                    distance[static_cast<std::size_t>(y)] = nd;
                    via[static_cast<std::size_t>(y)] = e;
                    queue.push({nd, y});
                }
            }
        }
        // The farthest main road reached directly enough: a route across the grown streets
        // rather than round a corner of them.
        int best = -1;
        double best_straight = 0.0;
        const Vec2 from = g.positions[static_cast<std::size_t>(roads[s].vertex)];
        for (std::size_t t = 0; t < roads.size(); ++t) {
            if (t == s || used[t] || roads[t].local < 0) continue;
            const double d = distance[static_cast<std::size_t>(roads[t].local)];
            if (!std::isfinite(d)) continue;
            const double straight = (g.positions[static_cast<std::size_t>(roads[t].vertex)] - from).norm();
            if (!(straight > 0.0) || d > o.max_detour * straight) continue;
            if (joined_already(roads[s].vertex, roads[t].vertex)) continue;
            if (straight > best_straight) {
                best = static_cast<int>(t);
                best_straight = straight;
            }
        }
        if (best < 0) continue;
        used[s] = used[static_cast<std::size_t>(best)] = 1;
        ++report.routes;
        const HighwayClass c = highway_rank(roads[s].highway) >= highway_rank(roads[static_cast<std::size_t>(best)].highway)
                                   ? roads[s].highway
                                   : roads[static_cast<std::size_t>(best)].highway;
        for (int x = roads[static_cast<std::size_t>(best)].local; x != roads[s].local;) {
            const std::size_t e = via[static_cast<std::size_t>(x)];
            if (highway_rank(c) < highway_rank(g.edge_highway[e])) {
                g.edge_highway[e] = c;
                g.edge_lanes[e] = 0;
                g.edge_width_m[e] = std::numeric_limits<double>::quiet_NaN();
            }
            const int a = local_of.at(g.edges[e][0]);
            x = a == x ? local_of.at(g.edges[e][1]) : a;
        }
    }

    // Main roads that face each other across the grown streets with no route between them
    // are joined by a straight main road, which crosses the grown streets at new
    // intersections.
    if (o.max_connector_m <= 0) return finished();
    const double facing = std::cos(o.max_connector_turn_deg * M_PI / 180.0);
    auto faces = [&](const MainRoad& from, const Vec2& towards) {
        for (const Vec2& h : from.headings) {
            if (h.dot(towards) >= facing) return true;
        }
        return false;
    };
    for (std::size_t s = 0; s < roads.size(); ++s) {
        if (used[s]) continue;
        const Vec2 from = g.positions[static_cast<std::size_t>(roads[s].vertex)];
        // The nearest main road that it faces and that faces it.
        std::vector<std::pair<double, std::size_t>> candidates;
        for (std::size_t t = 0; t < roads.size(); ++t) {
            if (t == s || used[t]) continue;
            const Vec2 d = g.positions[static_cast<std::size_t>(roads[t].vertex)] - from;
            const double length = d.norm();
            if (!(length > 0.0) || length > o.max_connector_m) continue;
            if (!faces(roads[s], d / length) || !faces(roads[t], -d / length)) continue;
            if (joined_already(roads[s].vertex, roads[t].vertex)) continue;
            candidates.push_back({length, t});
        }
        std::sort(candidates.begin(), candidates.end());
        for (const auto& [length, t] : candidates) {
            if (!o.region.empty()) {
                const Vec2 middle = 0.5 * (from + g.positions[static_cast<std::size_t>(roads[t].vertex)]);
                if (!inside(o.region, middle)) continue;
            }
            if (!index) index.emplace(g, first);
            const std::optional<Connector> plan = plan_connector(g, *index, first, roads[s].vertex, roads[t].vertex, o.clearance_m);
            if (!plan) continue;
            const HighwayClass c = highway_rank(roads[s].highway) >= highway_rank(roads[t].highway) ? roads[s].highway
                                                                                                : roads[t].highway;
            std::vector<std::pair<double, VertexId>> chain = plan->through;
            for (const auto& [at, e, where] : plan->splits) {
                chain.push_back({at, g.split_edge(static_cast<EdgeId>(e), where)});
                ++report.intersections;
            }
            chain.push_back({0.0, roads[s].vertex});
            chain.push_back({1.0, roads[t].vertex});
            std::sort(chain.begin(), chain.end());
            // Pieces that are streets already (the connector runs along a grown street) are
            // raised instead of doubled.
            std::map<std::pair<VertexId, VertexId>, std::size_t> existing;
            std::vector<char> on_chain(g.vertex_count(), 0);
            for (const auto& [at, v] : chain) on_chain[static_cast<std::size_t>(v)] = 1;
            for (std::size_t e = 0; e < g.edge_count(); ++e) {
                const auto [a, b] = g.edges[e];
                if (on_chain[static_cast<std::size_t>(a)] && on_chain[static_cast<std::size_t>(b)]) {
                    existing[{std::min(a, b), std::max(a, b)}] = e;
                }
            }
            EdgeAttributes attributes;
            attributes.highway = c;
            for (std::size_t i = 0; i + 1 < chain.size(); ++i) {
                const VertexId a = chain[i].second, b = chain[i + 1].second;
                const auto it = existing.find({std::min(a, b), std::max(a, b)});
                if (it == existing.end()) {
                    g.add_edge(a, b, attributes);
                    ++report.connector_streets;
                } else if (it->second >= first && highway_rank(c) < highway_rank(g.edge_highway[it->second])) {
                    g.edge_highway[it->second] = c;
                    g.edge_lanes[it->second] = 0;
                    g.edge_width_m[it->second] = std::numeric_limits<double>::quiet_NaN();
                }
            }
            used[s] = used[t] = 1;
            ++report.connectors;
            index->build();
            break;
        }
    }
    extend_ends();
    return finished();
}

} // namespace ggg
