#pragma once
// The spatial index of the library: Boost.Geometry's R-trees over points and boxes of the
// plane, in the graph's metres (or of more dimensions, for values other than positions). One
// definition for every stage that asks "which vertices, which street pieces, which patterns
// are near here", so that they index and query alike.
#include <algorithm>
#include <cstddef>
#include <utility>

#include <boost/geometry.hpp>
#include <boost/geometry/index/rtree.hpp>

#include "ggg/graph/geometric_graph.hpp"

namespace ggg::spatial {

namespace bg = boost::geometry;
namespace bgi = boost::geometry::index;

using Point = bg::model::point<double, 2, bg::cs::cartesian>;
using Box = bg::model::box<Point>;
// 16 entries a node, R* splits: the indexes here are mostly bulk-loaded and queried often.
template <class Value>
using RTree = bgi::rtree<Value, bgi::rstar<16>>;
// An index filled one entry at a time, between its queries: quadratic splits, which cost
// less per insertion than R*'s reinsertions.
template <class Value>
using IncrementalRTree = bgi::rtree<Value, bgi::quadratic<16>>;
// Points and boxes of more dimensions, for an index over values other than a position (the
// isogroup detection files its patterns by six numbers of their shape).
template <std::size_t Dimensions>
using PointIn = bg::model::point<double, Dimensions, bg::cs::cartesian>;
template <std::size_t Dimensions>
using BoxIn = bg::model::box<PointIn<Dimensions>>;
// The usual entries: a vertex at its point, an edge (or a piece of one) by its box.
using VertexEntry = std::pair<Point, VertexId>;
using EdgeEntry = std::pair<Box, EdgeId>;

inline Point point(const Vec2& p) { return {p.x(), p.y()}; }

// The square of half-side r around p.
inline Box around(const Vec2& p, double r) { return {{p.x() - r, p.y() - r}, {p.x() + r, p.y() + r}}; }

// The box of segment pq, grown by `margin` on every side.
inline Box around(const Vec2& p, const Vec2& q, double margin = 0.0) {
    return {{std::min(p.x(), q.x()) - margin, std::min(p.y(), q.y()) - margin},
            {std::max(p.x(), q.x()) + margin, std::max(p.y(), q.y()) + margin}};
}

// The box of an edge's whole polyline.
inline Box edge_box(const GeometricGraph& g, EdgeId e) {
    const Vec2* p = g.geometry_begin(e);
    Box box(point(p[0]), point(p[0]));
    for (std::size_t i = 1; i < g.geometry_size(e); ++i) bg::expand(box, point(p[i]));
    return box;
}

} // namespace ggg::spatial
