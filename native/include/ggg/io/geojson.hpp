#pragma once
// GeoJSON (RFC 7946): WGS84 lon/lat, one LineString feature per edge with its road
// attributes as properties, so the graph opens in QGIS. The origin of the local frame is
// kept in a foreign member "ggg" so that reading the file back gives the same frame.
// Reading accepts any GeoJSON of LineStrings/MultiLineStrings: shared coordinates are
// intersections, exactly as shared nodes are in OSM.
#include <iosfwd>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "ggg/graph/geometric_graph.hpp"
#include "ggg/osm/topology.hpp"

namespace ggg {

void write_geojson(const GeometricGraph& graph, std::ostream& out);
void write_geojson(const GeometricGraph& graph, const std::string& path);

// The outer ring of the first Polygon (or MultiPolygon) of a GeoJSON file, in the metres of
// the local frame centred on `origin` (not closed: the last corner is not repeated). A
// region to grow streets into. Throws InputError naming the file when there is none.
std::vector<Vec2> read_geojson_region(const std::string& path, const GeoOrigin& origin);
// The centre of that ring in longitude and latitude (a frame for a region without a base).
GeoOrigin geojson_region_centre(const std::string& path);

// `name` is used in error messages (the file name).
GeometricGraph read_geojson(const std::string& text, const std::string& name, const TopologyOptions& options = {});
GeometricGraph read_geojson(const nlohmann::json& document, const std::string& name, const TopologyOptions& options = {});

} // namespace ggg
