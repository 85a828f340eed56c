#pragma once
// The project's own graph file (.ggraph): JSON, columnar, lossless. docs/file-formats.md
// describes it. Positions are in metres of the local frame, written as the shortest
// decimal that reads back to the same double, so a write/read round trip is exact.
#include <iosfwd>
#include <string>

#include <nlohmann/json_fwd.hpp>

#include "ggg/graph/geometric_graph.hpp"

namespace ggg {

// Version 2 adds vertices.more_rewrites; a graph without them is written as version 1.
inline constexpr int graph_file_version = 2;

nlohmann::json graph_to_json(const GeometricGraph& graph);
// Throws InputError naming the member that is wrong ("edges.u[12]: vertex 99 out of range").
GeometricGraph graph_from_json(const nlohmann::json& document, const std::string& name);

void write_graph_file(const GeometricGraph& graph, const std::string& path);
GeometricGraph read_graph_file(const std::string& path);

} // namespace ggg
