// GeoJSON graph reader (ggg::read_geojson from text), then the writer on what it read. The
// input's size picks the topology options (plain, keep shape nodes, consolidate 5 m). A graph
// that comes back must be simple (topology.hpp); an InputError is a correct outcome.
#include <cstdint>
#include <sstream>
#include <string>

#include "fuzz_common.hpp"
#include "ggg/error.hpp"
#include "ggg/io/geojson.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    ggg::TopologyOptions options;
    options.keep_shape_nodes = size % 3 == 1;
    if (size % 3 == 2) options.consolidate_m = 5.0;
    try {
        const ggg::GeometricGraph graph = ggg::read_geojson(text, "fuzz.geojson", options);
        if (const std::string problem = ggg::check_simple(graph); !problem.empty()) {
            ggg_fuzz::fail("read_geojson returned a graph that is not simple: " + problem);
        }
        std::ostringstream out;
        ggg::write_geojson(graph, out);
    } catch (const ggg::Error&) {
    }
    return 0;
}
