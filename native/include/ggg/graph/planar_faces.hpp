#pragma once
// The faces of a road graph drawn in the plane: the city blocks between the streets.
//
// Each edge is two half-edges (u->v and v->u). Around every vertex the half-edges leaving it
// are sorted by the direction of their first polyline segment; a face is traced by arriving
// at a vertex and leaving along the next half-edge clockwise from the one we came in on
// (the "next edge by angle" rule). Every half-edge then lies on exactly one face, with the
// face on its left. Bounded faces of a planar graph come out counter-clockwise (positive
// area); each connected component also has one face around it, clockwise (negative area),
// which is the unbounded "outer" face and is dropped by default.
//
// What the traversal does with the shapes real road graphs have:
//  - A dead end, or any bridge of the graph (an edge whose removal disconnects it), has
//    the same face on both sides: the walk goes out along it and comes back. With
//    `remove_dangling` bridges are cut out of the rings, so a block's outline does not run
//    up and down its cul-de-sacs; a street that joins an inner loop to the block's
//    boundary leaves the loop as a separate, clockwise ring of the same face (a hole).
//    The count per face is reported either way, so a caller that insets blocks knows
//    which faces had streets inside. (Where roads cross without a vertex, an edge that
//    is not a bridge can also have one face on both sides; it stays in the ring.)
//  - Components are traced independently; a component lying inside a face of another one
//    (a park's footpath loop inside a block) is not subtracted from that face: the face's
//    area counts it, and its own faces are reported too.
//  - Roads that cross without a shared vertex (bridges, tunnels) make the drawing
//    non-planar. The traversal still partitions the half-edges into closed walks, but a
//    walk can then cross itself or overlap another face, and the Euler characteristic
//    V - E + F of the component drops below 2 (by 2 per "handle"). Faces with a positive
//    signed area are kept as they are; the most negative face per component is taken as
//    the outer one; any other face whose signed area is not positive is dropped and
//    counted in `nonpositive_dropped`.
#include <cstdint>
#include <vector>

#include "ggg/graph/geometric_graph.hpp"

namespace ggg {

struct PlanarFaceOptions {
    // Cut the bridges of the graph (dead ends, ...) out of the face rings.
    bool remove_dangling = true;
    // Keep the outer face of each component (and non-positive faces) instead of dropping it.
    bool keep_outer = false;
};

struct PlanarFaces {
    // Rings: ring r runs through points[ring_offsets[r] .. ring_offsets[r+1]), not closed
    // (the last point is not a copy of the first). Ring r belongs to face ring_face[r].
    std::vector<std::int64_t> ring_offsets{0};
    std::vector<Vec2> points;
    std::vector<std::int32_t> ring_face;

    // Faces, in the order their first half-edge appears (edge 0 forward, backward, edge 1, ...).
    std::vector<double> face_area;            // signed area of the whole boundary walk (m^2)
    std::vector<std::int32_t> face_component; // connected component of the face's edges
    std::vector<std::int32_t> face_dangling;  // bridges (dead ends, ...) inside the face
    // The boundary walk of face f: half-edges face_edges[face_edge_offsets[f] .. +1), each an
    // edge id with face_edge_reversed = 1 when walked from edges[e][1] to edges[e][0].
    std::vector<std::int64_t> face_edge_offsets{0};
    std::vector<EdgeId> face_edges;
    std::vector<std::uint8_t> face_edge_reversed;

    // Counts over the whole graph.
    std::size_t components = 0;         // connected components with at least one edge
    std::size_t traced_faces = 0;       // closed walks found, before any was dropped
    std::size_t outer_dropped = 0;      // one per component unless keep_outer
    std::size_t nonpositive_dropped = 0;
    std::size_t dangling_edges = 0;     // bridges of the graph: each lies inside one face
    // Sum over components of (2 - (V - E + F)) / 2: 0 for a plane drawing; more where roads
    // cross without a vertex (bridges, tunnels), seen by the traversal as handles.
    std::size_t genus = 0;

    std::size_t face_count() const noexcept { return face_area.size(); }
    std::size_t ring_count() const noexcept { return ring_face.size(); }
};

PlanarFaces planar_faces(const GeometricGraph& g, const PlanarFaceOptions& options = {});

// Signed area (shoelace) of a closed ring given without its closing point.
double ring_area(const Vec2* begin, const Vec2* end);

} // namespace ggg
