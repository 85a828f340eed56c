#pragma once
// How alike two street networks are, as distributions a planner would look at: vertex
// degree (how streets meet), edge length, street orientation (Boeing's street-orientation
// entropy: 36 bins of 10 degrees, weighted by length, both directions of every street) and
// block (face) area. Each distance is 0 for the same distribution and at most 1:
//  - degree: total variation distance between the degree histograms;
//  - edge length and block area: the Kolmogorov-Smirnov statistic (the largest gap
//    between the two cumulative distributions), which no change of units affects;
//  - orientation: total variation distance between the orientation histograms, after
//    turning one by the multiple of 10 degrees that matches them best, since a grid city
//    turned by 30 degrees has the same street pattern.
// Beside the distributions, the structure a planner reads off a street map: how streets meet
// (the angles at junctions, right angles, streets that go straight through), where they end
// (dead ends), vertices that only bend a street (degree 2), star junctions of five streets or
// more, and how direct the network is (circuity). The junction-angle distance is the
// Kolmogorov-Smirnov statistic of the angles, like the length and area distances.
#include <cmath>
#include <cstddef>
#include <vector>


#include "ggg/graph/geometric_graph.hpp"

namespace ggg {

// The direction in which edge `e` leaves vertex `v`, as the junction angles are measured:
// towards the point 20 m along its polyline (or half-way along a shorter one), so that a kink
// at the junction does not count.
Vec2 leaving_direction(const GeometricGraph& g, EdgeId e, VertexId v);

struct StreetStatistics {
    std::size_t vertices = 0;
    std::size_t edges = 0;
    std::vector<double> degree_histogram;      // share of vertices of degree 0, 1, ... 7, 8 or more
    std::vector<double> edge_lengths_m;        // sorted, one per edge (along its polyline)
    std::vector<double> orientation_histogram; // 36 shares, bin i = bearings [10 i, 10 i + 10) degrees
    double orientation_entropy = 0.0;          // nats; log 4 = 1.386 for a perfect grid, log 36 = 3.584 at most
    // Boeing's orientation order: 1 for a perfect grid, 0 for uniformly spread bearings.
    double orientation_order = 0.0;
    std::vector<double> block_areas_m2;        // sorted, the bounded faces
    // At every junction (three streets or more), the angles between neighbouring streets
    // (sorted around it; they add up to 360), each street's direction taken 20 m along it (or
    // half its length): sorted, degrees.
    std::vector<double> junction_angles_deg;
    std::size_t junctions = 0;
    double right_angle_share = 0.0; // of the junction angles, within 15 degrees of 90
    double through_share = 0.0;     // of the junctions, those where two streets continue within 25 degrees of straight
    // Network distance over straight distance, summed over pairs of vertices (deterministic
    // sample: up to 24 sources, every other vertex of their component as target); 1 for
    // straight streets, more for winding or broken networks. NaN with no pair (one vertex).
    double circuity = std::nan("");
};

StreetStatistics street_statistics(const GeometricGraph& graph);

struct NetworkDistances {
    double degree = 0.0;
    double edge_length = 0.0;
    double orientation = 0.0;
    double block_area = 0.0;
    double junction_angle = 0.0; // reported beside the four, not part of their mean
    // The four averaged: one number for "how alike".
    double mean() const { return (degree + edge_length + orientation + block_area) / 4.0; }
};

NetworkDistances network_distances(const StreetStatistics& a, const StreetStatistics& b);


} // namespace ggg
