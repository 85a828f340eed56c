#include "ggg/io/geojson.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <unordered_map>

#include <nlohmann/json.hpp>

#include "ggg/error.hpp"
#include "ggg/osm/projection.hpp"
#include "json_util.hpp"

namespace ggg {
namespace {

// 1e-9 degree is 0.1 mm: finer than any survey, and short.
void write_lonlat(std::ostream& out, const Vec2& lonlat) {
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, "[%.9f,%.9f]", lonlat.x(), lonlat.y());
    out << buffer;
}

} // namespace

void write_geojson(const GeometricGraph& g, std::ostream& out) {
    LocalProjection projection(g.origin);
    std::vector<Vec2> lonlat(g.geometry);
    projection.inverse(std::span<Vec2>(lonlat));

    out << R"({"type":"FeatureCollection","ggg":{"format":"ggg-geojson","version":1,"origin_latlon":[)";
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, "%.9f,%.9f", g.origin.lat, g.origin.lon);
    out << buffer << "],\"crs_local\":" << io_detail::dump(local_crs(g.origin)) << "},\n\"features\":[";
    for (std::size_t e = 0; e < g.edge_count(); ++e) {
        const auto id = static_cast<EdgeId>(e);
        const auto [u, v] = g.edges[e];
        out << (e ? ",\n" : "\n") << R"({"type":"Feature","properties":{"highway":")" << highway_name(g.edge_highway[e])
            << "\",\"name\":" << io_detail::dump(std::string(g.edge_name(id)))
            << ",\"osm_way_id\":" << g.edge_way_ids[e] << ",\"oneway\":" << int(g.edge_oneway[e]) << ",\"lanes\":";
        if (g.edge_lanes[e] > 0) out << g.edge_lanes[e];
        else out << "null";
        out << ",\"width\":";
        if (std::isfinite(g.edge_width_m[e])) out << io_detail::dump(g.edge_width_m[e]);
        else out << "null";
        out << ",\"from_osm_node\":" << g.vertex_osm_ids[static_cast<std::size_t>(u)]
            << ",\"to_osm_node\":" << g.vertex_osm_ids[static_cast<std::size_t>(v)]
            << R"(},"geometry":{"type":"LineString","coordinates":[)";
        const auto begin = static_cast<std::size_t>(g.geometry_offsets[e]);
        const auto end = static_cast<std::size_t>(g.geometry_offsets[e + 1]);
        for (std::size_t i = begin; i < end; ++i) {
            if (i > begin) out << ',';
            write_lonlat(out, lonlat[i]);
        }
        out << "]}}";
    }
    out << "\n]}\n";
}

void write_geojson(const GeometricGraph& g, const std::string& path) {
    io_detail::write_file(path, [&](std::ostream& out) { write_geojson(g, out); });
}

namespace {

struct GeoJsonReader {
    const std::string& name;
    TopologyInput input;
    std::vector<Vec2> lonlat; // per node
    std::unordered_map<std::uint64_t, std::int32_t> node_of;
    std::size_t features = 0;

    [[noreturn]] void fail(const std::string& where, const std::string& what) const {
        throw InputError(name + ": " + where + ": " + what);
    }

    std::int32_t node(const nlohmann::json& position, const std::string& where, std::int64_t osm_id) {
        if (!position.is_array() || position.size() < 2 || !position[0].is_number() || !position[1].is_number()) {
            fail(where, "a position must be [longitude, latitude]");
        }
        const double lon = position[0].get<double>();
        const double lat = position[1].get<double>();
        if (!std::isfinite(lon) || !std::isfinite(lat) || std::abs(lon) > 180 || std::abs(lat) > 90) {
            fail(where, "coordinates out of range (longitude must be in [-180, 180], latitude in [-90, 90])");
        }
        // One place is one node, as in OSM: 1e-7 degree is the OSM grid (about 1 cm).
        const auto qx = static_cast<std::uint32_t>(static_cast<std::int32_t>(std::llround(lon * 1e7)));
        const auto qy = static_cast<std::uint32_t>(static_cast<std::int32_t>(std::llround(lat * 1e7)));
        const std::uint64_t key = (static_cast<std::uint64_t>(qx) << 32) | qy;
        const auto [it, inserted] = node_of.emplace(key, static_cast<std::int32_t>(lonlat.size()));
        if (inserted) {
            lonlat.emplace_back(lon, lat);
            input.node_osm_ids.push_back(osm_id);
        } else if (osm_id != 0 && input.node_osm_ids[static_cast<std::size_t>(it->second)] == 0) {
            input.node_osm_ids[static_cast<std::size_t>(it->second)] = osm_id;
        }
        return it->second;
    }

    static std::int64_t integer_or(const nlohmann::json& props, const char* key, std::int64_t fallback) {
        const auto it = props.find(key);
        return it != props.end() && it->is_number_integer() ? it->get<std::int64_t>() : fallback;
    }

    void line(const nlohmann::json& coordinates, const nlohmann::json& props, const std::string& where) {
        if (!coordinates.is_array()) fail(where, "LineString coordinates must be an array");
        if (coordinates.size() < 2) return; // a single point is no road
        EdgeAttributes a;
        if (props.is_object()) {
            if (const auto it = props.find("highway"); it != props.end() && it->is_string()) a.highway = highway_from_name(it->get<std::string>());
            if (const auto it = props.find("name"); it != props.end() && it->is_string()) a.name = it->get<std::string>();
            a.way_id = integer_or(props, "osm_way_id", 0);
            const auto oneway = integer_or(props, "oneway", 0);
            a.oneway = static_cast<std::int8_t>(oneway > 0 ? 1 : oneway < 0 ? -1 : 0);
            const auto lanes = integer_or(props, "lanes", 0);
            a.lanes = static_cast<std::int16_t>(lanes > 0 && lanes <= 50 ? lanes : 0);
            if (const auto it = props.find("width"); it != props.end() && it->is_number()) {
                const double w = it->get<double>();
                if (std::isfinite(w) && w > 0) a.width_m = w;
            }
        }
        const std::int64_t from = props.is_object() ? integer_or(props, "from_osm_node", 0) : 0;
        const std::int64_t to = props.is_object() ? integer_or(props, "to_osm_node", 0) : 0;
        std::vector<std::int32_t> nodes;
        nodes.reserve(coordinates.size());
        for (std::size_t i = 0; i < coordinates.size(); ++i) {
            const std::int64_t osm = i == 0 ? from : i + 1 == coordinates.size() ? to : 0;
            nodes.push_back(node(coordinates[i], where + ".coordinates[" + std::to_string(i) + "]", osm));
        }
        input.add_way(nodes, std::move(a));
    }

    void geometry(const nlohmann::json& geom, const nlohmann::json& props, const std::string& where, int depth = 0) {
        if (geom.is_null()) return;
        if (depth > 8) fail(where, "GeometryCollections nested more than 8 deep");
        if (!geom.is_object() || !geom.contains("type") || !geom["type"].is_string()) fail(where, "a geometry needs a \"type\"");
        const std::string type = geom["type"].get<std::string>();
        if (type == "LineString") {
            if (!geom.contains("coordinates")) fail(where, "missing \"coordinates\"");
            line(geom["coordinates"], props, where);
        } else if (type == "MultiLineString") {
            if (!geom.contains("coordinates") || !geom["coordinates"].is_array()) fail(where, "missing \"coordinates\"");
            for (std::size_t i = 0; i < geom["coordinates"].size(); ++i) {
                line(geom["coordinates"][i], props, where + ".coordinates[" + std::to_string(i) + "]");
            }
        } else if (type == "GeometryCollection") {
            if (geom.contains("geometries") && geom["geometries"].is_array()) {
                for (std::size_t i = 0; i < geom["geometries"].size(); ++i) {
                    geometry(geom["geometries"][i], props, where + ".geometries[" + std::to_string(i) + "]", depth + 1);
                }
            }
        } // points and polygons are not roads
    }

    void feature(const nlohmann::json& f, const std::string& where) {
        if (!f.is_object()) fail(where, "a feature must be an object");
        ++features;
        const nlohmann::json no_properties = nlohmann::json::object();
        const auto props = f.find("properties");
        const auto geom = f.find("geometry");
        if (geom == f.end()) fail(where, "a feature needs a \"geometry\"");
        geometry(*geom, props != f.end() ? *props : no_properties, where + ".geometry");
    }
};

} // namespace

GeometricGraph read_geojson(const std::string& text, const std::string& name, const TopologyOptions& options) {
    return read_geojson(io_detail::parse<InputError>(text, name), name, options);
}

GeometricGraph read_geojson(const nlohmann::json& doc, const std::string& name, const TopologyOptions& options) {
    GeoJsonReader reader{name, {}, {}, {}};
    if (!doc.is_object() || !doc.contains("type") || !doc["type"].is_string()) {
        throw InputError(name + ": not GeoJSON (no \"type\" member)");
    }
    const std::string type = doc["type"].get<std::string>();
    if (type == "FeatureCollection") {
        if (!doc.contains("features") || !doc["features"].is_array()) throw InputError(name + ": a FeatureCollection needs a \"features\" array");
        const auto& features = doc["features"];
        for (std::size_t i = 0; i < features.size(); ++i) reader.feature(features[i], "features[" + std::to_string(i) + "]");
    } else if (type == "Feature") {
        reader.feature(doc, "feature");
    } else {
        reader.geometry(doc, nlohmann::json::object(), "geometry");
    }
    if (reader.input.way_count() == 0) {
        throw InputError(name + ": no roads: the GeoJSON has no LineString or MultiLineString with two or more positions");
    }
    GeoOrigin origin;
    bool have_origin = false;
    if (const auto it = doc.find("ggg"); it != doc.end() && it->is_object()) {
        const auto o = it->find("origin_latlon");
        if (o != it->end() && o->is_array() && o->size() == 2 && (*o)[0].is_number() && (*o)[1].is_number()) {
            origin = {(*o)[0].get<double>(), (*o)[1].get<double>()};
            have_origin = std::isfinite(origin.lat) && std::isfinite(origin.lon) && std::abs(origin.lat) <= 90 && std::abs(origin.lon) <= 180;
        }
    }
    if (!have_origin) {
        double min_lon = 180, max_lon = -180, min_lat = 90, max_lat = -90;
        for (const Vec2& p : reader.lonlat) {
            min_lon = std::min(min_lon, p.x());
            max_lon = std::max(max_lon, p.x());
            min_lat = std::min(min_lat, p.y());
            max_lat = std::max(max_lat, p.y());
        }
        origin = {(min_lat + max_lat) / 2, (min_lon + max_lon) / 2};
    }
    try {
        LocalProjection projection(origin);
        projection.forward(std::span<Vec2>(reader.lonlat));
        reader.input.node_positions = std::move(reader.lonlat);
        return build_graph(reader.input, origin, options);
    } catch (const InputError& e) {
        throw InputError(name + ": " + e.what());
    }
}

} // namespace ggg

namespace ggg {

namespace {

// The first polygon's outer ring, in longitude and latitude, found depth first through
// FeatureCollections, Features, GeometryCollections and MultiPolygons.
bool find_ring(const nlohmann::json& j, std::vector<Vec2>& ring, const std::string& name) {
    if (!j.is_object() || !j.contains("type") || !j["type"].is_string()) return false;
    const std::string type = j["type"].get<std::string>();
    auto take = [&](const nlohmann::json& rings) {
        if (!rings.is_array() || rings.empty() || !rings[0].is_array()) throw InputError(name + ": a Polygon needs an array of rings");
        for (const auto& c : rings[0]) {
            if (!c.is_array() || c.size() < 2 || !c[0].is_number() || !c[1].is_number()) {
                throw InputError(name + ": a polygon corner must be [longitude, latitude]");
            }
            ring.emplace_back(c[0].get<double>(), c[1].get<double>());
        }
        if (ring.size() >= 2 && ring.front() == ring.back()) ring.pop_back();
        if (ring.size() < 3) throw InputError(name + ": the region's polygon has fewer than three corners");
        for (const Vec2& p : ring) {
            if (!p.allFinite() || std::abs(p.x()) > 180 || std::abs(p.y()) > 90) throw InputError(name + ": a corner of the region is not a longitude and latitude");
        }
        return true;
    };
    if (type == "Polygon") return take(j.value("coordinates", nlohmann::json()));
    if (type == "MultiPolygon") {
        const auto& c = j.value("coordinates", nlohmann::json());
        if (!c.is_array() || c.empty()) throw InputError(name + ": an empty MultiPolygon");
        return take(c[0]);
    }
    if (type == "Feature") return j.contains("geometry") && find_ring(j["geometry"], ring, name);
    const char* list = type == "FeatureCollection" ? "features" : type == "GeometryCollection" ? "geometries" : nullptr;
    if (list && j.contains(list) && j[list].is_array()) {
        for (const auto& item : j[list]) {
            if (find_ring(item, ring, name)) return true;
        }
    }
    return false;
}

std::vector<Vec2> region_lonlat(const std::string& path) {
    std::vector<Vec2> ring;
    if (!find_ring(io_detail::parse<InputError>(io_detail::read_json_text<InputError>(path), path), ring, path)) {
        throw InputError(path + ": no Polygon in the file (a region is a GeoJSON Polygon or MultiPolygon)");
    }
    return ring;
}

} // namespace

GeoOrigin geojson_region_centre(const std::string& path) {
    const std::vector<Vec2> ring = region_lonlat(path);
    Vec2 c = Vec2::Zero();
    for (const Vec2& p : ring) c += p;
    c /= static_cast<double>(ring.size());
    return {c.y(), c.x()};
}

std::vector<Vec2> read_geojson_region(const std::string& path, const GeoOrigin& origin) {
    std::vector<Vec2> ring = region_lonlat(path);
    LocalProjection(origin).forward(ring);
    return ring;
}

} // namespace ggg
