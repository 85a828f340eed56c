#include "ggg/graph/planar_faces.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace ggg {

namespace {

// Half-edge h of edge h/2: even = as stored (edges[e][0] -> edges[e][1]), odd = reversed.
using HalfEdge = std::int64_t;

constexpr double kSamePoint = 1e-9; // metres: polyline points closer than this are one point

struct Walker {
    const GeometricGraph& g;

    VertexId origin(HalfEdge h) const { return g.edges[static_cast<std::size_t>(h >> 1)][static_cast<std::size_t>(h & 1)]; }
    VertexId target(HalfEdge h) const { return g.edges[static_cast<std::size_t>(h >> 1)][static_cast<std::size_t>((h & 1) ^ 1)]; }

    // The polyline of the edge, or nothing when it is the straight segment.
    std::pair<const Vec2*, std::size_t> line(HalfEdge h) const {
        const auto e = static_cast<EdgeId>(h >> 1);
        const std::size_t n = g.geometry_size(e);
        return {n >= 2 ? g.geometry_begin(e) : nullptr, n >= 2 ? n : 0};
    }

    // Direction in which h leaves its origin: towards the first polyline point that is not
    // the origin itself (shape nodes may repeat it), else towards the target.
    double leaving_angle(HalfEdge h) const {
        const Vec2& from = g.positions[static_cast<std::size_t>(origin(h))];
        Vec2 to = g.positions[static_cast<std::size_t>(target(h))];
        const auto [pts, n] = line(h);
        for (std::size_t k = 1; k < n; ++k) {
            const Vec2& p = pts[(h & 1) ? n - 1 - k : k];
            if ((p - from).norm() > kSamePoint) {
                to = p;
                break;
            }
        }
        return std::atan2(to.y() - from.y(), to.x() - from.x());
    }

    // Appends the points of h from its origin up to, not including, its target.
    void append_points(HalfEdge h, std::vector<Vec2>& out) const {
        const auto [pts, n] = line(h);
        if (n == 0) {
            out.push_back(g.positions[static_cast<std::size_t>(origin(h))]);
            return;
        }
        if ((h & 1) == 0) {
            out.insert(out.end(), pts, pts + (n - 1));
        } else {
            for (std::size_t k = n - 1; k > 0; --k) out.push_back(pts[k]);
        }
    }
};

// Components by union-find over the edges.
std::vector<std::int32_t> vertex_components(const GeometricGraph& g, std::size_t& count) {
    std::vector<std::int32_t> parent(g.vertex_count());
    std::iota(parent.begin(), parent.end(), 0);
    auto find = [&](std::int32_t v) {
        while (parent[static_cast<std::size_t>(v)] != v) {
            parent[static_cast<std::size_t>(v)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(v)])];
            v = parent[static_cast<std::size_t>(v)];
        }
        return v;
    };
    for (const auto& [u, v] : g.edges) {
        const auto a = find(u), b = find(v);
        if (a != b) parent[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);
    }
    // Number the roots of vertices that have edges, in vertex order.
    std::vector<std::int32_t> id(g.vertex_count(), -1), out(g.vertex_count(), -1);
    std::vector<char> has_edge(g.vertex_count(), 0);
    for (const auto& [u, v] : g.edges) has_edge[static_cast<std::size_t>(u)] = has_edge[static_cast<std::size_t>(v)] = 1;
    count = 0;
    for (std::size_t v = 0; v < g.vertex_count(); ++v) {
        if (!has_edge[v]) continue;
        const auto root = static_cast<std::size_t>(find(static_cast<std::int32_t>(v)));
        if (id[root] < 0) id[root] = static_cast<std::int32_t>(count++);
        out[v] = id[root];
    }
    return out;
}

// Bridges of the graph (edges whose removal disconnects their component), by Tarjan's
// low-link numbers with an explicit stack: dead ends and the streets that join an inner
// loop to a block are bridges, and a face walk goes out along a bridge and back along it.
std::vector<char> bridges(const GeometricGraph& g) {
    const Adjacency adjacency(g);
    const std::size_t n = g.vertex_count();
    std::vector<std::int64_t> order(n, -1), low(n, 0);
    std::vector<char> bridge(g.edge_count(), 0);
    struct Frame {
        VertexId v;
        EdgeId via;        // edge we arrived by (-1 at a root)
        std::int64_t next; // next adjacency slot to look at
    };
    std::vector<Frame> stack;
    std::int64_t counter = 0;
    for (std::size_t root = 0; root < n; ++root) {
        if (order[root] >= 0) continue;
        order[root] = low[root] = counter++;
        stack.push_back({static_cast<VertexId>(root), -1, adjacency.offsets[root]});
        while (!stack.empty()) {
            Frame& top = stack.back();
            const auto v = static_cast<std::size_t>(top.v);
            if (top.next < adjacency.offsets[v + 1]) {
                const auto k = static_cast<std::size_t>(top.next++);
                const EdgeId e = adjacency.edge_ids[k];
                if (e == top.via) continue;
                const auto w = static_cast<std::size_t>(adjacency.neighbors[k]);
                if (order[w] < 0) {
                    order[w] = low[w] = counter++;
                    stack.push_back({static_cast<VertexId>(w), e, adjacency.offsets[w]});
                } else {
                    low[v] = std::min(low[v], order[w]);
                }
                continue;
            }
            const Frame done = top;
            stack.pop_back();
            if (!stack.empty()) {
                const auto parent = static_cast<std::size_t>(stack.back().v);
                low[parent] = std::min(low[parent], low[v]);
                if (low[v] > order[parent]) bridge[static_cast<std::size_t>(done.via)] = 1;
            }
        }
    }
    return bridge;
}

} // namespace

double ring_area(const Vec2* begin, const Vec2* end) {
    const auto n = end - begin;
    if (n < 3) return 0.0;
    // Relative to the first point: the shoelace loses no precision far from the origin.
    const Vec2 o = begin[0];
    double twice = 0.0;
    for (std::ptrdiff_t i = 1; i + 1 < n; ++i) {
        const Vec2 a = begin[i] - o, b = begin[i + 1] - o;
        twice += a.x() * b.y() - a.y() * b.x();
    }
    return 0.5 * twice;
}

PlanarFaces planar_faces(const GeometricGraph& g, const PlanarFaceOptions& options) {
    const Walker walk{g};
    const std::size_t n = g.vertex_count();
    const auto half_count = static_cast<HalfEdge>(2 * g.edge_count());

    // Rotation system: half-edges leaving each vertex, counter-clockwise by angle (CSR).
    std::vector<double> angle(static_cast<std::size_t>(half_count));
    std::vector<std::int64_t> offsets(n + 1, 0);
    for (HalfEdge h = 0; h < half_count; ++h) {
        angle[static_cast<std::size_t>(h)] = walk.leaving_angle(h);
        ++offsets[static_cast<std::size_t>(walk.origin(h)) + 1];
    }
    std::partial_sum(offsets.begin(), offsets.end(), offsets.begin());
    std::vector<HalfEdge> rotation(static_cast<std::size_t>(half_count));
    {
        std::vector<std::int64_t> fill(offsets.begin(), offsets.end() - 1);
        for (HalfEdge h = 0; h < half_count; ++h) rotation[static_cast<std::size_t>(fill[static_cast<std::size_t>(walk.origin(h))]++)] = h;
    }
    std::vector<std::int64_t> slot(static_cast<std::size_t>(half_count));
    for (std::size_t v = 0; v < n; ++v) {
        const auto first = rotation.begin() + offsets[v], last = rotation.begin() + offsets[v + 1];
        // Ties (two roads leaving in exactly the same direction) by half-edge id, so the
        // result does not depend on the sort's whims.
        std::sort(first, last, [&](HalfEdge a, HalfEdge b) {
            const double aa = angle[static_cast<std::size_t>(a)], ab = angle[static_cast<std::size_t>(b)];
            return aa < ab || (aa == ab && a < b);
        });
        for (auto it = first; it != last; ++it) slot[static_cast<std::size_t>(*it)] = it - rotation.begin();
    }
    // Arriving by h at v, leave by the half-edge just clockwise of h's twin: the face on the
    // left of h continues on the left of that one.
    auto next = [&](HalfEdge h) {
        const auto v = static_cast<std::size_t>(walk.target(h));
        const std::int64_t begin = offsets[v], degree = offsets[v + 1] - offsets[v];
        const std::int64_t i = slot[static_cast<std::size_t>(h ^ 1)] - begin;
        return rotation[static_cast<std::size_t>(begin + (i - 1 + degree) % degree)];
    };

    // Trace every walk once.
    std::vector<std::int32_t> face_of(static_cast<std::size_t>(half_count), -1);
    std::vector<std::int64_t> walk_offsets{0};
    std::vector<HalfEdge> walks;
    walks.reserve(static_cast<std::size_t>(half_count));
    for (HalfEdge start = 0; start < half_count; ++start) {
        if (face_of[static_cast<std::size_t>(start)] >= 0) continue;
        const auto face = static_cast<std::int32_t>(walk_offsets.size() - 1);
        HalfEdge h = start;
        do {
            face_of[static_cast<std::size_t>(h)] = face;
            walks.push_back(h);
            h = next(h);
        } while (h != start);
        walk_offsets.push_back(static_cast<std::int64_t>(walks.size()));
    }
    const std::size_t traced = walk_offsets.size() - 1;

    PlanarFaces out;
    out.traced_faces = traced;
    const auto vertex_component = vertex_components(g, out.components);

    // Signed area and component of each walk; dangling edges.
    std::vector<double> area(traced);
    std::vector<std::int32_t> component(traced);
    std::vector<std::int32_t> dangling(traced, 0);
    std::vector<Vec2> buffer;
    for (std::size_t f = 0; f < traced; ++f) {
        buffer.clear();
        for (auto k = walk_offsets[f]; k < walk_offsets[f + 1]; ++k) walk.append_points(walks[static_cast<std::size_t>(k)], buffer);
        area[f] = ring_area(buffer.data(), buffer.data() + buffer.size());
        component[f] = vertex_component[static_cast<std::size_t>(walk.origin(walks[static_cast<std::size_t>(walk_offsets[f])]))];
    }
    const std::vector<char> is_bridge = bridges(g);
    for (std::size_t e = 0; e < g.edge_count(); ++e) {
        const auto f = face_of[2 * e];
        if (is_bridge[e]) {
            ++dangling[static_cast<std::size_t>(f)];
            ++out.dangling_edges;
        }
    }

    // The outer face of each component is its most negative walk.
    std::vector<std::int64_t> outer(out.components, -1);
    std::vector<std::int64_t> faces_in(out.components, 0), vertices_in(out.components, 0), edges_in(out.components, 0);
    for (std::size_t f = 0; f < traced; ++f) {
        const auto c = static_cast<std::size_t>(component[f]);
        ++faces_in[c];
        if (outer[c] < 0 || area[f] < area[static_cast<std::size_t>(outer[c])]) outer[c] = static_cast<std::int64_t>(f);
    }
    for (std::size_t v = 0; v < n; ++v) {
        if (vertex_component[v] >= 0) ++vertices_in[static_cast<std::size_t>(vertex_component[v])];
    }
    for (const auto& edge : g.edges) ++edges_in[static_cast<std::size_t>(vertex_component[static_cast<std::size_t>(edge[0])])];
    for (std::size_t c = 0; c < out.components; ++c) {
        const std::int64_t chi = vertices_in[c] - edges_in[c] + faces_in[c];
        if (chi < 2) out.genus += static_cast<std::size_t>((2 - chi) / 2);
    }

    std::vector<char> keep(traced, 1);
    if (!options.keep_outer) {
        for (std::size_t c = 0; c < out.components; ++c) {
            keep[static_cast<std::size_t>(outer[c])] = 0;
            ++out.outer_dropped;
        }
        for (std::size_t f = 0; f < traced; ++f) {
            if (keep[f] && !(area[f] > 0.0)) {
                keep[f] = 0;
                ++out.nonpositive_dropped;
            }
        }
    }

    // Emit the kept faces and their rings.
    std::vector<HalfEdge> kept;
    std::vector<std::vector<HalfEdge>> stack;
    auto emit_ring = [&](const std::vector<HalfEdge>& ring, std::int32_t face) {
        if (ring.empty()) return;
        for (HalfEdge h : ring) walk.append_points(h, out.points);
        out.ring_offsets.push_back(static_cast<std::int64_t>(out.points.size()));
        out.ring_face.push_back(face);
    };
    for (std::size_t f = 0; f < traced; ++f) {
        if (!keep[f]) continue;
        const auto face = static_cast<std::int32_t>(out.face_area.size());
        out.face_area.push_back(area[f]);
        out.face_component.push_back(component[f]);
        out.face_dangling.push_back(dangling[f]);
        for (auto k = walk_offsets[f]; k < walk_offsets[f + 1]; ++k) {
            const HalfEdge h = walks[static_cast<std::size_t>(k)];
            out.face_edges.push_back(static_cast<EdgeId>(h >> 1));
            out.face_edge_reversed.push_back(static_cast<std::uint8_t>(h & 1));
        }
        out.face_edge_offsets.push_back(static_cast<std::int64_t>(out.face_edges.size()));

        if (!options.remove_dangling || dangling[f] == 0) {
            kept.assign(walks.begin() + walk_offsets[f], walks.begin() + walk_offsets[f + 1]);
            emit_ring(kept, face);
            continue;
        }
        // Without the dangling half-edges the walk falls apart into closed rings that nest
        // like parentheses (an inner loop reached over a bridge sits inside the outer ring's
        // sequence): a chain that does not continue the current one opens a new ring, a
        // chain that returns to its start is a finished ring.
        stack.clear();
        stack.emplace_back();
        for (auto k = walk_offsets[f]; k < walk_offsets[f + 1]; ++k) {
            const HalfEdge h = walks[static_cast<std::size_t>(k)];
            if (is_bridge[static_cast<std::size_t>(h >> 1)]) continue;
            auto& chain = stack.back();
            if (!chain.empty() && walk.target(chain.back()) != walk.origin(h)) stack.emplace_back();
            stack.back().push_back(h);
            if (walk.target(h) == walk.origin(stack.back().front())) {
                emit_ring(stack.back(), face);
                stack.pop_back();
                if (stack.empty()) stack.emplace_back();
            }
        }
        // A chain left open can only be the start of the outer ring continued by its end.
        for (auto it = stack.rbegin(); it != stack.rend(); ++it) emit_ring(*it, face);
    }
    return out;
}

} // namespace ggg
