// Dead-end streets in a grown district, where its city has them (see street_cleanup.hpp).
//
// Tracing and rules make streets that meet other streets, so a grown district ends in the open
// less often than most cities do: Porto's hole has 13 % of its vertices at dead ends, its grown
// streets had 3 %, and its blocks, too large for its loops alone, held none of the courts and
// closes that fill the real ones. The share alone would be the wrong guide: a grid whose parks
// and edges hold dead ends has none in its small blocks, so the dead ends come block by block,
// as many as the city's blocks of about that area hold.
#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <utility>

#include "ggg/graph/planar_faces.hpp"
#include "ggg/graph/plane_geometry.hpp"
#include "ggg/graph/spatial_index.hpp"
#include "ggg/measures/network_comparison.hpp"
#include "street_cleanup.hpp"

namespace ggg::growth_detail {

using namespace spatial; // bg, bgi, Point, Box, point, RTree, VertexEntry, EdgeEntry

namespace {

// The city's blocks are read this far around the region (a multiple of its size), so that a
// district continues its own part of a large metro.
constexpr double city_reach = 1.5;
// A block's dead ends are predicted from at least this many of the city's blocks of about its
// area (within a factor of 2, else 4); with fewer, it gets none.
constexpr std::size_t min_blocks_to_say = 12;
// A new dead-end street keeps this share of the city's median one from other streets (and from
// other dead-end streets along the same street), and at least this many metres.
constexpr double clearance_share = 0.25;
constexpr double min_clearance_m = 8.0;

// The vertex a half-edge of a face's walk arrives at.
VertexId head(const GeometricGraph& g, const PlanarFaces& faces, std::size_t i) {
    const auto& [a, b] = g.edges[static_cast<std::size_t>(faces.face_edges[i])];
    return faces.face_edge_reversed[i] ? a : b;
}

// The centre of a face's outer ring (its first).
Vec2 face_centre(const PlanarFaces& faces, std::size_t ring) {
    Vec2 sum = Vec2::Zero();
    const auto begin = static_cast<std::size_t>(faces.ring_offsets[ring]), end = static_cast<std::size_t>(faces.ring_offsets[ring + 1]);
    for (std::size_t k = begin; k < end; ++k) sum += faces.points[k];
    return end > begin ? Vec2(sum / static_cast<double>(end - begin)) : sum;
}

// The first ring of each face (rings come face by face).
std::vector<std::size_t> first_rings(const PlanarFaces& faces) {
    std::vector<std::size_t> first(faces.face_count(), faces.ring_count());
    for (std::size_t r = faces.ring_count(); r-- > 0;) first[static_cast<std::size_t>(faces.ring_face[r])] = r;
    return first;
}

// The dead ends in face f: the vertices of one street that its walk arrives at.
std::size_t dead_ends_in(const GeometricGraph& g, const PlanarFaces& faces, const Adjacency& adjacency, std::size_t f) {
    std::size_t count = 0;
    for (auto i = faces.face_edge_offsets[f]; i < faces.face_edge_offsets[f + 1]; ++i) {
        count += adjacency.degree(head(g, faces, static_cast<std::size_t>(i))) == 1;
    }
    return count;
}

// How many dead ends the city's blocks of about `area` hold, on average; none where too few
// blocks are that large.
double dead_ends_for(const CityCulDeSacs& city, double area) {
    for (const double factor : {2.0, 4.0}) {
        const auto lo = std::lower_bound(city.blocks.begin(), city.blocks.end(), std::pair{area / factor, -1});
        const auto hi = std::lower_bound(city.blocks.begin(), city.blocks.end(), std::pair{area * factor, -1});
        if (static_cast<std::size_t>(hi - lo) < min_blocks_to_say) continue;
        double sum = 0.0;
        for (auto it = lo; it != hi; ++it) sum += it->second;
        return sum / static_cast<double>(hi - lo);
    }
    return 0.0;
}

// A piece of a street's polyline, for the checks of a new street against those there.
struct Piece {
    Vec2 a, b;
};

} // namespace

CityCulDeSacs cul_de_sacs_of(const GeometricGraph& city, const std::vector<Vec2>& region) {
    CityCulDeSacs out;
    if (city.edge_count() == 0 || region.size() < 3) return out;
    const Eigen::AlignedBox2d box = bounds(region.begin(), region.end());
    const double size = box.sizes().maxCoeff();
    const Vec2 centre = box.center();
    const PlanarFaces faces = planar_faces(city);
    const Adjacency adjacency(city);
    const std::vector<std::size_t> first = first_rings(faces);
    std::map<HighwayClass, std::size_t> classes;
    std::size_t across = 0, at_crossings = 0;
    for (std::size_t f = 0; f < faces.face_count(); ++f) {
        if (first[f] >= faces.ring_count() || faces.face_area[f] <= 0.0) continue;
        if ((face_centre(faces, first[f]) - centre).norm() > city_reach * size) continue;
        // Not the blocks the region cut: their dead ends are the streets it severed.
        Eigen::AlignedBox2d face_box;
        for (auto k = faces.ring_offsets[first[f]]; k < faces.ring_offsets[first[f] + 1]; ++k) face_box.extend(faces.points[static_cast<std::size_t>(k)]);
        if (face_box.intersects(box)) continue;
        int dead_ends = 0;
        for (auto i = faces.face_edge_offsets[f]; i < faces.face_edge_offsets[f + 1]; ++i) {
            VertexId at = head(city, faces, static_cast<std::size_t>(i));
            if (adjacency.degree(at) != 1) continue;
            ++dead_ends;
            // The street back from the dead end to its first junction.
            auto from = static_cast<std::size_t>(adjacency.offsets[static_cast<std::size_t>(at)]);
            EdgeId along = adjacency.edge_ids[from];
            double length = 0.0;
            classes[city.edge_highway[static_cast<std::size_t>(along)]]++;
            for (int step = 0; step < 64; ++step) {
                length += city.edge_length(along);
                const auto [a, b] = city.edges[static_cast<std::size_t>(along)];
                at = a == at ? b : a;
                if (adjacency.degree(at) != 2) break;
                const auto o = static_cast<std::size_t>(adjacency.offsets[static_cast<std::size_t>(at)]);
                along = adjacency.edge_ids[o] == along ? adjacency.edge_ids[o + 1] : adjacency.edge_ids[o];
            }
            out.lengths_m.push_back(length);
            // Whether it goes on across its junction from a street there (a crossing).
            if (adjacency.degree(at) == 4) {
                ++at_crossings;
                const Vec2 leaving = leaving_direction(city, along, at).normalized();
                for (auto k = adjacency.offsets[static_cast<std::size_t>(at)]; k < adjacency.offsets[static_cast<std::size_t>(at) + 1]; ++k) {
                    const EdgeId other = adjacency.edge_ids[static_cast<std::size_t>(k)];
                    if (other != along && leaving.dot(leaving_direction(city, other, at).normalized()) <= -std::cos(20.0 * M_PI / 180.0)) {
                        ++across;
                        break;
                    }
                }
            }
        }
        out.blocks.emplace_back(faces.face_area[f], dead_ends);
    }
    std::sort(out.blocks.begin(), out.blocks.end());
    std::sort(out.lengths_m.begin(), out.lengths_m.end());
    if (!out.lengths_m.empty()) out.across_share = static_cast<double>(across) / static_cast<double>(out.lengths_m.size());
    if (!classes.empty()) {
        out.highway = std::max_element(classes.begin(), classes.end(), [](const auto& x, const auto& y) { return x.second < y.second; })->first;
    }
    return out;
}

std::size_t make_cul_de_sacs(GeometricGraph& g, std::size_t base_vertices, std::size_t base_edges, const std::vector<Vec2>& region,
                             const CityCulDeSacs& city, std::mt19937_64& rng) {
    if (city.lengths_m.size() < 4 || g.edge_count() <= base_edges) return 0;
    const double median = city.lengths_m[city.lengths_m.size() / 2];
    const double clearance = std::max(min_clearance_m, clearance_share * median);
    const double shortest = std::max(clearance, city.lengths_m[city.lengths_m.size() / 10]);

    const PlanarFaces faces = planar_faces(g);
    const Adjacency adjacency(g);
    const std::vector<std::size_t> first = first_rings(faces);
    // Every piece of every street, to keep new streets clear of them.
    std::vector<Piece> pieces;
    RTree<EdgeEntry> index;
    auto add_piece = [&](const Vec2& a, const Vec2& b) {
        index.insert({around(a, b), static_cast<EdgeId>(pieces.size())});
        pieces.push_back({a, b});
    };
    for (std::size_t e = 0; e < g.edge_count(); ++e) {
        const Vec2* p = g.geometry_begin(static_cast<EdgeId>(e));
        for (std::size_t k = 0; k + 1 < g.geometry_size(static_cast<EdgeId>(e)); ++k) add_piece(p[k], p[k + 1]);
    }
    // Clear of every street but those through its root, and its end clear of them all.
    auto clear_of_streets = [&](const Vec2& root, const Vec2& end) {
        for (auto it = index.qbegin(bgi::intersects(around(root, end, clearance))); it != index.qend(); ++it) {
            const Piece& q = pieces[static_cast<std::size_t>(it->second)];
            if (distance_to_segment(end, q.a, q.b) < clearance) return false;
            if (distance_to_segment(root, q.a, q.b) > 1e-6 && segments_meet(root, end, q.a, q.b)) return false;
        }
        return true;
    };

    // A dead-end street leaves at a right angle from `root`, `into` the block: as long as one of
    // the city's, or shorter down to `shortest`, as far as it keeps clear.
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    auto fit = [&](const Vec2& root, const Vec2& into) -> std::optional<Vec2> {
        const double drawn = city.lengths_m[std::min(city.lengths_m.size() - 1, static_cast<std::size_t>(unit(rng) * static_cast<double>(city.lengths_m.size())))];
        if (!inside(region, root)) return std::nullopt; // (a grown street may leave the region to join the base)
        for (double l = drawn; l >= shortest; l *= 0.75) {
            const Vec2 end = root + l * into;
            if (!inside(region, end) || !clear_of_streets(root, end)) continue;
            add_piece(root, end);
            return end;
        }
        return std::nullopt;
    };

    std::vector<std::vector<double>> at(g.edge_count());
    struct Spur {
        EdgeId edge = -1; // split at s along it, or
        double s = 0.0;
        VertexId root = -1; // from a bend already there
        Vec2 end;
    };
    std::vector<Spur> spurs;
    std::vector<char> used(g.vertex_count(), 0);
    std::vector<double> length(g.edge_count(), -1.0);
    for (std::size_t f = 0; f < faces.face_count(); ++f) {
        if (first[f] >= faces.ring_count() || faces.face_area[f] <= 0.0) continue;
        if (!inside(region, face_centre(faces, first[f]))) continue;
        const double missing = dead_ends_for(city, faces.face_area[f]) - static_cast<double>(dead_ends_in(g, faces, adjacency, f));
        if (missing <= 0.0) continue;
        auto wanted = static_cast<std::size_t>(missing);
        wanted += unit(rng) < missing - static_cast<double>(wanted);
        if (wanted == 0) continue;
        // The grown streets of its walk, each walked once (one walked both ways lies inside it).
        std::map<EdgeId, std::pair<int, bool>> walked; // times, reversed
        const auto begin = faces.face_edge_offsets[f], end = faces.face_edge_offsets[f + 1];
        for (auto i = begin; i < end; ++i) {
            auto& w = walked[faces.face_edges[static_cast<std::size_t>(i)]];
            ++w.first;
            w.second = faces.face_edge_reversed[static_cast<std::size_t>(i)] != 0;
        }
        auto grown_once = [&](EdgeId e) { return static_cast<std::size_t>(e) >= base_edges && walked[e].first == 1; };
        // Where the walk goes on nearly straight at a grown vertex between two grown streets,
        // the dead-end street leaves from that vertex, so that no street is cut shorter for it:
        // at a bend (two streets), at a right angle; at a T-junction whose third street leaves
        // on the other side (a T's bar, walked), straight on across from that street, which
        // makes the T a crossing, as often as the city's dead-end streets meet a crossing so.
        std::vector<std::pair<VertexId, Vec2>> bends, across;
        for (auto i = begin; i < end; ++i) {
            const auto here = static_cast<std::size_t>(i), next = static_cast<std::size_t>(i + 1 < end ? i + 1 : begin);
            const VertexId v = head(g, faces, here);
            const EdgeId e1 = faces.face_edges[here], e2 = faces.face_edges[next];
            const std::size_t degree = adjacency.degree(v);
            if (e1 == e2 || (degree != 2 && degree != 3) || static_cast<std::size_t>(v) < base_vertices || used[static_cast<std::size_t>(v)] ||
                !grown_once(e1) || !grown_once(e2)) {
                continue;
            }
            const Vec2 in = -leaving_direction(g, e1, v).normalized(), out = leaving_direction(g, e2, v).normalized();
            if (in.dot(out) < std::cos(30.0 * M_PI / 180.0)) continue;
            const Vec2 tangent = (in + out).normalized();
            const Vec2 left(-tangent.y(), tangent.x());
            if (degree == 2) {
                bends.emplace_back(v, left);
                continue;
            }
            const auto o = static_cast<std::size_t>(adjacency.offsets[static_cast<std::size_t>(v)]);
            for (std::size_t k = o; k < o + 3; ++k) {
                const EdgeId stem = adjacency.edge_ids[k];
                if (stem == e1 || stem == e2) continue;
                const Vec2 on = -leaving_direction(g, stem, v).normalized();
                if (on.dot(left) >= std::cos(20.0 * M_PI / 180.0)) across.emplace_back(v, on);
            }
        }
        std::shuffle(bends.begin(), bends.end(), rng);
        std::shuffle(across.begin(), across.end(), rng);
        std::size_t made = 0;
        auto from_vertex = [&](std::vector<std::pair<VertexId, Vec2>>& roots) {
            while (!roots.empty()) {
                const auto [v, into] = roots.back();
                roots.pop_back();
                if (used[static_cast<std::size_t>(v)]) continue;
                if (auto tip = fit(g.positions[static_cast<std::size_t>(v)], into)) {
                    used[static_cast<std::size_t>(v)] = 1;
                    spurs.push_back({-1, 0.0, v, *tip});
                    return true;
                }
            }
            return false;
        };
        while (made < wanted) {
            const bool cross_first = unit(rng) < city.across_share;
            if (!from_vertex(cross_first ? across : bends) && !from_vertex(cross_first ? bends : across)) break;
            ++made;
        }
        // Else from a point along one of its grown streets, split there.
        std::vector<std::pair<EdgeId, bool>> hosts;
        std::vector<double> cumulative;
        double total = 0.0;
        for (const auto& [e, w] : walked) {
            const auto ei = static_cast<std::size_t>(e);
            if (!grown_once(e)) continue;
            if (length[ei] < 0.0) length[ei] = simple_line(g.geometry_begin(e), g.geometry_size(e)) ? g.edge_length(e) : 0.0;
            if (length[ei] < 2.0 * clearance) continue;
            hosts.emplace_back(e, w.second);
            total += length[ei];
            cumulative.push_back(total);
        }
        for (std::size_t tries = 0; made < wanted && !hosts.empty() && tries < 12 * wanted; ++tries) {
            const auto pick = static_cast<std::size_t>(std::upper_bound(cumulative.begin(), cumulative.end(), unit(rng) * total) - cumulative.begin());
            const auto [e, reversed] = hosts[std::min(pick, hosts.size() - 1)];
            const auto ei = static_cast<std::size_t>(e);
            const double s = clearance + unit(rng) * (length[ei] - 2.0 * clearance);
            if (std::any_of(at[ei].begin(), at[ei].end(), [&](double q) { return std::abs(q - s) < clearance; })) continue;
            // The point at s along the street, and the way into the block (the face lies to
            // the left of its walk).
            const Vec2* p = g.geometry_begin(e);
            double walked_m = 0.0;
            Vec2 x = p[0], tangent = Vec2::UnitX();
            for (std::size_t k = 0; k + 1 < g.geometry_size(e); ++k) {
                const double step = (p[k + 1] - p[k]).norm();
                if (walked_m + step >= s && step > 0.0) {
                    x = p[k] + (s - walked_m) / step * (p[k + 1] - p[k]);
                    tangent = (p[k + 1] - p[k]) / step;
                    break;
                }
                walked_m += step;
            }
            if (reversed) tangent = -tangent;
            if (auto tip = fit(x, Vec2(-tangent.y(), tangent.x()))) {
                at[ei].push_back(s);
                spurs.push_back({e, s, -1, *tip});
                ++made;
            }
        }
    }
    if (spurs.empty()) return 0;
    // The streets split where the dead-end streets leave them, then the dead-end streets.
    std::vector<std::vector<double>> sorted_at = at;
    const std::vector<std::vector<VertexId>> junctions = split_edges_at(g, sorted_at);
    EdgeAttributes attributes;
    attributes.highway = city.highway;
    for (const Spur& spur : spurs) {
        if (spur.root >= 0) {
            g.add_edge(spur.root, g.add_vertex(spur.end), attributes);
            continue;
        }
        const auto& points = sorted_at[static_cast<std::size_t>(spur.edge)];
        const auto k = static_cast<std::size_t>(std::lower_bound(points.begin(), points.end(), spur.s) - points.begin());
        const VertexId junction = junctions[static_cast<std::size_t>(spur.edge)][k];
        const VertexId end = g.add_vertex(spur.end);
        g.add_edge(junction, end, attributes);
    }
    return spurs.size();
}

} // namespace ggg::growth_detail
