#include "ggg/osm/topology.hpp"

#include <algorithm>
#include <numeric>


#include "ggg/error.hpp"
#include "ggg/graph/spatial_index.hpp"

namespace ggg {

void TopologyInput::add_way(const std::vector<std::int32_t>& nodes, EdgeAttributes attributes) {
    way_nodes.insert(way_nodes.end(), nodes.begin(), nodes.end());
    way_offsets.push_back(static_cast<std::int64_t>(way_nodes.size()));
    way_attributes.push_back(std::move(attributes));
}

namespace {

namespace bgi = spatial::bgi;

// A run of a way between two vertices: end keys u, v (vertex keys, see below) and the
// node indices in between.
struct Piece {
    std::int32_t u;
    std::int32_t v;
    std::int32_t node_u; // the end nodes before consolidation
    std::int32_t node_v;
    std::vector<std::int32_t> interior;
    std::uint32_t way;
    bool keep = true;
    bool both_directions = false; // a merged dual carriageway
};

double point_segment_distance(const Vec2& p, const Vec2& a, const Vec2& b) {
    const Vec2 ab = b - a;
    const double len2 = ab.squaredNorm();
    const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
    return (p - (a + t * ab)).norm();
}

// Every point of `a` lies within `tolerance` of polyline `b`.
bool within(const std::vector<Vec2>& a, const std::vector<Vec2>& b, double tolerance) {
    for (const Vec2& p : a) {
        double best = std::numeric_limits<double>::infinity();
        for (std::size_t i = 1; i < b.size() && best > tolerance; ++i) {
            best = std::min(best, point_segment_distance(p, b[i - 1], b[i]));
        }
        if (best > tolerance) return false;
    }
    return true;
}

double polyline_length(const std::vector<Vec2>& p) {
    double length = 0;
    for (std::size_t i = 1; i < p.size(); ++i) length += (p[i] - p[i - 1]).norm();
    return length;
}

class Builder {
public:
    Builder(const TopologyInput& input, const TopologyOptions& options, TopologyReport& report,
            const ProgressCallback& progress)
        : in_(input), options_(options), report_(report), progress_(progress) {}

    GeometricGraph run(GeoOrigin origin) {
        const std::size_t n = in_.node_positions.size();
        key_.resize(n);
        std::iota(key_.begin(), key_.end(), 0);
        vertex_position_ = in_.node_positions;
        mark_vertices();
        split_ways();
        report(progress_, 0.55, "building topology");
        if (options_.consolidate_m > 0) consolidate();
        resolve_self_loops();
        resolve_parallel_pieces();
        report(progress_, 0.8, "building graph");
        return emit(origin);
    }

private:
    const TopologyInput& in_;
    const TopologyOptions& options_;
    TopologyReport& report_;
    const ProgressCallback& progress_;
    std::vector<std::int32_t> key_;      // node -> vertex key (itself, or its cluster's representative)
    std::vector<Vec2> vertex_position_;  // by key
    std::vector<char> is_vertex_;        // by node
    std::vector<Piece> pieces_;

    void mark_vertices() {
        const std::size_t n = in_.node_positions.size();
        std::vector<std::uint8_t> uses(n, 0);
        is_vertex_.assign(n, options_.keep_shape_nodes ? 1 : 0);
        for (std::size_t w = 0; w < in_.way_count(); ++w) {
            const auto begin = in_.way_offsets[w];
            const auto end = in_.way_offsets[w + 1];
            if (end - begin < 2) continue;
            is_vertex_[static_cast<std::size_t>(in_.way_nodes[static_cast<std::size_t>(begin)])] = 1;
            is_vertex_[static_cast<std::size_t>(in_.way_nodes[static_cast<std::size_t>(end - 1)])] = 1;
            for (auto i = begin; i < end; ++i) {
                const auto node = static_cast<std::size_t>(in_.way_nodes[static_cast<std::size_t>(i)]);
                // A node repeated right after itself is one place, not a crossing.
                if (i > begin && in_.way_nodes[static_cast<std::size_t>(i - 1)] == in_.way_nodes[static_cast<std::size_t>(i)]) continue;
                if (++uses[node] >= 2) {
                    is_vertex_[node] = 1;
                    uses[node] = 2;
                }
            }
        }
    }

    void split_ways() {
        for (std::size_t w = 0; w < in_.way_count(); ++w) {
            const auto begin = static_cast<std::size_t>(in_.way_offsets[w]);
            const auto end = static_cast<std::size_t>(in_.way_offsets[w + 1]);
            std::int32_t start = -1;
            std::vector<std::int32_t> interior;
            std::int32_t previous = -1;
            for (std::size_t i = begin; i < end; ++i) {
                const std::int32_t node = in_.way_nodes[i];
                if (node == previous) continue;
                previous = node;
                if (!is_vertex_[static_cast<std::size_t>(node)]) {
                    interior.push_back(node);
                    continue;
                }
                if (start >= 0) {
                    pieces_.push_back({start, node, start, node, std::move(interior), static_cast<std::uint32_t>(w)});
                    interior.clear();
                }
                start = node;
            }
        }
    }

    std::vector<Vec2> polyline(const Piece& p) const {
        std::vector<Vec2> points;
        points.reserve(p.interior.size() + 2);
        points.push_back(vertex_position_[static_cast<std::size_t>(p.u)]);
        for (auto node : p.interior) points.push_back(vertex_position_[static_cast<std::size_t>(node)]);
        points.push_back(vertex_position_[static_cast<std::size_t>(p.v)]);
        return points;
    }

    // Turns interior node `index` of piece `i` into a vertex: the piece ends there and a
    // new piece carries the rest.
    void promote(std::size_t i, std::size_t index) {
        Piece& p = pieces_[i];
        const std::int32_t node = p.interior[index];
        Piece rest{node, p.v, node, p.node_v, std::vector<std::int32_t>(p.interior.begin() + static_cast<std::ptrdiff_t>(index) + 1, p.interior.end()), p.way};
        p.interior.resize(index);
        p.v = node;
        p.node_v = node;
        ++report_.promoted_shape_nodes;
        pieces_.push_back(std::move(rest));
    }

    void consolidate() {
        const double tolerance = options_.consolidate_m;
        std::vector<std::int32_t> vertices;
        for (std::size_t node = 0; node < is_vertex_.size(); ++node) {
            if (is_vertex_[node]) vertices.push_back(static_cast<std::int32_t>(node));
        }
        std::vector<std::pair<spatial::Point, std::int32_t>> entries;
        entries.reserve(vertices.size());
        for (auto node : vertices) {
            const Vec2& p = in_.node_positions[static_cast<std::size_t>(node)];
            entries.emplace_back(spatial::point(p), node);
        }
        spatial::RTree<std::pair<spatial::Point, std::int32_t>> tree(entries.begin(), entries.end());
        // Clusters grow around seeds, never by chaining: a vertex joins a seed it is within
        // the tolerance of, so a street of intersections 8 m apart does not collapse into one
        // point at a 10 m tolerance. Seeds are taken densest first (most vertices within
        // reach), then in node order, so the result is deterministic.
        std::vector<std::vector<std::int32_t>> near(vertices.size());
        std::vector<std::pair<spatial::Point, std::int32_t>> found;
        for (std::size_t i = 0; i < vertices.size(); ++i) {
            const Vec2& p = in_.node_positions[static_cast<std::size_t>(vertices[i])];
            const spatial::Box box = spatial::around(p, tolerance);
            found.clear();
            tree.query(bgi::intersects(box), std::back_inserter(found));
            for (const auto& [q, other] : found) {
                if (other != vertices[i] && (in_.node_positions[static_cast<std::size_t>(other)] - p).norm() <= tolerance) {
                    near[i].push_back(other);
                }
            }
            std::sort(near[i].begin(), near[i].end());
        }
        std::vector<std::size_t> seeds(vertices.size());
        std::iota(seeds.begin(), seeds.end(), 0);
        std::stable_sort(seeds.begin(), seeds.end(), [&](std::size_t a, std::size_t b) { return near[a].size() > near[b].size(); });
        std::vector<std::int32_t> cluster_of(in_.node_positions.size(), -1);
        for (std::size_t i : seeds) {
            const std::int32_t seed = vertices[i];
            if (cluster_of[static_cast<std::size_t>(seed)] >= 0) continue;
            cluster_of[static_cast<std::size_t>(seed)] = seed;
            for (std::int32_t other : near[i]) {
                if (cluster_of[static_cast<std::size_t>(other)] < 0) cluster_of[static_cast<std::size_t>(other)] = seed;
            }
        }
        std::vector<Vec2> sum(in_.node_positions.size(), Vec2::Zero());
        std::vector<std::int32_t> count(in_.node_positions.size(), 0);
        for (auto node : vertices) {
            const auto root = cluster_of[static_cast<std::size_t>(node)];
            key_[static_cast<std::size_t>(node)] = root;
            sum[static_cast<std::size_t>(root)] += in_.node_positions[static_cast<std::size_t>(node)];
            ++count[static_cast<std::size_t>(root)];
        }
        for (auto node : vertices) {
            if (key_[static_cast<std::size_t>(node)] == node) {
                const auto c = count[static_cast<std::size_t>(node)];
                vertex_position_[static_cast<std::size_t>(node)] = sum[static_cast<std::size_t>(node)] / c;
                report_.consolidated_vertices += static_cast<std::size_t>(c - 1);
            }
        }
        for (Piece& p : pieces_) {
            p.u = key_[static_cast<std::size_t>(p.u)];
            p.v = key_[static_cast<std::size_t>(p.v)];
        }
    }

    void resolve_self_loops() {
        const std::size_t count = pieces_.size();
        for (std::size_t i = 0; i < count; ++i) {
            Piece& p = pieces_[i];
            if (p.u != p.v) continue;
            if (options_.consolidate_m > 0 && polyline_length(polyline(p)) <= 4 * options_.consolidate_m) {
                p.keep = false; // a connector inside a consolidated intersection
                ++report_.dropped_degenerate;
            } else if (p.interior.size() >= 2) {
                const std::size_t a = p.interior.size() / 3;
                const std::size_t b = std::max(a + 1, (2 * p.interior.size()) / 3);
                promote(i, b);
                promote(i, a);
            } else if (p.interior.size() == 1) {
                // u -> x -> u runs the same segment twice: keep it once, as a spur.
                pieces_[i].v = pieces_[i].node_v = pieces_[i].interior[0];
                pieces_[i].interior.clear();
                ++report_.promoted_shape_nodes;
            } else {
                p.keep = false;
                ++report_.dropped_degenerate;
            }
        }
    }

    // The road direction a piece allows, relative to its u -> v: 1, -1, or 0 for both.
    int direction(const Piece& p) const { return in_.way_attributes[p.way].oneway; }

    // Piece `dropped` is stored as `kept`; if they let traffic go different ways, the kept
    // one now carries both (two one-way carriageways are one two-way road).
    void absorb(std::size_t kept, std::size_t dropped) {
        Piece& k = pieces_[kept];
        Piece& d = pieces_[dropped];
        d.keep = false;
        const int kept_direction = direction(k);
        const int dropped_direction = (d.u == k.u ? 1 : -1) * direction(d);
        if (kept_direction != 0 && dropped_direction != kept_direction) k.both_directions = true;
    }

    static bool same_run(const Piece& a, const Piece& b) {
        if (a.u == b.u && a.v == b.v) return a.interior == b.interior;
        if (a.u == b.v && a.v == b.u) return std::equal(a.interior.begin(), a.interior.end(), b.interior.rbegin(), b.interior.rend());
        return false;
    }

    void resolve_parallel_pieces() {
        std::vector<std::size_t> order;
        for (std::size_t i = 0; i < pieces_.size(); ++i) {
            if (pieces_[i].keep) order.push_back(i);
        }
        auto pair_of = [&](std::size_t i) {
            const Piece& p = pieces_[i];
            return std::pair{std::min(p.u, p.v), std::max(p.u, p.v)};
        };
        // Within a group: straighter first (fewest shape nodes), then input order.
        std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
            const auto ka = pair_of(a);
            const auto kb = pair_of(b);
            if (ka != kb) return ka < kb;
            if (pieces_[a].interior.size() != pieces_[b].interior.size()) return pieces_[a].interior.size() < pieces_[b].interior.size();
            return a < b;
        });
        std::size_t group_begin = 0;
        std::vector<std::size_t> kept;
        while (group_begin < order.size()) {
            std::size_t group_end = group_begin + 1;
            while (group_end < order.size() && pair_of(order[group_end]) == pair_of(order[group_begin])) ++group_end;
            kept.assign(1, order[group_begin]);
            for (std::size_t k = group_begin + 1; k < group_end; ++k) {
                const std::size_t i = order[k];
                const auto same = std::find_if(kept.begin(), kept.end(), [&](std::size_t j) { return same_run(pieces_[i], pieces_[j]); });
                if (same != kept.end()) {
                    absorb(*same, i);
                    const bool same_nodes = std::minmax(pieces_[i].node_u, pieces_[i].node_v) ==
                                            std::minmax(pieces_[*same].node_u, pieces_[*same].node_v);
                    ++(same_nodes ? report_.duplicate_pieces : report_.merged_parallel);
                    continue;
                }
                if (options_.consolidate_m > 0) {
                    const auto line = polyline(pieces_[i]);
                    const double tolerance = 2 * options_.consolidate_m;
                    const auto close = std::find_if(kept.begin(), kept.end(), [&](std::size_t j) {
                        const auto other = polyline(pieces_[j]);
                        return within(line, other, tolerance) && within(other, line, tolerance);
                    });
                    if (close != kept.end()) { // a dual carriageway: one road
                        absorb(*close, i);
                        ++report_.merged_parallel;
                        continue;
                    }
                }
                // Different roads between the same vertices: split this one at its middle.
                // It has shape nodes: only the first of a group can be straight.
                promote(i, pieces_[i].interior.size() / 2);
                kept.push_back(i);
            }
            group_begin = group_end;
        }
    }

    GeometricGraph emit(GeoOrigin origin) {
        GeometricGraph g;
        g.origin = origin;
        std::vector<char> used(in_.node_positions.size(), 0);
        std::size_t edge_count = 0;
        std::size_t points = 0;
        for (const Piece& p : pieces_) {
            if (!p.keep) continue;
            used[static_cast<std::size_t>(p.u)] = 1;
            used[static_cast<std::size_t>(p.v)] = 1;
            ++edge_count;
            points += p.interior.size() + 2;
        }
        std::vector<VertexId> vertex_of(in_.node_positions.size(), -1);
        const auto vertex_total = static_cast<std::size_t>(std::count(used.begin(), used.end(), 1));
        g.reserve(vertex_total, edge_count, points);
        for (std::size_t node = 0; node < used.size(); ++node) {
            if (used[node]) vertex_of[node] = g.add_vertex(vertex_position_[node], in_.node_osm_ids[node]);
        }
        std::vector<Vec2> line;
        for (const Piece& p : pieces_) {
            if (!p.keep) continue;
            EdgeAttributes attributes = in_.way_attributes[p.way];
            if (p.both_directions) attributes.oneway = 0;
            line = polyline(p);
            g.add_edge(vertex_of[static_cast<std::size_t>(p.u)], vertex_of[static_cast<std::size_t>(p.v)], attributes, line);
        }
        return g;
    }
};

} // namespace

GeometricGraph build_graph(const TopologyInput& input, GeoOrigin origin, const TopologyOptions& options,
                           TopologyReport* report, const ProgressCallback& progress) {
    if (options.consolidate_m < 0 || !std::isfinite(options.consolidate_m)) {
        throw UsageError("consolidation tolerance must be a finite number of metres >= 0");
    }
    if (input.node_positions.size() > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max())) {
        throw InputError("too many nodes for one graph");
    }
    TopologyReport local;
    Builder builder(input, options, report ? *report : local, progress);
    GeometricGraph g = builder.run(origin);
    if (g.edge_count() == 0) {
        throw InputError("no road segments left after building the graph");
    }
    return g;
}

} // namespace ggg
