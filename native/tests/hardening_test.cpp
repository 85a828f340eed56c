// What a hostile or careless user can do to the readers, the options and the outputs, and
// what they get: a clear error (exit 1 for bad input, 2 for bad usage), never a crash, a
// hang, a silently wrong graph, or a half-written or replaced file.
#include <gtest/gtest.h>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>
#include <osmium/builder/osm_object_builder.hpp>
#include <osmium/io/any_output.hpp>
#include <osmium/memory/buffer.hpp>

#include "fixtures.hpp"
#include "ggg/error.hpp"
#include "ggg/files.hpp"
#include "ggg/io/geojson.hpp"
#include "ggg/encoding/grammar_encoder.hpp"
#include "ggg/io/grammar_file.hpp"
#include "ggg/io/read_graph.hpp"

using namespace ggg;
using ggg::test::run_cli;
using ggg::test::temp_file;
using ggg::test::temp_path;
namespace fs = std::filesystem;

namespace {

const std::string sample_town = std::string(GGG_SAMPLES_DIR) + "/sample_city.osm";

std::string read_all(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

// A folder of its own, so that leftover temporary files can be counted.
std::string fresh_folder() {
    const std::string dir = temp_path("");
    fs::create_directories(dir);
    return dir;
}

std::size_t files_in(const std::string& dir) {
    return static_cast<std::size_t>(std::distance(fs::directory_iterator(dir), fs::directory_iterator()));
}

std::string small_town_xml(const std::string& lat_of_node_2) {
    return R"(<?xml version="1.0" encoding="UTF-8"?>
<osm version="0.6">
  <node id="1" version="1" lat="46.0" lon="8.0"/>
  <node id="2" version="1" lat=")" + lat_of_node_2 + R"(" lon="8.001"/>
  <node id="3" version="1" lat="46.001" lon="8.0"/>
  <way id="10" version="1"><nd ref="1"/><nd ref="2"/><nd ref="3"/><tag k="highway" v="residential"/></way>
</osm>
)";
}

std::string square_region(double lon, double lat, double half) {
    nlohmann::json ring = nlohmann::json::array();
    for (auto [dx, dy] : {std::pair{-1, -1}, {1, -1}, {1, 1}, {-1, 1}, {-1, -1}}) ring.push_back({lon + dx * half, lat + dy * half});
    return nlohmann::json{{"type", "Polygon"}, {"coordinates", {ring}}}.dump();
}

void expect_input_error(const std::string& path, const std::string& expected) {
    try {
        read_graph(path);
        ADD_FAILURE() << path << ": no error";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
}

} // namespace

// ---- readers ------------------------------------------------------------------------------

TEST(Hardening, ARegionNestedTensOfThousandsDeepIsAnErrorNotACrash) {
    const int depth = 50'000;
    std::string text;
    for (int i = 0; i < depth; ++i) text += R"({"type":"GeometryCollection","geometries":[)";
    text += square_region(8.0, 46.0, 0.001);
    for (int i = 0; i < depth; ++i) text += "]}";
    const std::string region = temp_file(text, ".geojson");
    try {
        read_geojson_region(region, GeoOrigin{46.0, 8.0});
        ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("nested more than 64 deep"), std::string::npos) << e.what();
    }
    const auto cli = run_cli("grow '" + std::string(GGG_SAMPLES_DIR) + "/sierpinski.grammar.json' --region '" + region + "' -o '" +
                             temp_path(".geojson") + "'");
    EXPECT_EQ(cli.code, 1) << cli.err;
    EXPECT_NE(cli.err.find("nested more than 64 deep"), std::string::npos) << cli.err;
}

TEST(Hardening, EveryJsonReaderBoundsNesting) {
    std::string deep = "[";
    for (int i = 0; i < 100'000; ++i) deep += "[";
    const std::string path = temp_file(deep, ".json");
    expect_input_error(path, "nested more than 64 deep");
    expect_input_error(temp_file(deep, ".ggraph"), "nested more than 64 deep");
    try {
        read_grammar(path);
        ADD_FAILURE() << "no error";
    } catch (const GrammarError& e) {
        EXPECT_NE(std::string(e.what()).find("nested more than 64 deep"), std::string::npos) << e.what();
    }
}

TEST(Hardening, ACoordinateOutOfRangeIsAnErrorNamingTheNode) {
    struct Case {
        std::string lat;
        std::string expected;
    };
    for (const Case& c : {Case{"1e300", "node 2: latitude '1e300' is out of range (-90 to 90)"},
                          Case{"-1e300", "node 2: latitude '-1e300' is out of range"},
                          Case{"95.0", "node 2: latitude '95.0' is out of range"},
                          Case{"46.0x", "node 2: latitude '46.0x' is not a number"},
                          Case{"nan", "node 2: latitude 'nan' is not a number"},
                          Case{"", "node 2: latitude '' is not a number"}}) {
        const std::string path = temp_file(small_town_xml(c.lat), ".osm");
        expect_input_error(path, c.expected);
        const auto cli = run_cli("info '" + path + "'");
        EXPECT_EQ(cli.code, 1) << c.lat << ": " << cli.err;
        EXPECT_NE(cli.err.find(c.expected), std::string::npos) << cli.err;
    }
    // The same in OPL, and in exponent form that stays in range (accepted: a real number).
    expect_input_error(temp_file("n1 v1 x8 y46\nn2 v1 x1e300 y46\nw1 v1 Thighway=residential Nn1,n2\n", ".opl"),
                       "node 2: longitude '1e300' is out of range (-180 to 180)");
    const GeometricGraph ok = read_graph(temp_file(small_town_xml("4.6001e1"), ".osm"));
    EXPECT_EQ(ok.edge_count(), 1u); // 1-2-3 is one street between two dead ends
}

TEST(Hardening, ACompressedFileIsCheckedAsItsText) {
    const std::string plain = temp_file(small_town_xml("1e300"), ".osm");
    for (const char* tool : {"gzip", "bzip2"}) {
        const std::string packed = temp_path(std::string(".osm.") + (tool[0] == 'g' ? "gz" : "bz2"));
        ASSERT_EQ(std::system((std::string(tool) + " -c '" + plain + "' > '" + packed + "'").c_str()), 0);
        expect_input_error(packed, "node 2: latitude '1e300' is out of range");
    }
}

TEST(Hardening, AHugeXmlAttributeIsRefusedQuickly) {
    const std::string huge(16u << 20, 'a');
    const std::string xml = R"(<?xml version="1.0" encoding="UTF-8"?>
<osm version="0.6">
  <node id="1" version="1" lat="46.0" lon="8.0"/>
  <node id="2" version="1" lat="46.001" lon="8.0"/>
  <way id="10" version="1"><nd ref="1"/><nd ref="2"/><tag k="highway" v="residential"/><tag k="note" v=")" +
                            huge + R"("/></way>
</osm>
)";
    expect_input_error(temp_file(xml, ".osm"), "is longer than 1 MiB (OSM tag values hold at most 255 characters)");
}

TEST(Hardening, ALinkToAnEndlessDeviceIsReadWithABound) {
    for (const char* suffix : {".geojson", ".ggraph", ".osm"}) {
        const std::string link = temp_path(suffix);
        fs::create_symlink("/dev/zero", link);
        const auto cli = run_cli("info '" + link + "'");
        EXPECT_EQ(cli.code, 1) << suffix << ": " << cli.err;
        EXPECT_NE(cli.err.find(link + ": more than 256 MiB came from this character device"), std::string::npos) << cli.err;
    }
    // zlib passes data that is not gzip through as it is: an endless stream of it too is bounded.
    const std::string gz = temp_path(".osm.gz");
    fs::create_symlink("/dev/zero", gz);
    const auto packed = run_cli("info '" + gz + "'");
    EXPECT_EQ(packed.code, 1) << packed.err;
    EXPECT_NE(packed.err.find("decompresses to more than 256 MiB"), std::string::npos) << packed.err;

    const std::string grammar = temp_path(".json");
    fs::create_symlink("/dev/zero", grammar);
    const auto cli = run_cli("derive '" + grammar + "' -o '" + temp_path(".geojson") + "'");
    EXPECT_EQ(cli.code, 1) << cli.err;
    EXPECT_NE(cli.err.find(grammar + ": more than 256 MiB"), std::string::npos) << cli.err;
}

// ---- options ------------------------------------------------------------------------------

TEST(Hardening, ValuesThatMeanNothingAreBadUsageNamingTheOption) {
    const std::string region = temp_file(square_region(8.0, 46.0, 0.002), ".geojson");
    const std::string out = temp_path(".geojson");
    const std::string grammar = std::string(GGG_SAMPLES_DIR) + "/sierpinski.grammar.json";
    struct Case {
        std::string arguments;
        std::string option;
    };
    for (const Case& c : std::vector<Case>{
             {"analyze '" + sample_town + "' --min-aspect nan", "--min-aspect"},
             {"analyze '" + sample_town + "' --min-irregularity NaN", "--min-irregularity"},
             {"analyze '" + sample_town + "' --tolerance nan", "--tolerance"},
             {"analyze '" + sample_town + "' --cut inf", "--cut"},
             {"analyze '" + sample_town + "' --recount -3", "--recount"},
             {"analyze '" + sample_town + "' --top -1", "--top"},
             {"analyze '" + sample_town + "' --min-leaves -1", "--min-leaves"},
             {"analyze '" + sample_town + "' --max-seconds nan", "--max-seconds"},
             {"analyze '" + sample_town + "' --max-memory -5", "--max-memory"},
             {"learn '" + sample_town + "' -o '" + out + "' --max-shape-error nan", "--max-shape-error"},
             {"learn '" + sample_town + "' -o '" + out + "' --levels -2", "--levels"},
             {"info '" + sample_town + "' --consolidate nan", "--consolidate"},
             {"derive '" + grammar + "' -o '" + out + "' --tolerance nan", "--tolerance"},
             {"derive '" + grammar + "' -o '" + out + "' --steps -1", "--steps"},
             {"grow '" + grammar + "' --region '" + region + "' -o '" + out + "' --border nan", "--border"},
             {"grow '" + grammar + "' --region '" + region + "' -o '" + out + "' --border inf", "--border"},
             {"grow '" + grammar + "' --region '" + region + "' -o '" + out + "' --seed 18446744073709551616", "--seed"},
             {"grow '" + grammar + "' --region '" + region + "' -o '" + out + "' --seed -1", "--seed"},
             {"grow '" + grammar + "' --region '" + region + "' -o '" + out + "' --max-placements 0", "--max-placements"},
         }) {
        const auto result = run_cli(c.arguments);
        EXPECT_EQ(result.code, 2) << c.arguments << ": " << result.err;
        EXPECT_NE(result.err.find(c.option), std::string::npos) << c.arguments << ": " << result.err;
        EXPECT_FALSE(fs::exists(out)) << c.arguments;
    }
    // The largest seed there is is a seed (the sample town's own grammar grown beside it).
    const std::string town_grammar = temp_path(".json");
    ASSERT_EQ(run_cli("learn '" + sample_town + "' -o '" + town_grammar + "'").code, 0);
    const std::string beside = temp_file(square_region(8.95 + 0.014, 46.0, 0.003), ".geojson");
    const auto largest = run_cli("grow '" + town_grammar + "' --base '" + sample_town + "' --region '" + beside + "' -o '" + out +
                                 "' --seed 18446744073709551615 --max-placements 5");
    EXPECT_EQ(largest.code, 0) << largest.err;
}

TEST(Hardening, ARegionWithoutAreaIsRefused) {
    // Collinear corners: a line, which the projection bends by a hair.
    nlohmann::json ring = nlohmann::json::array({{8.0, 46.0}, {8.01, 46.01}, {8.02, 46.02}, {8.0, 46.0}});
    const std::string region = temp_file(nlohmann::json{{"type", "Polygon"}, {"coordinates", {ring}}}.dump(), ".geojson");
    const auto result = run_cli("grow '" + std::string(GGG_SAMPLES_DIR) + "/sierpinski.grammar.json' --region '" + region + "' -o '" +
                                temp_path(".geojson") + "'");
    EXPECT_EQ(result.code, 2) << result.err;
    EXPECT_NE(result.err.find("no area"), std::string::npos) << result.err;
}

TEST(Hardening, ARegionThatCrossesItselfOrLiesFarFromTheBaseIsRefusedAndNothingIsWritten) {
    const std::string grammar = temp_path(".json");
    ASSERT_EQ(run_cli("learn '" + sample_town + "' -o '" + grammar + "'").code, 0);
    nlohmann::json bow = nlohmann::json::array({{8.964, 45.998}, {8.968, 46.002}, {8.968, 45.998}, {8.964, 46.002}, {8.964, 45.998}});
    const std::string bow_tie = temp_file(nlohmann::json{{"type", "Polygon"}, {"coordinates", {bow}}}.dump(), ".geojson");
    // The sample town's neighbourhood with longitude and latitude swapped: 4,800 km away.
    const std::string swapped = temp_file(square_region(46.0, 8.96, 0.002), ".geojson");
    for (const auto& [region, expected] : {std::pair{bow_tie, "crosses itself"}, std::pair{swapped, "km from the streets of the base"}}) {
        const std::string out = temp_path(".geojson");
        const auto result = run_cli("grow '" + grammar + "' --base '" + sample_town + "' --region '" + region + "' -o '" + out + "'");
        EXPECT_EQ(result.code, 2) << result.err;
        EXPECT_NE(result.err.find(expected), std::string::npos) << result.err;
        EXPECT_FALSE(std::ifstream(out).good()) << out << " was written";
    }
}

TEST(Hardening, UntilNothingRepeatsStopsAtItsBudgetAndKeepsWhatItFound) {
    const auto analysis = run_cli("analyze '" + sample_town + "' --max-order 0 --max-seconds 3 --top 3");
    ASSERT_EQ(analysis.code, 0) << analysis.err;
    const auto a = nlohmann::json::parse(analysis.out);
    EXPECT_TRUE(a["stopped_by_budget"].get<bool>());
    EXPECT_EQ(a["isogroups"].size(), 3u);
    EXPECT_NE(analysis.err.find("budget"), std::string::npos) << analysis.err;

    const std::string grammar = temp_path(".json");
    const auto learning = run_cli("learn '" + sample_town + "' -o '" + grammar + "' --max-order 0 --max-seconds 4");
    ASSERT_EQ(learning.code, 0) << learning.err;
    const auto l = nlohmann::json::parse(learning.out);
    EXPECT_TRUE(l["stopped_by_budget"].get<bool>());
    EXPECT_TRUE(l["roundtrip"]["edges_equal"].get<bool>()); // what was found is a whole grammar
    EXPECT_GE(l["rules"].get<int>(), 1);
    const auto decoded = run_cli("decode '" + grammar + "' -o '" + temp_path(".ggraph") + "'");
    EXPECT_EQ(decoded.code, 0) << decoded.err;
}

// ---- decoding -------------------------------------------------------------------------------

TEST(Hardening, ADamagedGrammarDoesNotDecode) {
    const std::string grammar = temp_path(".json");
    ASSERT_EQ(run_cli("learn '" + sample_town + "' -o '" + grammar + "'").code, 0);
    auto doc = nlohmann::json::parse(read_all(grammar));
    ASSERT_FALSE(test::packed_column(doc, "encoding", "decodes_to").empty());
    // The first nonterminal of the axiom moved 10 km (positions are delta-coded quanta of
    // 1 cm, the default: the next vertex stays): the streets its instance joins are no
    // longer where it aims.
    auto& x = test::packed_column(doc, "axiom", "x");
    ASSERT_FALSE(test::packed_column(doc, "axiom", "nonterminals").empty());
    const auto at = test::packed_column(doc, "axiom", "nonterminals")[0].get<std::size_t>();
    ASSERT_LT(at + 1, x.size());
    ASSERT_EQ(LearnOptions{}.quantum_m, 0.01);
    const auto ten_km = static_cast<std::int64_t>(std::llround(10'000.0 / 0.01));
    x[at] = x[at].get<std::int64_t>() + ten_km;
    x[at + 1] = x[at + 1].get<std::int64_t>() - ten_km;
    const std::string damaged = temp_file(doc.dump(), ".json");
    const auto result = run_cli("decode '" + damaged + "' -o '" + temp_path(".geojson") + "'");
    EXPECT_EQ(result.code, 1) << result.err;
    EXPECT_NE(result.err.find("does not decode to what it encodes"), std::string::npos) << result.err;
}

// ---- outputs ------------------------------------------------------------------------------

TEST(Hardening, ConcurrentWritersToOnePathAllSucceed) {
    const std::string dir = fresh_folder();
    const std::string target = dir + "/out.txt";
    std::vector<std::thread> writers;
    std::vector<int> failures(8, 0);
    for (int w = 0; w < 8; ++w) {
        writers.emplace_back([&, w] {
            try {
                for (int i = 0; i < 20; ++i) write_text_file(target, std::string(100'000, static_cast<char>('a' + w)));
            } catch (const Error&) {
                failures[static_cast<std::size_t>(w)] = 1;
            }
        });
    }
    for (auto& t : writers) t.join();
    EXPECT_EQ(std::count(failures.begin(), failures.end(), 1), 0);
    const std::string text = read_all(target);
    ASSERT_EQ(text.size(), 100'000u);
    EXPECT_EQ(std::count(text.begin(), text.end(), text[0]), 100'000); // one writer's whole file
    EXPECT_EQ(files_in(dir), 1u);                                       // no temporary file left

    // Four CLI runs at once, as in a batch script.
    const std::string output = dir + "/town.geojson";
    const std::string script = "pids=''; for i in 1 2 3 4; do '" + std::string(GGG_CLI_PATH) + "' export '" + sample_town + "' -o '" + output +
                               "' >/dev/null 2>>'" + dir + "/errors' & pids=\"$pids $!\"; done; s=0; for p in $pids; do wait $p || s=1; done; exit $s";
    const int code = std::system(("sh '" + temp_file(script, ".sh") + "'").c_str());
    EXPECT_EQ(WEXITSTATUS(code), 0) << read_all(dir + "/errors");
    EXPECT_EQ(read_all(dir + "/errors"), "");
    fs::remove(dir + "/errors");
    const auto info = run_cli("info '" + output + "'");
    EXPECT_EQ(info.code, 0) << info.err;
    EXPECT_EQ(files_in(dir), 2u); // out.txt and town.geojson
}

TEST(Hardening, AFailedRunLeavesThePreviousFileAndNoTemporaryFile) {
    const std::string dir = fresh_folder();
    const std::string keep = dir + "/keep.json";
    {
        std::ofstream(keep) << "previous";
    }
    // The second output cannot be written: nothing is written, the first is not replaced.
    const auto result = run_cli("learn '" + sample_town + "' -o '" + keep + "' --stats /nonexistent/s.json");
    EXPECT_EQ(result.code, 1) << result.err;
    EXPECT_NE(result.err.find("/nonexistent"), std::string::npos) << result.err;
    EXPECT_EQ(read_all(keep), "previous");

    // A write that fails half-way, as on a full disk (here a file size limit of 64 KiB).
    const std::string output = dir + "/town.geojson";
    {
        std::ofstream(output) << "previous";
    }
    const std::string script = "trap '' XFSZ; ulimit -f 64; exec '" + std::string(GGG_CLI_PATH) + "' export '" + sample_town + "' -o '" + output +
                               "' 2>'" + dir + "/err.txt'";
    const int status = std::system(("sh '" + temp_file(script, ".sh") + "'").c_str());
    EXPECT_EQ(WEXITSTATUS(status), 1);
    EXPECT_NE(read_all(dir + "/err.txt").find("write failed"), std::string::npos) << read_all(dir + "/err.txt");
    EXPECT_EQ(read_all(output), "previous");
    fs::remove(dir + "/err.txt");
    EXPECT_EQ(files_in(dir), 2u); // keep.json and town.geojson, no temporary file
}

TEST(Hardening, AnOutputThatIsNotARegularFileIsNeverReplaced) {
    const std::string dir = fresh_folder();
    const std::string target = dir + "/real.geojson";
    {
        std::ofstream(target) << "real";
    }
    const std::string link = dir + "/link.geojson";
    fs::create_symlink(target, link);
    const auto via_link = run_cli("export '" + sample_town + "' -o '" + link + "'");
    EXPECT_EQ(via_link.code, 2) << via_link.err;
    EXPECT_NE(via_link.err.find("symbolic link"), std::string::npos) << via_link.err;
    EXPECT_TRUE(fs::is_symlink(link));
    EXPECT_EQ(read_all(target), "real");

    EXPECT_THROW(check_output_path("/dev/null"), UsageError);
    EXPECT_THROW(check_output_path(dir), UsageError);
    EXPECT_EQ(files_in(dir), 2u);
}

// ---- fuzzing findings -----------------------------------------------------------------------

TEST(Hardening, APbfBlobHeaderWithoutATypeIsAnErrorNotUndefinedBehaviour) {
    // Found by the OSM fuzzer (native/fuzz): libosmium compares the missing type through a
    // null pointer. Six bytes: a header of two bytes holding only a data size.
    const std::string path = std::string(GGG_SOURCE_DIR) + "/native/tests/data/fuzz/osm_pbf_blob_header_without_type.osm.pbf";
    ASSERT_TRUE(fs::exists(path));
    expect_input_error(path, "the blob header at byte 0 has no type");
}

TEST(Hardening, APbfWithTimestampsThatOverflowIsReadWithoutUndefinedBehaviour) {
    // Found by the OSM fuzzer: libosmium's delta decoding of dense-node timestamps overflows a
    // signed integer. The import reads no metadata (a road graph has none), so it never
    // decodes them; under the sanitizer run (scripts/sanitize.sh) any overflow would abort.
    const std::string path = std::string(GGG_SOURCE_DIR) + "/native/tests/data/fuzz/osm_pbf_dense_node_timestamp_overflow.osm.pbf";
    ASSERT_TRUE(fs::exists(path));
    try {
        const GeometricGraph g = read_graph(path);
        EXPECT_EQ(check_simple(g), "");
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()).rfind(path, 0), 0u) << e.what();
    }
}

TEST(Hardening, APbfStringWithANulByteDoesNotMisleadTheTagLookup) {
    // Found by the OSM fuzzer: a string of the PBF string table holding a NUL byte misaligns
    // libosmium's key/value pairs, and its tag lookup read past the end of the list. The
    // import looks tags up within the list's bytes; the sanitizer run would catch a read past it.
    const std::string path = std::string(GGG_SOURCE_DIR) + "/native/tests/data/fuzz/osm_pbf_string_with_nul_heap_overflow.osm.pbf";
    ASSERT_TRUE(fs::exists(path));
    try {
        const GeometricGraph g = read_graph(path);
        EXPECT_EQ(check_simple(g), "");
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()).rfind(path, 0), 0u) << e.what();
    }
}

TEST(Hardening, ACorruptPbfLeavesNoFileOpen) {
    // Found by the OSM fuzzer: libosmium's PBF reader left the file's descriptor open when the
    // data was corrupt. The import reads the file whole and hands libosmium the bytes.
    const std::string path = std::string(GGG_SOURCE_DIR) + "/native/tests/data/fuzz/osm_pbf_no_header_fd_leak.osm.pbf";
    ASSERT_TRUE(fs::exists(path));
    auto open_descriptors = [] {
        return std::distance(fs::directory_iterator("/proc/self/fd"), fs::directory_iterator());
    };
    const auto before = open_descriptors();
    for (int i = 0; i < 20; ++i) {
        try {
            read_graph(path);
        } catch (const InputError&) {
        }
    }
    EXPECT_EQ(open_descriptors(), before);
}

TEST(Hardening, BoundsOutOfRangeAreAnErrorToo) {
    // Found by the OSM fuzzer: libosmium reads the corners of <bounds> with the same
    // coordinate parser, which overflowed on an exponent.
    const std::string path = std::string(GGG_SOURCE_DIR) + "/native/tests/data/fuzz/osm_xml_bounds_exponent_overflow.osm";
    ASSERT_TRUE(fs::exists(path));
    expect_input_error(path, "bounds: latitude minlat '1e32' is out of range (-90 to 90)");
}

TEST(Hardening, APbfWithCoordinatesThatOverflowIsAnErrorNotUndefinedBehaviour) {
    // Found by the OSM fuzzer: libosmium computes a dense node's coordinate as the sum of its
    // deltas times the granularity plus the offset, in 64 bits without checks. The import
    // checks that arithmetic first (osm_text.hpp), so the sanitizer run needs no suppression.
    const std::string path = std::string(GGG_SOURCE_DIR) + "/native/tests/data/fuzz/osm_pbf_dense_node_coordinate_overflow.osm.pbf";
    ASSERT_TRUE(fs::exists(path));
    expect_input_error(path, "runs past 64 bits");
}

TEST(Hardening, APbfNodeOutsideTheWorldIsAnErrorNamingTheNode) {
    // A location libosmium can hold (it stores 32 bits, up to ±214°) but the world cannot.
    const fs::path dir = fs::temp_directory_path() / "ggg_hardening_pbf_range";
    fs::create_directories(dir);
    const std::string path = (dir / "outside.osm.pbf").string();
    fs::remove(path);
    {
        osmium::memory::Buffer buffer{1024, osmium::memory::Buffer::auto_grow::yes};
        {
            osmium::builder::NodeBuilder node{buffer};
            node.object().set_id(41);
            node.object().set_location(osmium::Location{200.0, 10.0});
        }
        buffer.commit();
        osmium::io::Writer writer{osmium::io::File{path, "pbf"}};
        writer(std::move(buffer));
        writer.close();
    }
    expect_input_error(path, "node 41: its longitude is out of range (-180 to 180)");
    fs::remove_all(dir);
}
