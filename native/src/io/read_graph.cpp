#include "ggg/io/read_graph.hpp"

#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "ggg/error.hpp"
#include "ggg/io/geojson.hpp"
#include "ggg/io/graph_file.hpp"
#include "ggg/osm/projection.hpp"
#include "json_util.hpp"

namespace ggg {
namespace {

bool ends_with(const std::string& s, std::string_view suffix) {
    return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

} // namespace

GraphFileType graph_file_type(const std::string& path) {
    if (ends_with(path, ".ggraph")) return GraphFileType::graph_file;
    if (ends_with(path, ".geojson") || ends_with(path, ".json")) return GraphFileType::geojson;
    if (is_osm_path(path)) return GraphFileType::osm;
    return GraphFileType::unknown;
}

GeometricGraph read_graph(const std::string& path, const ImportOptions& options, ImportReport* import_report,
                          const ProgressCallback& progress) {
    const GraphFileType type = graph_file_type(path);
    if (type == GraphFileType::osm) return import_osm(path, options, import_report, progress);
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) throw InputError(path + ": no such file");
    if (type == GraphFileType::unknown) {
        throw InputError(path + ": unknown file type (expected .osm, .osm.pbf, .pbf, .osm.bz2, .osm.gz, .opl, .geojson, .json or .ggraph)");
    }
    report(progress, 0.0, "reading " + std::filesystem::path(path).filename().string());
    std::string text = io_detail::read_json_text<InputError>(path);
    const nlohmann::json doc = io_detail::parse<InputError>(text, path);
    text.clear();
    // A .json may hold either format; the content decides.
    GeometricGraph g = type == GraphFileType::graph_file || io_detail::has_format(doc, "ggg-graph")
                           ? graph_from_json(doc, path)
                           : read_geojson(doc, path, options.topology);
    if (options.origin) reproject(g, *options.origin);
    report(progress, 1.0, "done");
    return g;
}

void write_graph(const GeometricGraph& graph, const std::string& path) {
    if (ends_with(path, ".ggraph")) {
        write_graph_file(graph, path);
    } else if (ends_with(path, ".geojson") || ends_with(path, ".json")) {
        write_geojson(graph, path);
    } else {
        throw UsageError(path + ": unknown output type (use .geojson or .ggraph)");
    }
}

} // namespace ggg
