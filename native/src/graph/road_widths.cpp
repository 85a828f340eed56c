#include "ggg/graph/road_widths.hpp"

#include <cmath>
#include <string>

#include "ggg/error.hpp"
#include "ggg/graph/road_class.hpp"

namespace ggg {

std::vector<double> road_widths(const GeometricGraph& g, const RoadWidthRule& rule) {
    if (!(rule.lane_width_m > 0) || !std::isfinite(rule.lane_width_m)) {
        throw UsageError("lane width: must be a positive number of metres, got " + std::to_string(rule.lane_width_m));
    }
    if (!rule.class_widths_m.empty() && rule.class_widths_m.size() != static_cast<std::size_t>(highway_class_count)) {
        throw UsageError("class widths: need one per road class (" + std::to_string(highway_class_count) + "), got " +
                         std::to_string(rule.class_widths_m.size()));
    }
    for (const double w : rule.class_widths_m) {
        if (!(w > 0) || !std::isfinite(w)) throw UsageError("class widths: each must be a positive number of metres, got " + std::to_string(w));
    }
    std::vector<double> widths(g.edge_count());
    for (std::size_t e = 0; e < g.edge_count(); ++e) {
        const double tagged = e < g.edge_width_m.size() ? g.edge_width_m[e] : std::nan("");
        const int lanes = e < g.edge_lanes.size() ? g.edge_lanes[e] : 0;
        const auto c = g.edge_highway[e];
        if (std::isfinite(tagged) && tagged > 0) widths[e] = tagged;
        else if (lanes > 0) widths[e] = lanes * rule.lane_width_m;
        else widths[e] = rule.class_widths_m.empty() ? highway_default_width(c) : rule.class_widths_m[static_cast<std::size_t>(c)];
    }
    return widths;
}

} // namespace ggg
