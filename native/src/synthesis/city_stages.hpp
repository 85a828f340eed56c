#pragma once
// The stages of the city layout (synthesis/city_layout.hpp), private to it: the road pieces
// (road_pieces.cpp), each face's block, yard and buildings (city_blocks.cpp) and the
// buildings' heights (building_heights.cpp). city_layout.cpp runs them.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include <clipper.hpp>

#include "ggg/graph/geometric_graph.hpp"
#include "ggg/graph/spatial_index.hpp"
#include "ggg/synthesis/city_layout.hpp"

namespace ggg::city_detail {

namespace bg = spatial::bg;
namespace bgi = spatial::bgi;
namespace cl = ClipperLib;

using spatial::Box;
using spatial::VertexEntry;
using PieceEntry = std::pair<Box, std::size_t>;

// Clipper works on integers: millimetres, relative to the graph's bounding-box centre.
constexpr double kScale = 1000.0;

struct Frame {
    Vec2 centre = Vec2::Zero();
    cl::IntPoint to_int(const Vec2& p) const {
        return {static_cast<cl::cInt>(std::llround((p.x() - centre.x()) * kScale)),
                static_cast<cl::cInt>(std::llround((p.y() - centre.y()) * kScale))};
    }
    Vec2 to_metres(const cl::IntPoint& p) const {
        return {static_cast<double>(p.X) / kScale + centre.x(), static_cast<double>(p.Y) / kScale + centre.y()};
    }
    cl::Path path(const Vec2* begin, const Vec2* end) const {
        cl::Path out;
        out.reserve(static_cast<std::size_t>(end - begin));
        for (auto p = begin; p != end; ++p) out.push_back(to_int(*p));
        return out;
    }
};

Box box_of(const Vec2* begin, const Vec2* end);

// Turns `ring` counter-clockwise, as PolygonSet keeps its polygons.
void ccw(std::vector<Vec2>& ring);

// Where each edge's and vertex's road pieces are.
struct PieceIndex {
    std::vector<std::size_t> edge_begin; // pieces of edge e: [edge_begin[e], edge_begin[e+1])
    std::vector<std::int64_t> vertex_disc; // piece of the disc at v, -1 for none
    std::vector<Box> boxes;                // bounding box of every piece
};

// The road pieces: segment rectangles, bevel triangles at bends, discs at vertices.
void road_pieces(const GeometricGraph& g, const std::vector<double>& half, int sides, CityLayout& out, PieceIndex& where);

// Edges that cross another edge without a shared vertex (bridges, tunnels): their pieces are
// cut out of every block they pass over.
std::vector<char> crossing_edges(const GeometricGraph& g);

// What every face's work reads.
struct Shared {
    const GeometricGraph& g;
    const PlanarFaces& faces;
    const std::vector<std::size_t>& first_ring;
    const PolygonSet& roads;
    const PieceIndex& where;
    const Adjacency& adjacency;
    const spatial::RTree<VertexEntry>& vertices;
    const spatial::RTree<PieceEntry>& crossing_pieces;
    const std::vector<RoadPiece>& piece_kind;
    const std::vector<cl::Paths>& outlines; // union of each edge's segment and bend pieces
    const Frame& frame;
    const CityLayoutOptions& options;
};

struct FaceResult {
    PolygonSet blocks, yards, buildings;
    std::vector<double> depth;
    bool empty = false;
};

// The block, yard and buildings of face f. stamp, edge_stamp and pieces_in are the calling
// thread's scratch, kept from face to face.
void build_face(const Shared& s, std::size_t f, std::vector<std::int32_t>& stamp, std::vector<std::int32_t>& edge_stamp,
                std::vector<std::size_t>& pieces_in, FaceResult& out);

// Floors grow towards the middle of the network and in small blocks (a dense core, low-rise
// suburbs), vary from lot to lot, and one lot in a hundred of the densest blocks is a tower.
void building_heights(const GeometricGraph& g, const CityLayoutOptions& o, CityLayout& out);

} // namespace ggg::city_detail
