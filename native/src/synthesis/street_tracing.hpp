#pragma once
// Streets continued into a region the way the city's own streets run: the first stage of
// growth (growth.hpp). Every street that reaches the region is traced on into it, one street
// at a time, and each new junction takes the shape of one of the city's own junctions: how
// many streets leave it, at which angles, how long they are, how they bend and of which class
// they are. The city here is the grammar's (a learned grammar decodes to it), so a district
// grows in the style its grammar was learned from.
//
// Parish & Müller's local constraints join the traced streets to what is there instead of
// dropping them: a street that ends near a junction ends at it, one that ends near a street
// meets it in a T-junction, one that crosses a street stops there in an intersection. Main
// roads are traced first, then the streets between them. No junction gets more than four
// streets, and no street leaves the region except to join a street outside it.
#include <cstddef>
#include <optional>
#include <random>
#include <vector>

#include "ggg/graph/geometric_graph.hpp"
#include "ggg/graph/spatial_index.hpp"
#include "ggg/progress.hpp"

namespace ggg::growth_detail {

struct TracingReport {
    std::size_t seeds = 0;        // streets of the base that reach the region and were traced on
    std::size_t streets = 0;      // streets added
    std::size_t joined = 0;       // streets that ended at a junction already there
    std::size_t t_junctions = 0;  // streets that ended on a street, split there
    std::size_t dropped = 0;      // streets that fitted nowhere
    std::size_t dense = 0;        // streets not traced: the streets around were as dense as the city's
    std::size_t across = 0;       // streets joined straight across to a street that faces them
    std::size_t avenues = 0;      // main roads running straight across the grid laid on until two meet
    std::size_t crossed = 0;      // streets sent on across a street they met, as often as the city's junctions are crossings
    std::size_t joined_offsets = 0;   // grown offset crossings (beyond the city's share) made one crossing
    std::size_t closed_corners = 0;   // grown corners made T-junctions: one of their streets went on across
    std::size_t offset_crossings = 0; // crossings made two T-junctions a few metres apart, as often as the city has them
    std::size_t empty_ground = 0; // streets opened into ground farther from every street than the city's is
    std::size_t junction_islands = 0; // short streets cutting the corner of a T-junction, as often as the city has them
    // What tracing measured of the city, for the rules placed after it: metres of street per
    // square metre of the ground next to the region (0: too little ground to say), and the
    // typical street's length.
    double density = 0.0;
    double junction_density = 0.0; // junctions (three streets or more) per square metre there
    double typical_m = 0.0;
};

struct TracingSettings {
    double border_m = 0.0;            // a base street this close to the region reaches it
    std::size_t max_vertices = 0;     // the whole graph, base included
    double min_block_m2 = 0.0;        // no street closes a block smaller than this
    // Blocks smaller than `usual_block_m2` (and not below `min_block_m2`) are closed only as
    // often as the city has them: at most this share of the blocks that tracing closes.
    double usual_block_m2 = 0.0;
    double small_block_share = 0.0;
    // The city, or its streets next to the region, run on a grid (most of their length along
    // two perpendicular directions): only then are streets joined straight across the region
    // (join_across).
    bool grid_city = false;
    // No street of the base reaches the region (a district drawn apart from the city): the
    // ground beside it is the city's edge, sparser than any part of the city, so its streets
    // are held to the density of the whole city instead.
    bool no_street_reaches = false;
    // The grid the city's streets around the region run on (radians, modulo 90 degrees), if
    // they do: the street that reaches such a district runs along it.
    std::optional<double> grid_angle;
};

// How tracing, and the rules placed after it, hold the streets they add to the city's density
// (TracingReport::density): the metres of street in a disc two typical streets across, counting
// each straight piece whose middle lies in it. The piece ab:
inline double piece_within(const Vec2& a, const Vec2& b, const Vec2& centre, double r) {
    return (0.5 * (a + b) - centre).norm() <= r ? (b - a).norm() : 0.0;
}
// ... and the streets of `g` (found through `segments`, an index of its edges' boxes).
double street_length_within(const GeometricGraph& g, const spatial::RTree<spatial::EdgeEntry>& segments, const Vec2& centre, double r);
// ... and its junctions (vertices of three streets or more) in the same disc, found through
// `vertices` (an index of its vertices); `around[v]` lists what meets at v (streets or
// neighbours: only its size counts).
template <typename Around>
std::size_t junctions_within(const GeometricGraph& g, const spatial::RTree<spatial::VertexEntry>& vertices, const Around& around,
                             const Vec2& centre, double r) {
    std::size_t junctions = 0;
    for (auto it = vertices.qbegin(spatial::bgi::intersects(spatial::around(centre, r))); it != vertices.qend(); ++it) {
        const auto v = static_cast<std::size_t>(it->second);
        junctions += around[v].size() >= 3 && (g.positions[v] - centre).norm() <= r;
    }
    return junctions;
}

// Adds the traced streets to `g` (whose first `base_vertices` vertices are the base). `city`
// is the example (the grammar's city); nothing is traced when it has no junctions to learn
// from or no street reaches the region.
TracingReport trace_streets(GeometricGraph& g, std::size_t base_vertices, const GeometricGraph& city,
                            const std::vector<Vec2>& region, const TracingSettings& settings, std::mt19937_64& rng,
                            const ProgressCallback& progress);

} // namespace ggg::growth_detail
