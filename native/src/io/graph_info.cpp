#include "ggg/io/graph_info.hpp"

#include <algorithm>
#include <limits>
#include <map>

namespace ggg {

nlohmann::json graph_info(const GeometricGraph& g) {
    double xmin = std::numeric_limits<double>::infinity(), ymin = xmin;
    double xmax = -xmin, ymax = -xmin;
    for (const Vec2& p : g.geometry) {
        xmin = std::min(xmin, p.x());
        ymin = std::min(ymin, p.y());
        xmax = std::max(xmax, p.x());
        ymax = std::max(ymax, p.y());
    }
    if (g.geometry.empty()) xmin = ymin = xmax = ymax = 0;
    std::map<std::string, std::size_t> classes;
    for (HighwayClass c : g.edge_highway) ++classes[std::string(highway_name(c))];
    return {
        {"vertices", g.vertex_count()},
        {"edges", g.edge_count()},
        {"total_length_m", g.total_length()},
        {"bbox_m", {xmin, ymin, xmax, ymax}},
        {"origin_latlon", {g.origin.lat, g.origin.lon}},
        {"classes", classes},
    };
}

} // namespace ggg
