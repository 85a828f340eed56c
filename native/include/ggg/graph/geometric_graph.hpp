#pragma once
// The geometric graph every stage of the pipeline works on: vertices with positions in
// metres of a local projected frame, undirected simple edges with road attributes and
// the polyline between their end vertices. Struct of arrays, so that numpy can view the
// columns without copying and the analyzer can scan them without chasing pointers.
// Vertex and edge ids are indices; they stay stable as long as nothing is removed.
#include <array>
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

#include "ggg/graph/road_class.hpp"
#include "ggg/graph/similarity.hpp"

namespace ggg {

using VertexId = std::int32_t;
using EdgeId = std::int32_t;

// Where the local frame sits on the earth: a transverse Mercator centred on the origin.
struct GeoOrigin {
    double lat = 0.0;
    double lon = 0.0;
};

// Attributes of one edge as they come from its OSM way.
struct EdgeAttributes {
    HighwayClass highway = HighwayClass::other;
    std::int8_t oneway = 0;     // 0 two-way, 1 along u->v, -1 along v->u
    std::int16_t lanes = 0;     // 0 = not tagged
    double width_m = std::numeric_limits<double>::quiet_NaN(); // NaN = not tagged
    std::int64_t way_id = 0;    // 0 = no OSM way
    std::string name;
};

// A rewrite pending at a vertex besides the one its own symbol and frame hold. Where rules
// place nonterminals with different frames at one place (the corner two Sierpinski triangles
// share), the place stays one vertex, rewritten once for each of its pending rewrites.
struct PendingRewrite {
    VertexId vertex = -1;
    std::uint32_t symbol = 0;
    Similarity2 frame;
};

class GeometricGraph {
public:
    GeoOrigin origin;

    // Vertices.
    std::vector<Vec2> positions;
    std::vector<std::int64_t> vertex_osm_ids; // 0 where the vertex is not an OSM node
    std::vector<std::uint32_t> symbols;       // 0 = terminal street vertex, k = nonterminal of rule k
    std::vector<Similarity2> frames;          // local frame of the vertex (rules, paper 3.2)
    // Per vertex, the instance of a learned grammar (Grammar::encoding) that rewrites it, -1
    // for none. Optional: empty means none anywhere, so graphs outside a decoding never carry it.
    std::vector<std::int32_t> instances;
    // Rewrites pending at a vertex besides symbols[v] and frames[v], sorted by vertex (stable
    // among one vertex's). Empty unless nonterminals of different rewrites share a place.
    std::vector<PendingRewrite> more_rewrites;

    // Edges.
    std::vector<std::array<VertexId, 2>> edges;
    std::vector<HighwayClass> edge_highway;
    std::vector<std::int8_t> edge_oneway;
    std::vector<std::int16_t> edge_lanes;
    std::vector<double> edge_width_m;
    std::vector<std::int64_t> edge_way_ids;
    std::vector<std::uint32_t> edge_name_index; // into `names`; 0 is the empty name
    std::vector<std::string> names{std::string{}};

    // Edge polylines: edge e runs through geometry[geometry_offsets[e] .. geometry_offsets[e+1]),
    // first point at edges[e][0], last point at edges[e][1].
    std::vector<std::int64_t> geometry_offsets{0};
    std::vector<Vec2> geometry;

    std::size_t vertex_count() const noexcept { return positions.size(); }
    std::int32_t instance_of(VertexId v) const {
        return static_cast<std::size_t>(v) < instances.size() ? instances[static_cast<std::size_t>(v)] : -1;
    }
    std::size_t edge_count() const noexcept { return edges.size(); }
    // The entries of more_rewrites at v, as [first, last).
    std::pair<const PendingRewrite*, const PendingRewrite*> more_rewrites_at(VertexId v) const;

    VertexId add_vertex(const Vec2& position, std::int64_t osm_id = 0);
    // `polyline` includes both end points; an empty one means the straight segment.
    EdgeId add_edge(VertexId u, VertexId v, const EdgeAttributes& attributes,
                    const std::vector<Vec2>& polyline = {});

    // A new vertex at `where` on the edge e = (a, b): e becomes (a, x), keeping its id, and
    // (x, b) is appended with e's attributes. Returns x. A street gets a junction where another
    // meets it; ids of everything else stay. A polyline is split on its piece nearest to
    // `where` (which should lie on it), each half keeping its points. Throws UsageError for an
    // edge out of range or a point that is not finite.
    VertexId split_edge(EdgeId e, const Vec2& where);

    EdgeAttributes edge_attributes(EdgeId e) const;
    std::string_view edge_name(EdgeId e) const { return names[edge_name_index[static_cast<std::size_t>(e)]]; }
    std::size_t geometry_size(EdgeId e) const {
        return static_cast<std::size_t>(geometry_offsets[static_cast<std::size_t>(e) + 1] -
                                        geometry_offsets[static_cast<std::size_t>(e)]);
    }
    const Vec2* geometry_begin(EdgeId e) const {
        return geometry.data() + geometry_offsets[static_cast<std::size_t>(e)];
    }

    double edge_length(EdgeId e) const;
    double total_length() const;

    void reserve(std::size_t vertices, std::size_t edges, std::size_t geometry_points);

private:
    std::uint32_t intern_name(const std::string& name);
    std::unordered_map<std::string, std::uint32_t> name_lookup_;
    std::size_t name_lookup_size_ = static_cast<std::size_t>(-1); // names.size() the lookup was built for
};

// Compressed adjacency (CSR) of a graph: neighbours of v are
// neighbors[offsets[v] .. offsets[v+1]) with the edge ids alongside.
struct Adjacency {
    std::vector<std::int64_t> offsets;
    std::vector<VertexId> neighbors;
    std::vector<EdgeId> edge_ids;

    explicit Adjacency(const GeometricGraph& g);
    std::size_t degree(VertexId v) const {
        return static_cast<std::size_t>(offsets[static_cast<std::size_t>(v) + 1] - offsets[static_cast<std::size_t>(v)]);
    }
};

// Appends to `to` the rewrites pending at vertex v of `from` besides its own, at vertex w of
// `to`. Callers append vertices in order, so `to.more_rewrites` stays sorted.
void copy_more_rewrites(const GeometricGraph& from, VertexId v, GeometricGraph& to, VertexId w);

// What makes a graph "simple" here; empty when the graph is fine, else the first problem.
// Used by tests and as a guard after import.
std::string check_simple(const GeometricGraph& g);

} // namespace ggg
