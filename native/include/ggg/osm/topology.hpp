#pragma once
// From polylines to a simple road graph. Readers (OSM, GeoJSON) hand over "ways": sequences
// of nodes where a node is one place (nodes at the same location are already one node).
// Intersections and way ends become vertices, the degree-2 runs between them become one
// edge that keeps its polyline. The result has no self-loops, parallel or zero-length
// edges, yet keeps every distinct road segment once:
//  - a closed way that meets the network at one vertex (a roundabout, a cul-de-sac loop)
//    is kept as a cycle by turning two of its shape nodes into vertices;
//  - two different roads between the same two vertices are kept apart by turning a shape
//    node of the curvier one into a vertex; identical pieces are stored once.
// So the total length equals the length of the distinct segments of the input.
#include <cstdint>
#include <vector>

#include "ggg/graph/geometric_graph.hpp"
#include "ggg/progress.hpp"

namespace ggg {

struct TopologyInput {
    std::vector<Vec2> node_positions;        // metres
    std::vector<std::int64_t> node_osm_ids;  // 0 = none
    std::vector<std::int64_t> way_offsets{0}; // way w = way_nodes[way_offsets[w] .. way_offsets[w+1])
    std::vector<std::int32_t> way_nodes;
    std::vector<EdgeAttributes> way_attributes;

    void add_way(const std::vector<std::int32_t>& nodes, EdgeAttributes attributes);
    std::size_t way_count() const noexcept { return way_attributes.size(); }
};

struct TopologyOptions {
    // Keep every node as a vertex (each segment becomes an edge).
    bool keep_shape_nodes = false;
    // Merge vertices closer than this (metres) into their centroid: clusters grow around
    // seed vertices (densest first), each member within this distance of its seed, never by
    // chains of neighbours. Parallel roads that then run within twice this distance of each
    // other (dual carriageways) become one edge.
    // 0 turns consolidation off.
    double consolidate_m = 0.0;
};

// What the builder did, for reports and tests.
struct TopologyReport {
    std::size_t duplicate_pieces = 0;      // identical pieces stored once
    std::size_t promoted_shape_nodes = 0;  // shape nodes made vertices to keep the graph simple
    std::size_t dropped_degenerate = 0;    // pieces that collapsed (consolidation)
    std::size_t merged_parallel = 0;       // parallel roads merged by consolidation
    std::size_t consolidated_vertices = 0; // vertices absorbed into a neighbour by consolidation
};

GeometricGraph build_graph(const TopologyInput& input, GeoOrigin origin, const TopologyOptions& options,
                           TopologyReport* report = nullptr, const ProgressCallback& progress = {});

} // namespace ggg
