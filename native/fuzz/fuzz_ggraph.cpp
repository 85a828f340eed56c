// .ggraph reader (ggg::graph_from_json on the parsed text; the parse has the readers' depth
// limit), then writing and reading back, which must succeed (the format is lossless).
#include <cstdint>

#include <nlohmann/json.hpp>

#include "fuzz_common.hpp"
#include "ggg/error.hpp"
#include "ggg/io/graph_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using json = nlohmann::json;
    // As the library's parser: documents nested deeper than 64 are refused before reading.
    const json::parser_callback_t depth_limit = [](int depth, json::parse_event_t, json&) { return depth <= 64; };
    const json doc = json::parse(data, data + size, depth_limit, /*allow_exceptions=*/false);
    if (doc.is_discarded()) return 0;
    ggg::GeometricGraph graph;
    try {
        graph = ggg::graph_from_json(doc, "fuzz.ggraph");
    } catch (const ggg::Error&) {
        return 0;
    }
    try {
        const ggg::GeometricGraph again = ggg::graph_from_json(json::parse(ggg::graph_to_json(graph).dump(-1, ' ', false, json::error_handler_t::replace)), "written");
        if (again.vertex_count() != graph.vertex_count() || again.edge_count() != graph.edge_count()) {
            ggg_fuzz::fail("a .ggraph reads back with other counts after writing");
        }
    } catch (const ggg::Error& e) {
        ggg_fuzz::fail(std::string("a .ggraph read from a file does not read back after writing: ") + e.what());
    }
    return 0;
}
