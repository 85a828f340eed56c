// Bad input ends in a clear message: InputError from the library, "error:" and exit 1 from
// the CLI; bad usage exits 2. Never a crash.
#include <gtest/gtest.h>

#include <osmium/builder/attr.hpp>
#include <osmium/io/any_output.hpp>
#include <osmium/memory/buffer.hpp>

#include <filesystem>
#include <fstream>
#include <random>

#include <nlohmann/json.hpp>

#include "fixtures.hpp"
#include "ggg/error.hpp"
#include "ggg/io/read_graph.hpp"

using namespace ggg;
using ggg::test::run_cli;
using ggg::test::temp_file;
using ggg::test::temp_path;

namespace {

std::string random_bytes(std::size_t n, unsigned seed) {
    std::mt19937 rng(seed);
    std::string s(n, '\0');
    for (auto& ch : s) ch = static_cast<char>(rng() & 0xff);
    return s;
}

// A real PBF written by libosmium: a grid of streets, big enough for several blocks.
std::string write_grid_pbf() {
    using namespace osmium::builder::attr;
    osmium::memory::Buffer buffer(1 << 20, osmium::memory::Buffer::auto_grow::yes);
    const int n = 60;
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
            osmium::builder::add_node(buffer, _id(1 + i * n + j), _version(1), _location(8.0 + i * 0.001, 46.0 + j * 0.001));
        }
    }
    for (int i = 0; i < n; ++i) {
        std::vector<osmium::object_id_type> row, column;
        for (int j = 0; j < n; ++j) {
            row.push_back(1 + j * n + i);
            column.push_back(1 + i * n + j);
        }
        osmium::builder::add_way(buffer, _id(100000 + i), _version(1), _nodes(row), _tag("highway", "residential"));
        osmium::builder::add_way(buffer, _id(200000 + i), _version(1), _nodes(column), _tag("highway", "residential"));
    }
    const std::string path = temp_path(".osm.pbf");
    osmium::io::Writer writer(path, osmium::io::overwrite::allow);
    writer(std::move(buffer));
    writer.close();
    return path;
}

std::string truncated_copy(const std::string& path, double fraction) {
    std::ifstream in(path, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    bytes.resize(static_cast<std::size_t>(static_cast<double>(bytes.size()) * fraction));
    return temp_file(bytes, ".osm.pbf");
}

const char* no_highways_xml = R"(<?xml version="1.0" encoding="UTF-8"?>
<osm version="0.6">
  <node id="1" version="1" lat="46.0" lon="8.0"/>
  <node id="2" version="1" lat="46.001" lon="8.0"/>
  <node id="3" version="1" lat="46.001" lon="8.001"/>
  <way id="10" version="1"><nd ref="1"/><nd ref="2"/><nd ref="3"/><nd ref="1"/><tag k="building" v="yes"/></way>
</osm>
)";

const char* out_of_range_xml = R"(<?xml version="1.0" encoding="UTF-8"?>
<osm version="0.6">
  <node id="1" version="1" lat="95.0" lon="8.0"/>
  <node id="2" version="1" lat="96.0" lon="8.0"/>
  <way id="10" version="1"><nd ref="1"/><nd ref="2"/><tag k="highway" v="residential"/></way>
</osm>
)";

struct BadFile {
    const char* label;
    std::string path;
    const char* expected; // part of the message
};

std::vector<BadFile> bad_files() {
    const std::string pbf = write_grid_pbf();
    return {
        {"missing file", "/nonexistent/city.osm.pbf", "no such file"},
        {"empty file", temp_file("", ".osm"), "empty"},
        {"random bytes as PBF", temp_file(random_bytes(5000, 1), ".osm.pbf"), "not a readable OSM file"},
        {"random bytes as XML", temp_file(random_bytes(5000, 2), ".osm"), "not a readable OSM file"},
        {"random bytes as gzip", temp_file(random_bytes(5000, 3), ".osm.gz"), "not a readable OSM file"},
        {"random bytes as bzip2", temp_file(random_bytes(5000, 4), ".osm.bz2"), "not a readable OSM file"},
        {"truncated PBF", truncated_copy(pbf, 0.5), "not a readable OSM file"},
        {"PBF cut inside its header", truncated_copy(pbf, 0.001), "not a readable OSM file"},
        {"XML with no highways", temp_file(no_highways_xml, ".osm"), "no roads"},
        {"coordinates out of range", temp_file(out_of_range_xml, ".osm"), "node 1: latitude '95.0' is out of range"},
        {"a folder", std::filesystem::temp_directory_path().string() + "/", "unknown file type"},
        {"unknown file type", temp_file("hello", ".txt"), "unknown file type"},
        {"empty GeoJSON", temp_file("  \n", ".geojson"), "empty"},
        {"GeoJSON that is not JSON", temp_file(random_bytes(300, 5), ".geojson"), "not valid JSON"},
    };
}

} // namespace

TEST(BadInput, LibraryThrowsInputErrorWithAClearMessage) {
    for (const auto& bad : bad_files()) {
        try {
            read_graph(bad.path);
            ADD_FAILURE() << bad.label << ": no error";
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find(bad.expected), std::string::npos) << bad.label << ": " << e.what();
        }
    }
}

TEST(BadInput, TheGridPbfItselfIsFine) {
    const GeometricGraph g = read_graph(write_grid_pbf());
    EXPECT_EQ(g.vertex_count(), 60u * 60u);
    EXPECT_EQ(g.edge_count(), 2u * 60u * 59u);
}

TEST(BadInput, CliExitsOneWithErrorOnStderr) {
    for (const auto& bad : bad_files()) {
        const auto result = run_cli("info '" + bad.path + "'");
        EXPECT_EQ(result.code, 1) << bad.label << ": " << result.err;
        EXPECT_EQ(result.err.rfind("error: ", 0), 0u) << bad.label << ": " << result.err;
        EXPECT_NE(result.err.find(bad.expected), std::string::npos) << bad.label << ": " << result.err;
        EXPECT_EQ(result.out, "") << bad.label;
    }
}

TEST(BadInput, CliExitsTwoOnBadUsage) {
    const std::string ok = write_grid_pbf();
    for (const std::string& args : std::vector<std::string>{"", "frobnicate", "info", "info '" + ok + "' --highways 'a;b'", "info '" + ok + "' --consolidate -1",
                                   "export '" + ok + "'", "export '" + ok + "' -o out.shp", "info '" + ok + "' --no-such-flag"}) {
        const auto result = run_cli(args);
        EXPECT_EQ(result.code, 2) << "ggg " << args << ": " << result.err;
        EXPECT_EQ(result.err.rfind("error: ", 0), 0u) << "ggg " << args << ": " << result.err;
    }
}

TEST(Cli, InfoPrintsTheDocumentedSummary) {
    const auto result = run_cli("info '" + write_grid_pbf() + "'");
    ASSERT_EQ(result.code, 0) << result.err;
    const auto info = nlohmann::json::parse(result.out);
    EXPECT_EQ(info["vertices"], 3600);
    EXPECT_EQ(info["edges"], 7080);
    EXPECT_EQ(info["classes"]["residential"], 7080);
    EXPECT_EQ(info["bbox_m"].size(), 4u);
    EXPECT_NEAR(info["origin_latlon"][0].get<double>(), 46.0295, 1e-9);
    // 2 x 60 lines of 59 blocks; a block is 0.001 degree (~111 m north-south, ~77 m east-west).
    EXPECT_NEAR(info["total_length_m"].get<double>(), 60 * 59 * (111.2 + 77.3), 60 * 59 * 1.0);
}

TEST(Cli, ExportWritesGeoJsonAndGgraphThatReadBack) {
    const std::string pbf = write_grid_pbf();
    for (const char* suffix : {".geojson", ".ggraph"}) {
        const std::string out = temp_path(suffix);
        const auto result = run_cli("export '" + pbf + "' -o '" + out + "'");
        ASSERT_EQ(result.code, 0) << result.err;
        const auto info = run_cli("info '" + out + "'");
        ASSERT_EQ(info.code, 0) << info.err;
        EXPECT_EQ(nlohmann::json::parse(info.out)["edges"], 7080) << suffix;
    }
}

TEST(BadInput, DataSpanningTooMuchOfTheEarthIsAnErrorNotInfinity) {
    const std::string opl = "n1 v1 x-45 y0\nn2 v1 x-44.999 y0\nn3 v1 x135 y0\nn4 v1 x135.001 y0\n"
                            "w1 v1 Thighway=residential Nn1,n2\nw2 v1 Thighway=residential Nn3,n4\n";
    const std::string path = temp_file(opl, ".opl");
    try {
        read_graph(path);
        ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("cannot be projected"), std::string::npos) << e.what();
        EXPECT_EQ(std::string(e.what()).rfind(path, 0), 0u) << e.what();
    }
}

TEST(BadInput, DeeplyNestedGeoJsonIsRefused) {
    std::string text = R"({"type":"Feature","geometry":)";
    for (int i = 0; i < 50; ++i) text += R"({"type":"GeometryCollection","geometries":[)";
    text += R"({"type":"LineString","coordinates":[[8,46],[8.1,46]]})";
    for (int i = 0; i < 50; ++i) text += "]}";
    text += "}";
    try {
        read_graph(temp_file(text, ".geojson"));
        ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("nested"), std::string::npos) << e.what();
    }
}

TEST(BadInput, AGraphThatCollapsesNamesTheFile) {
    const std::string path = temp_file("n1 v1 x8 y46\nn2 v1 x8 y46\nw1 v1 Thighway=residential Nn1,n2\n", ".opl");
    try {
        read_graph(path);
        ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()).rfind(path + ": ", 0), 0u) << e.what();
    }
}
