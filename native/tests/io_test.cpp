#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>

#include "fixtures.hpp"
#include "ggg/error.hpp"
#include "ggg/io/graph_info.hpp"
#include "ggg/io/geojson.hpp"
#include "ggg/io/graph_file.hpp"
#include "ggg/io/read_graph.hpp"
#include "ggg/osm/highway_filter.hpp"

using namespace ggg;
using ggg::test::temp_file;
using ggg::test::temp_path;

namespace {

GeometricGraph paris_all() {
    ImportOptions options;
    options.highways = HighwayFilter::all();
    return read_graph(ggg::test::shared_osm_dir() + "/paris_marais.osm.pbf", options);
}

template <typename T>
bool same_with_nan(const std::vector<T>& a, const std::vector<T>& b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i) {
        if (!(a[i] == b[i]) && !(std::isnan(a[i]) && std::isnan(b[i]))) return false;
    }
    return true;
}

// The smallest graph a file can hold: two vertices, one edge.
GeometricGraph one_edge_graph() {
    GeometricGraph g;
    g.add_vertex({0, 0});
    g.add_vertex({10, 0});
    g.add_edge(0, 1, {});
    return g;
}

std::string message_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const InputError& e) {
        return e.what();
    }
    return "(no InputError)";
}

} // namespace

TEST(GraphFile, RoundTripIsExact) {
    GGG_REQUIRE_CORPUS();
    const GeometricGraph g = paris_all();
    const std::string path = temp_path(".ggraph");
    write_graph(g, path);
    const GeometricGraph back = read_graph(path);
    EXPECT_EQ(back.positions, g.positions);
    EXPECT_EQ(back.vertex_osm_ids, g.vertex_osm_ids);
    EXPECT_EQ(back.edges, g.edges);
    EXPECT_EQ(back.edge_highway, g.edge_highway);
    EXPECT_EQ(back.edge_oneway, g.edge_oneway);
    EXPECT_EQ(back.edge_lanes, g.edge_lanes);
    EXPECT_TRUE(same_with_nan(back.edge_width_m, g.edge_width_m));
    EXPECT_EQ(back.edge_way_ids, g.edge_way_ids);
    EXPECT_EQ(back.names, g.names);
    EXPECT_EQ(back.edge_name_index, g.edge_name_index);
    EXPECT_EQ(back.geometry_offsets, g.geometry_offsets);
    EXPECT_EQ(back.geometry, g.geometry);
    EXPECT_EQ(back.origin.lat, g.origin.lat);
    EXPECT_EQ(back.origin.lon, g.origin.lon);
}

TEST(GraphFile, SymbolsAndFramesRoundTrip) {
    GeometricGraph g;
    g.add_vertex({0, 0});
    g.add_vertex({10, 0});
    g.symbols[1] = 3;
    g.frames[1] = Similarity2::from(0.5, 2.0, {10, 0});
    g.add_edge(0, 1, {});
    const GeometricGraph back = graph_from_json(graph_to_json(g), "memory");
    EXPECT_EQ(back.symbols, g.symbols);
    EXPECT_EQ(back.frames[1].a, g.frames[1].a);
    EXPECT_EQ(back.frames[1].t, g.frames[1].t);
}

TEST(GeoJson, RoundTripKeepsTheGraph) {
    GGG_REQUIRE_CORPUS();
    const GeometricGraph g = paris_all();
    const std::string path = temp_path(".geojson");
    write_graph(g, path);
    const GeometricGraph back = read_graph(path);
    EXPECT_EQ(back.vertex_count(), g.vertex_count());
    EXPECT_EQ(back.edge_count(), g.edge_count());
    EXPECT_NEAR(back.total_length(), g.total_length(), 1e-6 * g.total_length());
    EXPECT_NEAR(back.origin.lat, g.origin.lat, 1e-9);
    EXPECT_EQ(graph_info(back)["classes"], graph_info(g)["classes"]);
    std::map<std::int64_t, Vec2> before;
    for (std::size_t v = 0; v < g.vertex_count(); ++v) before[g.vertex_osm_ids[v]] = g.positions[v];
    for (std::size_t v = 0; v < back.vertex_count(); ++v) {
        const auto it = before.find(back.vertex_osm_ids[v]);
        ASSERT_NE(it, before.end()) << "vertex with OSM id " << back.vertex_osm_ids[v] << " appeared";
        EXPECT_LT((it->second - back.positions[v]).norm(), 1e-3);
    }
    // RFC 7946: a FeatureCollection of LineStrings in lon/lat.
    std::ifstream in(path);
    const auto doc = nlohmann::json::parse(in);
    EXPECT_EQ(doc["type"], "FeatureCollection");
    EXPECT_EQ(doc["features"].size(), g.edge_count());
    const auto& first = doc["features"][0];
    EXPECT_EQ(first["geometry"]["type"], "LineString");
    const double lon = first["geometry"]["coordinates"][0][0];
    EXPECT_NEAR(lon, 2.36, 0.05);
    EXPECT_TRUE(first["properties"].contains("highway"));
}

TEST(GeoJson, ForeignLineStringsMeetAtSharedPositions) {
    const std::string text = R"({"type":"FeatureCollection","features":[
      {"type":"Feature","properties":{"highway":"primary","name":"A"},
       "geometry":{"type":"LineString","coordinates":[[8.0,46.0],[8.001,46.0],[8.002,46.0]]}},
      {"type":"Feature","properties":null,
       "geometry":{"type":"MultiLineString","coordinates":[[[8.001,45.999],[8.001,46.0],[8.001,46.001]]]}},
      {"type":"Feature","properties":{},"geometry":{"type":"Point","coordinates":[8.0,46.0]}}]})";
    const GeometricGraph g = read_graph(temp_file(text, ".geojson"));
    EXPECT_EQ(g.vertex_count(), 5u);
    EXPECT_EQ(g.edge_count(), 4u);
    EXPECT_EQ(check_simple(g), "");
}

TEST(GeoJson, MalformedFilesNameThePlaceOfTheProblem) {
    EXPECT_NE(message_of([] { read_graph(temp_file("{\"type\": ", ".geojson")); }).find("not valid JSON"), std::string::npos);
    EXPECT_NE(message_of([] { read_graph(temp_file(R"({"type":"FeatureCollection","features":[{"type":"Feature","properties":{}}]})", ".geojson")); })
                  .find("features[0]"),
              std::string::npos);
    const std::string out_of_range = R"({"type":"FeatureCollection","features":[
      {"type":"Feature","geometry":{"type":"LineString","coordinates":[[8,46],[8.1,46]]}},
      {"type":"Feature","geometry":{"type":"LineString","coordinates":[[8,46],[200,46]]}}]})";
    const std::string m = message_of([&] { read_graph(temp_file(out_of_range, ".geojson")); });
    EXPECT_NE(m.find("features[1].geometry.coordinates[1]"), std::string::npos) << m;
    EXPECT_NE(m.find("out of range"), std::string::npos) << m;
    EXPECT_NE(message_of([] { read_graph(temp_file(R"({"type":"FeatureCollection","features":[]})", ".geojson")); }).find("no roads"),
              std::string::npos);
}

TEST(GraphFile, MalformedFilesNameThePlaceOfTheProblem) {
    GeometricGraph g = one_edge_graph();
    auto doc = graph_to_json(g);
    auto bad = doc;
    bad["edges"]["u"][0] = 7;
    EXPECT_NE(message_of([&] { graph_from_json(bad, "g.ggraph"); }).find("edges.u[0]"), std::string::npos);
    bad = doc;
    bad["vertices"]["y"] = nlohmann::json::array();
    EXPECT_NE(message_of([&] { graph_from_json(bad, "g.ggraph"); }).find("vertices.y"), std::string::npos);
    bad = doc;
    bad["version"] = 99;
    EXPECT_NE(message_of([&] { graph_from_json(bad, "g.ggraph"); }).find("newer"), std::string::npos);
    bad = doc;
    bad["edges"]["shape"][0] = {1.0};
    EXPECT_NE(message_of([&] { graph_from_json(bad, "g.ggraph"); }).find("edges.shape[0]"), std::string::npos);
    EXPECT_NE(message_of([] { read_graph(temp_file("[1,2", ".ggraph")); }).find("not valid JSON"), std::string::npos);
}

TEST(WriteGraph, BadDestinationsAreErrors) {
    GeometricGraph g = one_edge_graph();
    EXPECT_THROW(write_graph(g, "/nonexistent-dir/x.geojson"), InputError);
    EXPECT_THROW(write_graph(g, temp_path(".shp")), UsageError);
}

TEST(ReadGraph, IntoTheFrameOfAnotherOrigin) {
    GGG_REQUIRE_CORPUS();
    const std::string path = ggg::test::shared_osm_dir() + "/paris_marais.osm.pbf";
    const GeometricGraph own = read_graph(path);
    ImportOptions options;
    options.origin = GeoOrigin{48.85, 2.35};
    const GeometricGraph moved = read_graph(path, options);
    EXPECT_EQ(moved.origin.lat, 48.85);
    ASSERT_EQ(moved.vertex_count(), own.vertex_count());
    // Same graph, other frame: lengths agree (both frames are conformal near the city), the
    // positions differ by the offset between the origins (about 1.6 km here).
    EXPECT_NEAR(moved.total_length(), own.total_length(), 1e-5 * own.total_length());
    EXPECT_GT((moved.positions[0] - own.positions[0]).norm(), 1000.0);
    // Reading and then moving a .ggraph lands on the same positions as importing there.
    const std::string saved = temp_path(".ggraph");
    write_graph(own, saved);
    const GeometricGraph moved_file = read_graph(saved, options);
    for (std::size_t v = 0; v < own.vertex_count(); ++v) EXPECT_LT((moved_file.positions[v] - moved.positions[v]).norm(), 1e-6);
}

TEST(ReadGraph, OwnFormatUnderAJsonNameIsRecognisedByContent) {
    GeometricGraph g = one_edge_graph();
    const std::string path = temp_path(".json");
    write_graph_file(g, path);
    EXPECT_EQ(read_graph(path).edge_count(), 1u);
}

TEST(ReadGraph, StrangeDocumentsAreInputErrors) {
    EXPECT_NE(message_of([] { read_graph(temp_file(R"({"format": 5})", ".json")); }).find(".json: not GeoJSON"), std::string::npos);
    EXPECT_NE(message_of([] { read_graph(temp_file(R"({"format": 5})", ".ggraph")); }).find("not a ggg graph file"), std::string::npos);
    GeometricGraph g = one_edge_graph();
    auto doc = graph_to_json(g);
    auto loop = doc;
    loop["edges"]["v"][0] = 0;
    EXPECT_NE(message_of([&] { graph_from_json(loop, "g.ggraph"); }).find("edges.v[0]: an edge must join two different vertices"), std::string::npos);
    auto twice = doc;
    for (const char* c : {"u", "v", "highway", "oneway", "lanes", "width", "way_id", "name", "shape"}) twice["edges"][c].push_back(twice["edges"][c][0]);
    EXPECT_NE(message_of([&] { graph_from_json(twice, "g.ggraph"); }).find("edges.v[1]: a second edge"), std::string::npos);
    auto width = doc;
    width["edges"]["width"][0] = -3.0;
    EXPECT_NE(message_of([&] { graph_from_json(width, "g.ggraph"); }).find("edges.width[0]"), std::string::npos);
}

TEST(WriteGraph, InvalidUtf8NamesAreReplacedAndFailedWritesLeaveNoFile) {
    GeometricGraph g;
    g.add_vertex({0, 0});
    g.add_vertex({10, 0});
    EdgeAttributes a;
    a.name = std::string("Rue \xff\xfe des Bugs");
    g.add_edge(0, 1, a);
    for (const char* suffix : {".geojson", ".ggraph"}) {
        const std::string path = temp_path(suffix);
        write_graph(g, path);
        const GeometricGraph back = read_graph(path);
        EXPECT_EQ(back.edge_count(), 1u);
        EXPECT_NE(std::string(back.edge_name(0)).find("des Bugs"), std::string::npos);
    }
    const std::string dir = temp_path("");
    std::filesystem::create_directories(dir);
    const std::string blocked = dir + "/out.geojson";
    std::filesystem::create_directories(blocked); // a folder where the file should go: never replaced
    EXPECT_THROW(write_graph(g, blocked), UsageError);
    // A folder that cannot be written to: the write fails, and leaves no temporary file.
    const std::string locked = dir + "/locked";
    std::filesystem::create_directories(locked);
    std::filesystem::permissions(locked, std::filesystem::perms::owner_read | std::filesystem::perms::owner_exec);
    if (::geteuid() != 0) EXPECT_THROW(write_graph(g, locked + "/out.geojson"), InputError);
    std::filesystem::permissions(locked, std::filesystem::perms::owner_all);
    EXPECT_TRUE(std::filesystem::is_empty(locked));
    EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir), std::filesystem::directory_iterator()), 2);
}

TEST(GraphFile, RepeatedNamesInTheTableAreFine) {
    GeometricGraph g;
    g.add_vertex({0, 0});
    for (int i = 1; i <= 50; ++i) {
        g.add_vertex({10.0 * i, 0});
        EdgeAttributes a;
        a.name = i % 2 ? "Main" : "Side";
        g.add_edge(i - 1, i, a);
    }
    auto doc = graph_to_json(g);
    doc["names"].push_back("Main"); // a table that repeats a name, as another writer may make
    const GeometricGraph back = graph_from_json(doc, "g.ggraph");
    ASSERT_EQ(back.edge_count(), 50u);
    for (std::size_t e = 0; e < 50; ++e) EXPECT_EQ(back.edge_name(static_cast<EdgeId>(e)), g.edge_name(static_cast<EdgeId>(e)));
}
