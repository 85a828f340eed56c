// Roundabouts in a grown district, as often as its city has them (see street_cleanup.hpp).
#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <limits>
#include <optional>
#include <span>
#include <utility>

#include "ggg/graph/planar_faces.hpp"
#include "ggg/graph/plane_geometry.hpp"
#include "ggg/graph/road_class.hpp"
#include "ggg/graph/spatial_index.hpp"
#include "ggg/measures/network_comparison.hpp"
#include "street_cleanup.hpp"

namespace ggg::growth_detail {

using namespace spatial; // bg, bgi, Point, Box, point, RTree, VertexEntry, EdgeEntry

namespace {

// A roundabout is a small block that is nearly a circle (its area at least 0.8 of the disc with
// its perimeter), ringed by one-way streets that all run one way round it, with three or more
// streets meeting its ring: the loop of a link is not round, a small round block with two-way
// streets round it is a square or a park, and one few streets reach is a cul-de-sac's loop.
constexpr double min_roundness = 0.8;
constexpr double min_radius_m = 5.0, max_radius_m = 60.0;
constexpr std::size_t min_arms = 3;
// A city's share of roundabouts is measured among at least this many of its junctions.
constexpr std::size_t min_junctions_to_say = 300;

// Roundabouts are mostly where main roads meet: the share is counted apart for the junctions
// with a main road (motorway to tertiary, and their links) and for the others.
bool main_road(HighwayClass c) { return highway_rank(c) <= highway_rank(HighwayClass::tertiary_link); }

// The point where the polyline, from its first point (the centre), first leaves the circle of
// radius r around it: (index of the piece, point). None when it never does.
std::optional<std::pair<std::size_t, Vec2>> leaving_circle(const std::vector<Vec2>& line, double r) {
    const Vec2& c = line.front();
    for (std::size_t i = 0; i + 1 < line.size(); ++i) {
        const Vec2 a = line[i] - c, d = line[i + 1] - line[i];
        if ((line[i + 1] - c).norm() < r) continue;
        // |a + t d| = r, the larger root in [0, 1] (a is inside or on the circle).
        const double qa = d.squaredNorm(), qb = 2 * a.dot(d), qc = a.squaredNorm() - r * r;
        const double disc = qb * qb - 4 * qa * qc;
        if (qa <= 0 || disc < 0) return std::nullopt;
        const double t = std::clamp((-qb + std::sqrt(disc)) / (2 * qa), 0.0, 1.0);
        return std::pair{i, line[i] + t * d};
    }
    return std::nullopt;
}

} // namespace

CityRoundabouts roundabouts_of(const GeometricGraph& city, const std::vector<Vec2>& region) {
    CityRoundabouts out;
    if (city.edge_count() == 0) return out;
    const Adjacency adjacency(city);
    auto degree = [&](std::size_t v) { return adjacency.degree(static_cast<VertexId>(v)); };
    std::vector<char> main_at(city.vertex_count(), 0); // a main road meets there
    for (std::size_t e = 0; e < city.edge_count(); ++e) {
        if (!main_road(city.edge_highway[e])) continue;
        for (const VertexId v : city.edges[e]) main_at[static_cast<std::size_t>(v)] = 1;
    }
    const PlanarFaces faces = planar_faces(city);
    std::vector<char> on_ring(city.vertex_count(), 0);
    std::vector<Vec2> centres;    // of the roundabouts
    std::vector<char> on_main;    // per roundabout: a main road meets it
    std::vector<double> radii;    // per roundabout
    std::size_t anticlockwise = 0;
    for (std::size_t f = 0; f < faces.face_count(); ++f) {
        const double area = faces.face_area[f];
        if (!(area > 0) || faces.face_dangling[f] != 0) continue;
        double perimeter = 0.0;
        int direction = 0;
        bool circulates = true;
        std::vector<VertexId> ring;
        for (auto k = faces.face_edge_offsets[f]; k < faces.face_edge_offsets[f + 1]; ++k) {
            const auto e = static_cast<std::size_t>(faces.face_edges[static_cast<std::size_t>(k)]);
            const bool reversed = faces.face_edge_reversed[static_cast<std::size_t>(k)] != 0;
            perimeter += city.edge_length(static_cast<EdgeId>(e));
            ring.push_back(city.edges[e][reversed ? 1 : 0]);
            // One way, the way the walk round the block goes (or all against it).
            const int along = e < city.edge_oneway.size() ? city.edge_oneway[e] * (reversed ? -1 : 1) : 0;
            if (direction == 0) direction = along;
            circulates = circulates && along != 0 && along == direction;
        }
        const double radius = perimeter / (2 * M_PI);
        if (!circulates || radius < min_radius_m || radius > max_radius_m) continue;
        if (4 * M_PI * area < min_roundness * perimeter * perimeter) continue;
        std::size_t arms = 0;
        for (const VertexId v : ring) arms += degree(static_cast<std::size_t>(v)) >= 3;
        if (arms < min_arms) continue;
        Vec2 centre = Vec2::Zero();
        bool main = false;
        for (const VertexId v : ring) {
            on_ring[static_cast<std::size_t>(v)] = 1;
            centre += city.positions[static_cast<std::size_t>(v)];
            main = main || main_at[static_cast<std::size_t>(v)];
        }
        centres.push_back(centre / static_cast<double>(ring.size()));
        on_main.push_back(main);
        radii.push_back(radius);
        anticlockwise += direction > 0; // a bounded face is walked anticlockwise
    }
    out.circulation = 2 * anticlockwise >= radii.size() ? 1 : -1;
    // A district does not chain roundabouts closer than its city does (Rome's infill grew four
    // in 200 m, where the city keeps them hundreds of metres apart).
    if (centres.size() >= 2) {
        std::vector<double> nearest;
        for (std::size_t k = 0; k < centres.size(); ++k) {
            double d = std::numeric_limits<double>::infinity();
            for (std::size_t j = 0; j < centres.size(); ++j) {
                if (j != k) d = std::min(d, (centres[j] - centres[k]).norm());
            }
            nearest.push_back(d);
        }
        const auto tenth = nearest.begin() + static_cast<long>(nearest.size() / 10);
        std::nth_element(nearest.begin(), tenth, nearest.end());
        out.spacing_m = *tenth;
    }
    out.centres = centres;
    // The shares among the junctions nearest the region (the parts of a city differ: a ring
    // road of roundabouts around an old town of crossings), further out until there are enough
    // of them to say. Each roundabout stands for one junction.
    auto distance = [&](const Vec2& p) { return inside(region, p) ? 0.0 : distance_to_ring(region, p); };
    std::vector<double> junction_distance, roundabout_distance;
    std::vector<char> junction_main;
    for (std::size_t v = 0; v < city.vertex_count(); ++v) {
        if (degree(v) < 3 || on_ring[v]) continue;
        junction_distance.push_back(distance(city.positions[v]));
        junction_main.push_back(main_at[v]);
    }
    for (const Vec2& c : centres) roundabout_distance.push_back(distance(c));
    double size = 0.0;
    for (const Vec2& p : region) size = std::max(size, (p - region.front()).norm());
    for (double within = 0.25 * size;; within *= 2) {
        const bool all = !(within <= 2.0 * size);
        const auto near = [&](double d) { return all || d <= within; };
        out.radii_m.clear();
        std::array<std::size_t, 2> roundabouts{0, 0}, junctions{0, 0}; // [other, main]
        for (std::size_t k = 0; k < centres.size(); ++k) {
            if (!near(roundabout_distance[k])) continue;
            out.radii_m.push_back(radii[k]);
            ++roundabouts[on_main[k] ? 1 : 0];
            ++junctions[on_main[k] ? 1 : 0];
        }
        for (std::size_t j = 0; j < junction_distance.size(); ++j) junctions[junction_main[j] ? 1 : 0] += near(junction_distance[j]);
        if (junctions[0] + junctions[1] >= min_junctions_to_say || all) {
            auto share = [&](std::size_t i) { return junctions[i] ? static_cast<double>(roundabouts[i]) / static_cast<double>(junctions[i]) : 0.0; };
            out.share = share(0);
            out.main_share = share(1);
            break;
        }
    }
    std::sort(out.radii_m.begin(), out.radii_m.end());
    return out;
}

std::size_t make_roundabouts(GeometricGraph& g, std::size_t base_vertices, std::size_t base_edges, const std::vector<Vec2>& region,
                             const CityRoundabouts& city, std::mt19937_64& rng) {
    if (city.radii_m.empty() || g.vertex_count() <= base_vertices) return 0;
    const std::size_t n = g.vertex_count();
    const Adjacency adjacency(g); // of the graph as it was: roundabouts only add vertices after it
    auto at = [&](std::size_t v) {
        const auto from = static_cast<std::size_t>(adjacency.offsets[v]);
        return std::span<const EdgeId>(adjacency.edge_ids.data() + from, adjacency.degree(static_cast<VertexId>(v)));
    };
    // Grown junctions of grown streets only: the base is never changed.
    std::vector<VertexId> junctions;
    double expected = 0.0;
    for (std::size_t v = base_vertices; v < n; ++v) {
        const auto es = at(v);
        if (es.size() < min_arms || es.size() > 5) continue;
        if (std::any_of(es.begin(), es.end(), [&](EdgeId e) { return static_cast<std::size_t>(e) < base_edges; })) continue;
        junctions.push_back(static_cast<VertexId>(v));
        const bool main = std::any_of(es.begin(), es.end(), [&](EdgeId e) { return main_road(g.edge_highway[static_cast<std::size_t>(e)]); });
        expected += main ? city.main_share : city.share;
    }
    // (The fraction left over, by chance: a district of 20 junctions in a city where one in 40
    // is a roundabout has one half the time.)
    auto wanted = static_cast<std::size_t>(std::floor(expected));
    if (std::uniform_real_distribution<double>(0.0, 1.0)(rng) < expected - static_cast<double>(wanted)) ++wanted;
    if (wanted == 0) return 0;
    // Junctions whose streets meet at odd angles first (a roundabout is where a city gives up
    // on a square crossing): by how many of the angles between neighbouring streets are within
    // 15 degrees of square, at random among equals.
    std::shuffle(junctions.begin(), junctions.end(), rng);
    std::vector<int> order(n, 0);
    for (const VertexId v : junctions) {
        std::vector<double> bearings;
        for (const EdgeId e : at(static_cast<std::size_t>(v))) {
            const Vec2 d = leaving_direction(g, e, v); // as `ggg compare` measures the angles
            bearings.push_back(std::atan2(d.y(), d.x()));
        }
        std::sort(bearings.begin(), bearings.end());
        int square = 0;
        for (std::size_t i = 0; i < bearings.size(); ++i) {
            const double angle = (i + 1 < bearings.size() ? bearings[i + 1] : bearings[0] + 2 * M_PI) - bearings[i];
            square += std::abs(angle - M_PI / 2) <= M_PI / 12;
        }
        order[static_cast<std::size_t>(v)] = square;
    }
    std::stable_sort(junctions.begin(), junctions.end(), [&](VertexId a, VertexId b) { return order[static_cast<std::size_t>(a)] < order[static_cast<std::size_t>(b)]; });

    RTree<EdgeEntry> pieces;
    std::vector<std::pair<EdgeId, std::size_t>> piece_of;
    for (std::size_t e = 0; e < g.edge_count(); ++e) {
        const Vec2* p = g.geometry_begin(static_cast<EdgeId>(e));
        for (std::size_t i = 0; i + 1 < g.geometry_size(static_cast<EdgeId>(e)); ++i) {
            pieces.insert({around(p[i], p[i + 1]), static_cast<EdgeId>(piece_of.size())});
            piece_of.emplace_back(static_cast<EdgeId>(e), i);
        }
    }
    std::vector<char> replaced_edge(g.edge_count(), 0), centre(n, 0);
    std::vector<Street> added; // the arms cut back to the ring, and the ring's arcs
    std::vector<std::pair<Vec2, double>> made; // centre and radius of each roundabout made
    std::uniform_int_distribution<std::size_t> pick_radius(0, city.radii_m.size() - 1);
    for (const VertexId v : junctions) {
        if (made.size() == wanted) break;
        const Vec2 c = g.positions[static_cast<std::size_t>(v)];
        const double r = city.radii_m[pick_radius(rng)];
        // Room: inside the region, clear of the other roundabouts, and no street but its own
        // arms within the ring and a margin around it.
        const double margin = 0.5 * r;
        if (!inside(region, c) || distance_to_ring(region, c) < r + margin) continue;
        if (std::any_of(made.begin(), made.end(), [&](const auto& m) { return (m.first - c).norm() < std::max(m.second + r + 2 * margin, city.spacing_m); })) continue;
        if (std::any_of(city.centres.begin(), city.centres.end(), [&](const Vec2& m) { return (m - c).norm() < city.spacing_m; })) continue;
        const auto es = at(static_cast<std::size_t>(v));
        if (std::any_of(es.begin(), es.end(), [&](EdgeId e) { return replaced_edge[static_cast<std::size_t>(e)] != 0; })) continue;
        bool clear = true;
        for (auto it = pieces.qbegin(bgi::intersects(around(c, r + margin))); it != pieces.qend() && clear; ++it) {
            const auto [e, i] = piece_of[static_cast<std::size_t>(it->second)];
            if (std::find(es.begin(), es.end(), e) != es.end()) continue;
            const Vec2* p = g.geometry_begin(e);
            clear = distance_to_segment(c, p[i], p[i + 1]) >= r + margin;
        }
        if (!clear) continue;
        // Each arm cut where it leaves the ring; it must stay out of the ring after that and
        // be long enough beyond it to remain a street.
        struct Arm {
            EdgeId edge;
            VertexId far;
            std::vector<Vec2> rest; // from the ring outwards
            double angle;
            bool forward; // the edge ran from the centre
        };
        std::vector<Arm> arms;
        for (const EdgeId e : es) {
            const Vec2* p = g.geometry_begin(e);
            std::vector<Vec2> line(p, p + g.geometry_size(e));
            const bool forward = g.edges[static_cast<std::size_t>(e)][0] == v;
            if (!forward) std::reverse(line.begin(), line.end());
            const auto cut = leaving_circle(line, r);
            if (!cut) break;
            std::vector<Vec2> rest{cut->second};
            rest.insert(rest.end(), line.begin() + static_cast<long>(cut->first) + 1, line.end());
            double length = 0.0, nearest = std::numeric_limits<double>::infinity();
            for (std::size_t i = 0; i + 1 < rest.size(); ++i) {
                length += (rest[i + 1] - rest[i]).norm();
                nearest = std::min(nearest, distance_to_segment(c, rest[i], rest[i + 1]));
            }
            if (length < r || nearest < 0.99 * r) break;
            const Vec2 d = cut->second - c;
            arms.push_back({e, g.edges[static_cast<std::size_t>(e)][forward ? 1 : 0], std::move(rest), std::atan2(d.y(), d.x()), forward});
        }
        if (arms.size() != es.size()) continue;
        std::sort(arms.begin(), arms.end(), [](const Arm& a, const Arm& b) { return a.angle < b.angle; });
        // Arms at least 30 degrees apart along the ring, so that its arcs are streets.
        bool apart = true;
        for (std::size_t k = 0; k < arms.size(); ++k) {
            const double next = k + 1 < arms.size() ? arms[k + 1].angle : arms[0].angle + 2 * M_PI;
            apart = apart && next - arms[k].angle >= M_PI / 6;
        }
        if (!apart) continue;
        // The ring takes the class of its most important arm, as a city's roundabouts do, and
        // is driven round as most of the city's are (its arcs are drawn anticlockwise).
        EdgeAttributes ring;
        ring.oneway = static_cast<std::int8_t>(city.circulation);
        ring.highway = g.edge_highway[static_cast<std::size_t>(arms[0].edge)];
        for (const Arm& a : arms) {
            const HighwayClass h = g.edge_highway[static_cast<std::size_t>(a.edge)];
            if (highway_rank(h) < highway_rank(ring.highway)) ring.highway = h;
        }
        // The ring's arcs: each a polyline of pieces of 15 degrees at most between two arms.
        std::vector<std::vector<Vec2>> arcs;
        for (std::size_t k = 0; k < arms.size(); ++k) {
            const std::size_t next = (k + 1) % arms.size();
            const double from = arms[k].angle;
            const double to = next ? arms[next].angle : arms[0].angle + 2 * M_PI;
            const auto steps = static_cast<int>(std::ceil((to - from) / (M_PI / 12)));
            std::vector<Vec2> arc;
            for (int s = 0; s <= steps; ++s) {
                const double a = from + (to - from) * s / steps;
                arc.push_back(c + r * Vec2(std::cos(a), std::sin(a)));
            }
            arc.front() = arms[k].rest.front();
            arc.back() = arms[next].rest.front();
            arcs.push_back(std::move(arc));
        }
        // An arm that leaves the ring at a graze may cut across the chord of an arc next to it
        // (the arms keep out of the circle, the arcs' chords run inside it): no roundabout
        // there (Malta's infill test grew one).
        auto cuts_an_arc = [&](const Arm& arm) {
            for (const std::vector<Vec2>& arc : arcs) {
                for (std::size_t i = 0; i + 1 < arm.rest.size(); ++i) {
                    for (std::size_t k = 0; k + 1 < arc.size(); ++k) {
                        const auto m = segment_meeting(arm.rest[i], arm.rest[i + 1], arc[k], arc[k + 1]);
                        if (m && m->first > 1e-9 && m->first < 1 - 1e-9 && m->second > 1e-9 && m->second < 1 - 1e-9) return true;
                    }
                }
            }
            return false;
        };
        if (std::any_of(arms.begin(), arms.end(), cuts_an_arc)) continue;
        std::vector<VertexId> on_ring;
        for (const Arm& a : arms) {
            const VertexId w = g.add_vertex(a.rest.front());
            on_ring.push_back(w);
            EdgeAttributes attributes = g.edge_attributes(a.edge);
            if (!a.forward) attributes.oneway = static_cast<std::int8_t>(-attributes.oneway); // it now runs from the ring
            added.push_back({w, a.far, std::move(attributes), a.rest});
            replaced_edge[static_cast<std::size_t>(a.edge)] = 1;
        }
        for (std::size_t k = 0; k < arms.size(); ++k) added.push_back({on_ring[k], on_ring[(k + 1) % arms.size()], ring, std::move(arcs[k])});
        centre[static_cast<std::size_t>(v)] = 1;
        made.emplace_back(c, r);
    }
    if (made.empty()) return 0;
    // The streets kept first, in their order (the base's keep their ids), then the new ones.
    std::vector<Street> streets;
    for (std::size_t e = 0; e < g.edge_count(); ++e) {
        if (replaced_edge[e]) continue;
        streets.push_back(street_of(g, static_cast<EdgeId>(e)));
    }
    streets.insert(streets.end(), std::make_move_iterator(added.begin()), std::make_move_iterator(added.end()));
    std::vector<char> drop(g.vertex_count(), 0);
    for (std::size_t v = 0; v < n; ++v) drop[v] = centre[v];
    g = rebuilt(g, drop, streets);
    return made.size();
}

} // namespace ggg::growth_detail
