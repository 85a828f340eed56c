#pragma once
// Synthetic road graphs for the analyzer's tests: street grids (optionally jittered and
// rotated) and a random street graph with a motif planted into it.
#include <cstdint>
#include <set>
#include <vector>

#include "ggg/analysis/pattern.hpp"
#include "ggg/graph/geometric_graph.hpp"

namespace ggg::test {

struct GridOptions {
    int n = 12;              // n x n vertices
    double spacing = 100.0;  // metres
    double jitter = 0.0;     // Gaussian sigma as a fraction of the spacing
    double angle_rad = 0.0;  // rotation of the whole grid
    std::uint64_t seed = 1;
};
GeometricGraph make_grid(const GridOptions& o);

// The vertex sets of the unit squares of make_grid's graph, each sorted.
std::set<std::vector<VertexId>> grid_squares(int n);

// Sorted vertex sets of an isogroup's occurrences.
std::set<std::vector<VertexId>> occurrence_sets(const Isogroup& group);

// A motif planted `scales.size()` times into a jittered street grid with some streets
// removed: each copy at a random rotation, with the given size (RMS radius in metres),
// in a hole cut into the grid and tied to it by two streets. The copies' vertex sets are
// returned in `copies`.
struct PlantedMotif {
    GeometricGraph graph;
    Pattern motif;
    std::vector<std::vector<VertexId>> copies;
};
PlantedMotif plant_motif(const std::vector<double>& scales, std::uint64_t seed);

} // namespace ggg::test
