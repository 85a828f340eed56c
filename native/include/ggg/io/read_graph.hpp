#pragma once
// One entry point for every command that reads a graph: OSM files, GeoJSON and .ggraph,
// chosen by the file name and, for JSON, by its content.
#include <string>

#include "ggg/graph/geometric_graph.hpp"
#include "ggg/osm/osm_import.hpp"

namespace ggg {

enum class GraphFileType { osm, geojson, graph_file, unknown };

GraphFileType graph_file_type(const std::string& path);

// The highway filter applies to OSM input; the topology options to OSM and GeoJSON.
// `report` is filled for OSM input only.
GeometricGraph read_graph(const std::string& path, const ImportOptions& options = {},
                          ImportReport* report = nullptr, const ProgressCallback& progress = {});

// By extension: .geojson/.json or .ggraph. Throws UsageError for another extension and
// InputError when the file cannot be written.
void write_graph(const GeometricGraph& graph, const std::string& path);

} // namespace ggg
