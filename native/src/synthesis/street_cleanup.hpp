#pragma once
// The last stage of growth (synthesis/growth.hpp), private to it: the grown streets tidied
// once everything is placed. Each takes the graph with the base first (base_vertices,
// base_edges: what growth started from, never changed) and the grown streets after it.
#include <cstddef>
#include <random>
#include <vector>

#include "ggg/graph/geometric_graph.hpp"
#include "ggg/graph/road_class.hpp"

namespace ggg::growth_detail {

// A street to keep, between two vertices of the graph as it was.
struct Street {
    VertexId a = -1, b = -1;
    EdgeAttributes attributes;
    std::vector<Vec2> polyline;
};

// Street e of g as it is.
Street street_of(const GeometricGraph& g, EdgeId e);

// The graph again with the vertices not dropped (the base first, unchanged; grown ids shift
// down) and these streets, given in the old vertex ids.
GeometricGraph rebuilt(const GeometricGraph& g, const std::vector<char>& drop_vertex, const std::vector<Street>& streets);

// The last guard of the rule that no two streets cross without an intersection: a grown street
// that crosses another street is taken out again, the newer of two grown ones. Returns how many.
std::size_t remove_crossing_streets(GeometricGraph& g, std::size_t base_vertices, std::size_t base_edges);

// Grown junctions in `region` thinned to the city's density (`junction_density` junctions a
// square metre, measured around the region): where more are grown, rungs are taken out (a
// minor grown street between two grown T-junctions, the stem of both, with another way between
// its ends near by), in the most crowded places first (the most junctions within `radius`
// metres, none where there are no more than the city's), the shortest there first. Their
// T's become bends, which dissolve_bends then dissolves. Returns how many went.
std::size_t thin_junctions(GeometricGraph& g, std::size_t base_vertices, std::size_t base_edges, const std::vector<Vec2>& region,
                           double junction_density, double radius);

// Each piece of grown streets joined to no street of the base (a region no street of the base
// reaches is grown from a rule placed in its middle) gets a street to the city: the shortest
// one, no longer than `reach` metres, from one of its vertices to one of the city's, that
// crosses no street and meets the streets at both its ends at 30 degrees or more. A base with
// no streets has no city to join. Returns how many were joined.
std::size_t join_grown_islands(GeometricGraph& g, std::size_t base_vertices, std::size_t base_edges, double reach);

// Grown T-junctions in `region` (of grown streets only) that are a little askew, 15 to 35
// degrees off a right angle, slid along their bar until the stem meets it square, as long as
// a larger share of the grown T's (square or askew) is askew than of the city's around it.
// A junction moves 40 m at most (four fifths of its street's piece on that side), and only where
// its streets then cross nothing, make no corner sharper than 30 degrees where their first pieces
// end (or sharper than it was), and it comes within 5 m of no other vertex. Returns how many
// were squared.
std::size_t square_junctions(GeometricGraph& g, std::size_t base_vertices, std::size_t base_edges, const std::vector<Vec2>& region);

// A grown vertex where two grown streets of one class meet and nothing else is no junction:
// the two become one street through it (a bend of its polyline). Returns how many went.
std::size_t dissolve_bends(GeometricGraph& g, std::size_t base_vertices, std::size_t base_edges);

// A city's roundabouts (growth_roundabouts.cpp): how many of the places where its streets meet
// near the region are one, and the radius of each (sorted). Told by their one-way streets,
// which a learned grammar does not keep: these are the base's.
struct CityRoundabouts {
    double share = 0.0;      // of the junctions of other streets
    double main_share = 0.0; // of the junctions a main road meets
    std::vector<double> radii_m;
    // The centres of all of them, and how close the city puts two: the tenth percentile of the
    // distance from each to the nearest other (0 where it has fewer than two).
    std::vector<Vec2> centres;
    double spacing_m = 0.0;
    int circulation = 1; // most are driven round anticlockwise (1, right-hand traffic) or clockwise (-1)
};

CityRoundabouts roundabouts_of(const GeometricGraph& city, const std::vector<Vec2>& region);

// Grown junctions (of grown streets only, inside the region) made roundabouts as often as the
// city's junctions are ones, each of the radius of one of the city's: the junction gives way to
// a ring of one-way arcs that its streets meet. Where there is no room (another street within
// half the radius of the ring, an arm too short, or two arms closer than 30 degrees), or where
// another roundabout, grown or the city's, is closer than the city puts two, another junction
// is tried. Returns how many were made.
std::size_t make_roundabouts(GeometricGraph& g, std::size_t base_vertices, std::size_t base_edges, const std::vector<Vec2>& region,
                             const CityRoundabouts& city, std::mt19937_64& rng);

// The city's share of vertices where only two streets meet (most maps split a street wherever
// one of its tags changes, so that a share of a city's vertices are such bends), measured on
// the base around `region` (within `radius` of its centre), and the length of its short edges
// (their 10th percentile, 0 when there are none).
struct CityBends {
    double share = 0.0;
    double short_edge_m = 0.0;
};
CityBends bends_of(const GeometricGraph& base, const Vec2& centre, double radius);

// Grown streets split at points along them, as often as the city's streets are: until the grown
// vertices have the city's share of bends (vertices of two streets). Each split point lies on a
// grown street, at least `bends.short_edge_m` from its ends and from the other splits; longer
// streets are split more often. Returns how many vertices were added.
std::size_t split_streets(GeometricGraph& g, std::size_t base_vertices, std::size_t base_edges, const CityBends& bends,
                          std::mt19937_64& rng);


// Whether the polyline p[0..n) neither crosses nor folds back onto itself: split there, its
// two pieces would cross each other.
bool simple_line(const Vec2* p, std::size_t n);

// Each edge e split at the arc lengths at[e] along its polyline (sorted in place, each inside
// the edge), with a new vertex at each; the other edges as they were (the graph is rebuilt, so
// edge ids change; vertex ids do not). Returns the new vertices, edge by edge, in the order of
// their points along it.
std::vector<std::vector<VertexId>> split_edges_at(GeometricGraph& g, std::vector<std::vector<double>>& at);

// A city's dead-end streets, as growth makes them (growth_cul_de_sacs.cpp): in the blocks near
// the region, how many dead ends each block holds by its area, and how long the streets to them
// are (from the dead end to the first junction). Cul-de-sacs, courts and closes are where a
// city's blocks are too large for loops alone: a grid's small blocks have none, a suburb's
// large ones several.
struct CityCulDeSacs {
    std::vector<std::pair<double, int>> blocks; // (area m^2, dead ends in it), by area
    std::vector<double> lengths_m;              // the dead-end streets' lengths, sorted
    double across_share = 0.0; // of them, those that go on across a crossing from a street there
    HighwayClass highway = HighwayClass::residential; // their most common class
};
CityCulDeSacs cul_de_sacs_of(const GeometricGraph& city, const std::vector<Vec2>& region);

// Dead-end streets added to the grown blocks (inside the region), each as many as the city's
// blocks of about its area hold on average, less those it has: each leaves a grown street at a
// right angle into the block (or goes on across a T-junction from its third street, as often
// as the city's go on across a crossing), as long as one of the city's, and keeps clear of
// every other street. Returns how many were added.
std::size_t make_cul_de_sacs(GeometricGraph& g, std::size_t base_vertices, std::size_t base_edges, const std::vector<Vec2>& region,
                             const CityCulDeSacs& city, std::mt19937_64& rng);

} // namespace ggg::growth_detail
