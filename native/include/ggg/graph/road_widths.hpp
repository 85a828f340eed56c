#pragma once
// How wide each road of a graph is: the one rule behind the imported road surfaces, the 3-D
// city and the benchmarks, so that the CLI, Python and Blender draw the same roads.
#include <vector>

#include "ggg/graph/geometric_graph.hpp"

namespace ggg {

struct RoadWidthRule {
    // A road without a `width` tag but with `lanes` is this wide per lane.
    double lane_width_m = 3.25;
    // Width of each class, by class code (size highway_class_count); empty = the library's
    // defaults (highway_default_width).
    std::vector<double> class_widths_m;
};

// Width in metres of each edge: its `width` tag where that is a positive number, else its
// lanes times the lane width, else the width of its class. Throws UsageError for a class table
// of the wrong size or a width that is not a positive number.
std::vector<double> road_widths(const GeometricGraph& g, const RoadWidthRule& rule = {});

} // namespace ggg
