// The last stage of growth: the grown streets tidied (see street_cleanup.hpp).
#include "street_cleanup.hpp"

#include <algorithm>
#include <cmath>
#include <set>

#include "ggg/graph/plane_geometry.hpp"
#include "ggg/graph/spatial_index.hpp"

namespace ggg::growth_detail {

using namespace spatial; // bg, bgi, Point, Box, point, RTree, VertexEntry, EdgeEntry

// The graph again with the vertices not dropped (the base first, unchanged; grown ids shift
// down) and these streets, given in the old vertex ids.
Street street_of(const GeometricGraph& g, EdgeId e) {
    const Vec2* p = g.geometry_begin(e);
    return {g.edges[static_cast<std::size_t>(e)][0], g.edges[static_cast<std::size_t>(e)][1], g.edge_attributes(e),
            std::vector<Vec2>(p, p + g.geometry_size(e))};
}

GeometricGraph rebuilt(const GeometricGraph& g, const std::vector<char>& drop_vertex, const std::vector<Street>& streets) {
    GeometricGraph kept;
    kept.origin = g.origin;
    kept.names = g.names;
    std::vector<VertexId> id(g.vertex_count(), -1);
    for (std::size_t v = 0; v < g.vertex_count(); ++v) {
        if (drop_vertex[v]) continue;
        id[v] = kept.add_vertex(g.positions[v], g.vertex_osm_ids.empty() ? 0 : g.vertex_osm_ids[v]);
        if (!g.symbols.empty()) kept.symbols[static_cast<std::size_t>(id[v])] = g.symbols[v];
        if (!g.frames.empty()) kept.frames[static_cast<std::size_t>(id[v])] = g.frames[v];
        copy_more_rewrites(g, static_cast<VertexId>(v), kept, id[v]);
    }
    for (const Street& street : streets) {
        kept.add_edge(id[static_cast<std::size_t>(street.a)], id[static_cast<std::size_t>(street.b)], street.attributes, street.polyline);
    }
    if (!g.instances.empty()) {
        kept.instances.clear();
        for (std::size_t v = 0; v < g.vertex_count(); ++v) {
            if (!drop_vertex[v]) kept.instances.push_back(g.instances[v]);
        }
    }
    return kept;
}

// The last guard of the rule that no two streets cross without an intersection: a grown
// street that crosses another street (each stage checks as it goes; this catches what
// their combination lets through) is taken out again, the newer of two grown ones.
std::size_t remove_crossing_streets(GeometricGraph& g, std::size_t base_vertices, std::size_t base_edges) {
    if (g.edge_count() <= base_edges) return 0;
    // Only pieces that can meet a grown street are indexed (those in the box around all of
    // them), and the index is packed at once: built piece by piece over a whole metro's
    // streets, it took 1.6 s of a 10 s growth, twice.
    Box reach = edge_box(g, static_cast<EdgeId>(base_edges));
    for (std::size_t e = base_edges + 1; e < g.edge_count(); ++e) bg::expand(reach, edge_box(g, static_cast<EdgeId>(e)));
    std::vector<EdgeEntry> entries;
    std::vector<std::pair<std::size_t, std::size_t>> piece_of; // (edge, piece)
    for (std::size_t e = 0; e < g.edge_count(); ++e) {
        if (!bg::intersects(edge_box(g, static_cast<EdgeId>(e)), reach)) continue;
        const Vec2* p = g.geometry_begin(static_cast<EdgeId>(e));
        for (std::size_t i = 0; i + 1 < g.geometry_size(static_cast<EdgeId>(e)); ++i) {
            Box box(point(p[i]), point(p[i]));
            bg::expand(box, point(p[i + 1]));
            entries.push_back({box, static_cast<EdgeId>(piece_of.size())});
            piece_of.emplace_back(e, i);
        }
    }
    const RTree<EdgeEntry> pieces(entries.begin(), entries.end());
    std::vector<char> drop_edge(g.edge_count(), 0);
    std::size_t dropped = 0;
    for (std::size_t e = base_edges; e < g.edge_count(); ++e) {
        if (drop_edge[e]) continue;
        const auto [u, v] = g.edges[e];
        const Vec2* p = g.geometry_begin(static_cast<EdgeId>(e));
        bool crossing = false;
        for (std::size_t i = 0; i + 1 < g.geometry_size(static_cast<EdgeId>(e)) && !crossing; ++i) {
            Box box(point(p[i]), point(p[i]));
            bg::expand(box, point(p[i + 1]));
            for (auto it = pieces.qbegin(bgi::intersects(box)); it != pieces.qend() && !crossing; ++it) {
                const auto [f, k] = piece_of[static_cast<std::size_t>(it->second)];
                if (f == e || drop_edge[f] || (f > e)) continue; // each pair once: the newer one goes
                const auto [a, b] = g.edges[f];
                const Vec2* q = g.geometry_begin(static_cast<EdgeId>(f));
                const auto m = segment_meeting(p[i], p[i + 1], q[k], q[k + 1]);
                crossing = m && m->first > 1e-9 && m->first < 1 - 1e-9 && m->second > 1e-9 && m->second < 1 - 1e-9;
                // Two streets from one junction meet there, and their pieces at it nowhere
                // else (two straight pieces meet once; almost straight on from each other,
                // their meeting is found a little off it). Further along they must not meet.
                if (crossing) {
                    const std::size_t last_e = g.geometry_size(static_cast<EdgeId>(e)) - 2, last_f = g.geometry_size(static_cast<EdgeId>(f)) - 2;
                    for (const VertexId shared : {a, b}) {
                        const bool piece_e_at = (i == 0 && u == shared) || (i == last_e && v == shared);
                        const bool piece_f_at = (k == 0 && a == shared) || (k == last_f && b == shared);
                        if (piece_e_at && piece_f_at) crossing = false;
                    }
                }
            }
        }
        if (crossing) {
            drop_edge[e] = 1;
            ++dropped;
        }
    }
    if (dropped == 0) return 0;
    std::vector<std::size_t> degree(g.vertex_count(), 0);
    std::vector<Street> streets;
    for (std::size_t e = 0; e < g.edge_count(); ++e) {
        if (drop_edge[e]) continue;
        ++degree[static_cast<std::size_t>(g.edges[e][0])];
        ++degree[static_cast<std::size_t>(g.edges[e][1])];
        streets.push_back(street_of(g, static_cast<EdgeId>(e)));
    }
    std::vector<char> drop_vertex(g.vertex_count(), 0);
    for (std::size_t v = base_vertices; v < g.vertex_count(); ++v) drop_vertex[v] = degree[v] == 0;
    g = rebuilt(g, drop_vertex, streets);
    return dropped;
}

// A grown vertex where two grown streets of one class meet and nothing else is no junction:
// the two become one street through it (a bend of its polyline). Returns how many went.
std::size_t dissolve_bends(GeometricGraph& g, std::size_t base_vertices, std::size_t base_edges) {
    const std::size_t n = g.vertex_count();
    std::vector<std::vector<EdgeId>> at(n);
    for (std::size_t e = 0; e < g.edge_count(); ++e) {
        at[static_cast<std::size_t>(g.edges[e][0])].push_back(static_cast<EdgeId>(e));
        at[static_cast<std::size_t>(g.edges[e][1])].push_back(static_cast<EdgeId>(e));
    }
    auto other = [&](EdgeId e, VertexId v) { return g.edges[static_cast<std::size_t>(e)][0] == v ? g.edges[static_cast<std::size_t>(e)][1] : g.edges[static_cast<std::size_t>(e)][0]; };
    std::vector<char> bend(n, 0);
    std::size_t bends = 0;
    for (std::size_t v = base_vertices; v < n; ++v) {
        const auto& es = at[v];
        if (es.size() != 2 || es[0] == es[1]) continue;
        if (static_cast<std::size_t>(es[0]) < base_edges || static_cast<std::size_t>(es[1]) < base_edges) continue;
        // A change of class between two grown streets goes too: a city's streets change class
        // at a bend rarely (at 0.1 to 2.6 % of the vertices of the shared extracts), where
        // traced streets, each taking the class of its example's street, did so at one grown
        // vertex in eleven (Rome), each one more street to count and to draw.
        bend[v] = 1;
        ++bends;
    }
    if (bends == 0) return 0;
    std::vector<char> used(g.edge_count(), 0);
    std::vector<Street> streets;
    std::set<std::pair<VertexId, VertexId>> pairs;
    for (std::size_t e = 0; e < g.edge_count(); ++e) {
        if (!bend[static_cast<std::size_t>(g.edges[e][0])] && !bend[static_cast<std::size_t>(g.edges[e][1])]) {
            pairs.insert(std::minmax(g.edges[e][0], g.edges[e][1]));
        }
    }
    // The street a chain becomes, walked from `start`, is of the class of its longest piece,
    // one way where that piece is, in the direction that piece runs.
    auto chain_attributes = [&](const std::vector<EdgeId>& chain, VertexId start) {
        EdgeId longest = chain.front();
        double most = -1.0;
        bool longest_along = true; // the longest piece runs from its first vertex on along the walk
        VertexId from = start;
        for (const EdgeId e : chain) {
            const bool along = g.edges[static_cast<std::size_t>(e)][0] == from;
            if (const double length = g.edge_length(e); length > most) most = length, longest = e, longest_along = along;
            from = other(e, from);
        }
        EdgeAttributes attributes = g.edge_attributes(longest);
        if (!longest_along) attributes.oneway = static_cast<std::int8_t>(-attributes.oneway);
        return attributes;
    };
    // Each chain of bends, walked from a junction at one end.
    auto walk = [&](VertexId start, EdgeId first) {
        std::vector<EdgeId> chain{first};
        std::vector<Vec2> line = polyline_from(g, first, start);
        VertexId v = other(first, start);
        used[static_cast<std::size_t>(first)] = 1;
        while (bend[static_cast<std::size_t>(v)] && v != start) {
            const auto& es = at[static_cast<std::size_t>(v)];
            const EdgeId next = es[0] == chain.back() ? es[1] : es[0];
            if (used[static_cast<std::size_t>(next)]) break;
            used[static_cast<std::size_t>(next)] = 1;
            const std::vector<Vec2> more = polyline_from(g, next, v);
            line.insert(line.end(), more.begin() + 1, more.end());
            chain.push_back(next);
            v = other(next, v);
        }
        const auto pair = std::minmax(start, v);
        if (chain.size() > 1 && start != v && !bend[static_cast<std::size_t>(v)] && pairs.insert(pair).second) {
            streets.push_back({start, v, chain_attributes(chain, start), std::move(line)});
            return;
        }
        // A loop, or a street already there between its ends: its bends stay junctions.
        VertexId from = start;
        for (const EdgeId e : chain) {
            const VertexId to = other(e, from);
            if (bend[static_cast<std::size_t>(to)] && to != start) bend[static_cast<std::size_t>(to)] = 2; // kept
            from = to;
        }
        for (const EdgeId e : chain) {
            const Vec2* p = g.geometry_begin(e);
            streets.push_back({g.edges[static_cast<std::size_t>(e)][0], g.edges[static_cast<std::size_t>(e)][1], g.edge_attributes(e),
                               std::vector<Vec2>(p, p + g.geometry_size(e))});
        }
    };
    for (std::size_t e = 0; e < g.edge_count(); ++e) {
        if (used[e]) continue;
        const auto [a, b] = g.edges[e];
        if (!bend[static_cast<std::size_t>(a)]) walk(a, static_cast<EdgeId>(e));
        else if (!bend[static_cast<std::size_t>(b)]) walk(b, static_cast<EdgeId>(e));
    }
    // What is left is rings of bends only: kept as they are.
    for (std::size_t e = 0; e < g.edge_count(); ++e) {
        if (used[e]) continue;
        for (const VertexId end : g.edges[e]) bend[static_cast<std::size_t>(end)] = 2;
        streets.push_back(street_of(g, static_cast<EdgeId>(e)));
    }
    std::vector<char> drop(n, 0);
    std::size_t dropped = 0;
    for (std::size_t v = 0; v < n; ++v) {
        drop[v] = bend[v] == 1;
        dropped += drop[v];
    }
    if (dropped == 0) return 0;
    g = rebuilt(g, drop, streets);
    return dropped;
}

CityBends bends_of(const GeometricGraph& base, const Vec2& centre, double radius) {
    const Adjacency adjacency(base);
    std::size_t vertices = 0, bends = 0;
    for (std::size_t v = 0; v < base.vertex_count(); ++v) {
        const std::size_t degree = adjacency.degree(static_cast<VertexId>(v));
        if (degree == 0 || (base.positions[v] - centre).norm() > radius) continue;
        ++vertices;
        bends += degree == 2;
    }
    std::vector<double> lengths;
    for (const auto& [a, b] : base.edges) {
        const Vec2 pa = base.positions[static_cast<std::size_t>(a)], pb = base.positions[static_cast<std::size_t>(b)];
        if ((pa - centre).norm() <= radius) lengths.push_back((pb - pa).norm());
    }
    CityBends city;
    // Too few to say: no splits.
    if (vertices < 50 || lengths.empty()) return city;
    city.share = static_cast<double>(bends) / static_cast<double>(vertices);
    const auto tenth = lengths.begin() + static_cast<std::ptrdiff_t>(lengths.size() / 10);
    std::nth_element(lengths.begin(), tenth, lengths.end());
    city.short_edge_m = *tenth;
    return city;
}

bool simple_line(const Vec2* p, std::size_t n) {
    for (std::size_t i = 0; i + 1 < n; ++i) {
        if (i + 2 < n && (p[i + 1] - p[i]).dot(p[i + 2] - p[i + 1]) < -0.99 * (p[i + 1] - p[i]).norm() * (p[i + 2] - p[i + 1]).norm()) return false;
        for (std::size_t j = i + 2; j + 1 < n; ++j) {
            if (segments_meet(p[i], p[i + 1], p[j], p[j + 1])) return false;
        }
    }
    return true;
}

std::size_t split_streets(GeometricGraph& g, std::size_t base_vertices, std::size_t base_edges, const CityBends& bends,
                          std::mt19937_64& rng) {
    if (bends.share <= 0.0 || bends.share >= 0.95 || bends.short_edge_m <= 0.0) return 0;
    const Adjacency adjacency(g);
    std::size_t grown = 0, two = 0;
    for (std::size_t v = base_vertices; v < g.vertex_count(); ++v) {
        const std::size_t degree = adjacency.degree(static_cast<VertexId>(v));
        grown += degree > 0;
        two += degree == 2;
    }
    // (two + k) / (grown + k) = share
    const double missing = (bends.share * static_cast<double>(grown) - static_cast<double>(two)) / (1.0 - bends.share);
    if (missing < 1.0) return 0;
    const auto wanted = static_cast<std::size_t>(std::lround(missing));
    // The grown streets by length, and the points along each where it is split (arc lengths).
    std::vector<double> length(g.edge_count(), 0.0), cumulative;
    std::vector<EdgeId> candidates;
    double total = 0.0;
    for (std::size_t e = base_edges; e < g.edge_count(); ++e) {
        const Vec2* p = g.geometry_begin(static_cast<EdgeId>(e));
        for (std::size_t k = 0; k + 1 < g.geometry_size(static_cast<EdgeId>(e)); ++k) length[e] += (p[k + 1] - p[k]).norm();
        if (length[e] < 2.0 * bends.short_edge_m || !simple_line(p, g.geometry_size(static_cast<EdgeId>(e)))) continue;
        candidates.push_back(static_cast<EdgeId>(e));
        total += length[e];
        cumulative.push_back(total);
    }
    if (candidates.empty()) return 0;
    std::vector<std::vector<double>> at(g.edge_count());
    const double gap = bends.short_edge_m;
    std::size_t made = 0;
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (std::size_t attempt = 0; made < wanted && attempt < 20 * wanted; ++attempt) {
        const auto pick = static_cast<std::size_t>(std::upper_bound(cumulative.begin(), cumulative.end(), unit(rng) * total) - cumulative.begin());
        const auto e = static_cast<std::size_t>(candidates[std::min(pick, candidates.size() - 1)]);
        const double s = gap + unit(rng) * (length[e] - 2.0 * gap);
        auto& points = at[e];
        if (std::any_of(points.begin(), points.end(), [&](double q) { return std::abs(q - s) < gap; })) continue;
        points.push_back(s);
        ++made;
    }
    if (made == 0) return 0;
    split_edges_at(g, at);
    return made;
}

std::vector<std::vector<VertexId>> split_edges_at(GeometricGraph& g, std::vector<std::vector<double>>& at) {
    std::vector<std::vector<VertexId>> made(g.edge_count());
    // The graph again: each split street in pieces, with a vertex at each split.
    std::vector<Street> streets;
    streets.reserve(g.edge_count());
    const std::size_t edges = g.edge_count();
    for (std::size_t e = 0; e < edges; ++e) {
        const Vec2* p = g.geometry_begin(static_cast<EdgeId>(e));
        const std::size_t n = g.geometry_size(static_cast<EdgeId>(e));
        auto& points = at[e];
        if (points.empty()) {
            streets.push_back({g.edges[e][0], g.edges[e][1], g.edge_attributes(static_cast<EdgeId>(e)), std::vector<Vec2>(p, p + n)});
            continue;
        }
        std::sort(points.begin(), points.end());
        const EdgeAttributes attributes = g.edge_attributes(static_cast<EdgeId>(e));
        VertexId from = g.edges[e][0];
        std::vector<Vec2> piece{p[0]};
        double walked = 0.0;
        std::size_t next = 0;
        for (std::size_t k = 0; k + 1 < n; ++k) {
            const double step = (p[k + 1] - p[k]).norm();
            while (next < points.size() && points[next] <= walked + step) {
                const Vec2 x = p[k] + (step > 0.0 ? (points[next] - walked) / step : 0.0) * (p[k + 1] - p[k]);
                piece.push_back(x);
                const VertexId v = g.add_vertex(x);
                made[e].push_back(v);
                streets.push_back({from, v, attributes, std::move(piece)});
                from = v;
                piece = {x};
                ++next;
            }
            walked += step;
            piece.push_back(p[k + 1]);
        }
        streets.push_back({from, g.edges[e][1], attributes, std::move(piece)});
    }
    g = rebuilt(g, std::vector<char>(g.vertex_count(), 0), streets);
    return made;
}

} // namespace ggg::growth_detail
