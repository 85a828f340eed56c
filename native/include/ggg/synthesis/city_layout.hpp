#pragma once
// The ground plan of a 3-D city on a road graph: road surfaces, the kerb outline of every
// block, the yard inside its sidewalk, and building footprints along the streets.
//
// Everything is built from one set of convex "road pieces" so that the parts fit without
// gaps or overlaps: a rectangle of the road's width per polyline segment, a mitre on the
// outer side of every bend (a disc for a bend sharper than 120 degrees), and a disc (a polygon around the circle) of the widest
// road's half width at every vertex. The road surface is these pieces; a block is its
// planar face (planar_faces.hpp) minus every piece that reaches into it, so dead ends,
// roads of other components and roads that cross without a vertex (bridges) are all cut
// out the same way. The yard is the block inset by the sidewalk; buildings fill a band of
// the yard along its outline, cut into lots of seeded frontages. Polygon operations use
// Clipper (integer coordinates, millimetres), which is exact and does not fail on the
// touching and degenerate rings that real road graphs produce.
//
// Blocks of faces that overlap (only where roads cross without a vertex) may overlap too;
// nothing else does.
#include <cstdint>
#include <vector>

#include "ggg/graph/geometric_graph.hpp"
#include "ggg/graph/planar_faces.hpp"
#include "ggg/progress.hpp"

namespace ggg {

struct CityLayoutOptions {
    // Half the paved width of each edge in metres (size edge_count()); empty = half of
    // road_widths(g) (graph/road_widths.hpp: its width tag, else lanes, else its class).
    std::vector<double> half_widths;
    double sidewalk_m = 3.0;        // kerb to building line
    double lot_min_m = 9.0;         // frontage of a lot along the street
    double lot_max_m = 26.0;
    double depth_min_m = 10.0;      // depth of the building band behind the building line
    double depth_max_m = 18.0;
    double gap_m = 0.6;             // between neighbouring buildings
    double min_building_area_m2 = 30.0;
    // Faces larger than this are fields, forests or parks between distant roads, not city
    // blocks: they get kerbs and a yard but no buildings.
    double max_block_area_m2 = 250000.0;
    // A yard smaller than this is a traffic island or the middle of a roundabout: no buildings.
    double min_yard_area_m2 = 400.0;
    int disc_sides = 12;            // sides of the polygon around a junction
    double floor_height_m = 3.2;    // building heights are whole floors of this, plus a roof
    std::uint64_t seed = 1;         // lot frontages, band depths and building heights
    unsigned threads = 0;           // 0 = hardware concurrency
};

// Simple polygons without holes, counter-clockwise, not closed: polygon i runs through
// points[offsets[i] .. offsets[i+1]); owner[i] says what it belongs to.
struct PolygonSet {
    std::vector<std::int64_t> offsets{0};
    std::vector<Vec2> points;
    std::vector<std::int32_t> owner;

    std::size_t size() const noexcept { return owner.size(); }
    void add(const std::vector<Vec2>& ring, std::int32_t owner_id);
};

enum class RoadPiece : std::uint8_t { segment = 0, bend = 1, junction = 2 };

struct CityLayout {
    PolygonSet roads;                  // owner = edge (for a junction: its most important edge)
    std::vector<RoadPiece> road_piece; // per road polygon
    PolygonSet blocks;                 // kerb outlines; owner = face of `faces`
    PolygonSet yards;                  // blocks inset by the sidewalk; owner = face
    PolygonSet buildings;              // footprints; owner = face
    std::vector<double> building_depth; // depth of the band the lot was cut from (m)
    // Per building: its height (m) and a facade tint in [0, 1). Floors grow towards the middle
    // of the network and in small blocks (4 in blocks under 0.3 ha, 1.5 over 25 ha, up to 1.6
    // times that in the middle), vary from lot to lot, and one lot in a hundred of the densest
    // blocks is a tower; seeded.
    std::vector<double> building_height_m;
    std::vector<double> building_tint;
    PlanarFaces faces;                 // the faces the blocks come from
    std::size_t empty_blocks = 0;      // faces that roads cover completely (islands)
    std::size_t crossing_edges = 0;    // edges crossing another without a vertex (bridges, tunnels)
};

CityLayout city_layout(const GeometricGraph& g, const CityLayoutOptions& options = {},
                       const ProgressCallback& progress = {});

} // namespace ggg
