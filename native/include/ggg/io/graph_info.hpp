#pragma once
// The summary `ggg info` prints and Graph.info() returns.
#include <nlohmann/json.hpp>

#include "ggg/graph/geometric_graph.hpp"

namespace ggg {

// {"vertices", "edges", "total_length_m", "bbox_m", "origin_latlon", "classes"}
nlohmann::json graph_info(const GeometricGraph& graph);

} // namespace ggg
