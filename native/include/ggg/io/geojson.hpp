#pragma once
// GeoJSON (RFC 7946): WGS84 lon/lat, one LineString feature per edge with its road
// attributes as properties, so the graph opens in QGIS. The origin of the local frame is
// kept in a foreign member "ggg" so that reading the file back gives the same frame.
// Reading accepts any GeoJSON of LineStrings/MultiLineStrings: shared coordinates are
// intersections, exactly as shared nodes are in OSM.
#include <iosfwd>
#include <string>

#include <nlohmann/json_fwd.hpp>

#include "ggg/geometric_graph.hpp"
#include "ggg/topology.hpp"

namespace ggg {

void write_geojson(const GeometricGraph& graph, std::ostream& out);
void write_geojson(const GeometricGraph& graph, const std::string& path);

// `name` is used in error messages (the file name).
GeometricGraph read_geojson(const std::string& text, const std::string& name, const TopologyOptions& options = {});
GeometricGraph read_geojson(const nlohmann::json& document, const std::string& name, const TopologyOptions& options = {});

} // namespace ggg
