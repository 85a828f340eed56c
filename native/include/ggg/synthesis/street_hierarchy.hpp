#pragma once
// The street hierarchy across grown streets. Rules are learned pieces of one kind of street
// (mostly residential blocks), so a region grown from them would stop every main road at
// its border. Here a main road that reaches the grown streets is continued through them to
// another main road that reaches them, as directly as they allow, and the grown streets on
// the way take the class of the less important of the two: a primary road of one city meets
// a primary road of the other across the seam of a stitch (paper Fig. 18), a secondary road
// crosses a grown district instead of ending at it. Where the grown streets offer no such
// route between two main roads that face each other, a straight main road joins them, and
// each grown street it crosses gets an intersection there. A main road that ends at the region
// and is joined to none of them goes straight on to the first grown street ahead (within
// max_connector_m), and meets it in a T-junction.
#include <cstddef>
#include <vector>

#include "ggg/graph/geometric_graph.hpp"

namespace ggg {

struct HierarchyOptions {
    // A route may be at most this many times longer than the straight line between its two
    // main roads; a longer one would be a main road nobody drives.
    double max_detour = 1.6;
    // Two main roads that face each other (each heading within max_connector_turn_deg of
    // the other) no farther apart than this, with no route through the grown streets, are
    // joined by a straight main road that crosses the grown streets at new intersections;
    // 0 = never. It never crosses a street the growth started from, and keeps clearance_m
    // from every vertex it does not pass through.
    double max_connector_m = 1000.0;
    double max_connector_turn_deg = 40.0;
    double clearance_m = 8.0;
    // The region the streets were grown into, if known (a simple polygon, not closed): then a
    // main road that ends in it (or within border_m of it; < 0: 5 % of the region's size, as
    // for growth) counts even where no grown street
    // reaches it, and a straight connector's middle must lie in it.
    std::vector<Vec2> region;
    double border_m = -1.0;
};

struct HierarchyReport {
    std::size_t main_roads = 0;     // main roads that reach the grown streets
    std::size_t routes = 0;         // of those, pairs joined through them
    std::size_t raised_streets = 0; // grown streets that took a main road's class
    std::size_t connectors = 0;        // pairs joined by a straight new main road
    std::size_t connector_streets = 0; // its pieces between intersections
    std::size_t intersections = 0;     // grown streets it crossed, split where it crosses
    std::size_t extensions = 0;        // main roads that ended at the region, joined to nothing, continued straight to a grown street
};

// Edges from `first_new_edge` on are the grown streets, the ones before are the streets they
// grew from; only grown streets change class (their width and lanes become untagged, so they
// follow the class), and new vertices and edges (connectors) come after the others. A main road is a street of class motorway to unclassified (not a link)
// that is more important than the grown streets' most common class. Main roads are joined
// most important first; each takes part in one route at most, and two main roads already
// joined by one street are not joined again. Deterministic.
HierarchyReport continue_hierarchy(GeometricGraph& g, EdgeId first_new_edge, const HierarchyOptions& options = {});

} // namespace ggg
