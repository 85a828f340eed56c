#include "ggg/io/graph_file.hpp"

#include <cmath>
#include <fstream>
#include <sstream>
#include <unordered_set>

#include <nlohmann/json.hpp>

#include "ggg/error.hpp"
#include "json_util.hpp"

namespace ggg {

using nlohmann::json;

namespace {

bool frame_is_default(const GeometricGraph& g, std::size_t v) {
    const Similarity2& f = g.frames[v];
    return f.a == 1.0 && f.b == 0.0 && f.t == g.positions[v];
}

} // namespace

json graph_to_json(const GeometricGraph& g) {
    const std::size_t n = g.vertex_count();
    const std::size_t m = g.edge_count();
    json x = json::array(), y = json::array(), osm = json::array();
    for (std::size_t v = 0; v < n; ++v) {
        x.push_back(g.positions[v].x());
        y.push_back(g.positions[v].y());
        osm.push_back(g.vertex_osm_ids[v]);
    }
    json vertices = {{"x", std::move(x)}, {"y", std::move(y)}, {"osm_id", std::move(osm)}};
    // Symbols and frames matter only once a grammar is involved: written when not default.
    bool any_symbol = false, any_frame = false;
    for (std::size_t v = 0; v < n; ++v) {
        any_symbol |= g.symbols[v] != 0;
        any_frame |= !frame_is_default(g, v);
    }
    if (any_symbol) vertices["symbol"] = g.symbols;
    if (any_frame) {
        json frames = json::array();
        for (const auto& f : g.frames) frames.push_back({f.a, f.b, f.t.x(), f.t.y()});
        vertices["frame"] = std::move(frames);
    }
    // Rewrites pending at a vertex besides its own (version 2): where rules placed
    // nonterminals with different frames at one place.
    if (!g.more_rewrites.empty()) {
        json at = json::array(), symbol = json::array(), frame = json::array();
        for (const PendingRewrite& r : g.more_rewrites) {
            at.push_back(r.vertex);
            symbol.push_back(r.symbol);
            frame.push_back({r.frame.a, r.frame.b, r.frame.t.x(), r.frame.t.y()});
        }
        vertices["more_rewrites"] = {{"vertex", std::move(at)}, {"symbol", std::move(symbol)}, {"frame", std::move(frame)}};
    }

    json u = json::array(), v = json::array(), highway = json::array(), oneway = json::array(), lanes = json::array(),
         width = json::array(), way = json::array(), name = json::array(), shape = json::array();
    for (std::size_t e = 0; e < m; ++e) {
        u.push_back(g.edges[e][0]);
        v.push_back(g.edges[e][1]);
        highway.push_back(static_cast<int>(g.edge_highway[e]));
        oneway.push_back(g.edge_oneway[e]);
        lanes.push_back(g.edge_lanes[e]);
        if (std::isfinite(g.edge_width_m[e])) width.push_back(g.edge_width_m[e]);
        else width.push_back(nullptr);
        way.push_back(g.edge_way_ids[e]);
        name.push_back(g.edge_name_index[e]);
        json points = json::array();
        const auto begin = static_cast<std::size_t>(g.geometry_offsets[e]) + 1;
        const auto end = static_cast<std::size_t>(g.geometry_offsets[e + 1]) - 1;
        for (std::size_t i = begin; i < end; ++i) {
            points.push_back(g.geometry[i].x());
            points.push_back(g.geometry[i].y());
        }
        shape.push_back(std::move(points));
    }
    json classes = json::array();
    for (int c = 0; c < highway_class_count; ++c) classes.push_back(highway_name(static_cast<HighwayClass>(c)));
    return {
        {"format", "ggg-graph"},
        // The oldest version that holds what the graph has, so older programs read most files.
        {"version", g.more_rewrites.empty() ? 1 : graph_file_version},
        {"origin_latlon", {g.origin.lat, g.origin.lon}},
        {"highway_classes", std::move(classes)},
        {"names", g.names},
        {"vertices", std::move(vertices)},
        {"edges",
         {{"u", std::move(u)}, {"v", std::move(v)}, {"highway", std::move(highway)}, {"oneway", std::move(oneway)},
          {"lanes", std::move(lanes)}, {"width", std::move(width)}, {"way_id", std::move(way)},
          {"name", std::move(name)}, {"shape", std::move(shape)}}},
    };
}

namespace {

// Columns of the graph file: arrays of one length.
class Reader : public io_detail::JsonReader<InputError> {
public:
    using JsonReader::JsonReader;
    static constexpr std::size_t npos = any_size;

    const json& column(const json& object, const char* key, const std::string& where, std::size_t size) const {
        return array(member(object, key, where), where + "." + key, size);
    }
};

std::string at(const char* column, std::size_t i) { return std::string(column) + "[" + std::to_string(i) + "]"; }

} // namespace

GeometricGraph graph_from_json(const json& doc, const std::string& name) {
    Reader r(name);
    if (!io_detail::has_format(doc, "ggg-graph")) {
        throw InputError(name + ": not a ggg graph file (\"format\": \"ggg-graph\" missing)");
    }
    const auto version = r.integer(r.member(doc, "version", "file"), "version", 1, 1 << 20);
    if (version > graph_file_version) {
        throw InputError(name + ": graph file version " + std::to_string(version) + " is newer than this program reads (" +
                         std::to_string(graph_file_version) + "); update ggg");
    }
    GeometricGraph g;
    const json& origin = r.column(doc, "origin_latlon", "file", 2);
    g.origin = {r.number(origin[0], "origin_latlon[0]"), r.number(origin[1], "origin_latlon[1]")};
    if (std::abs(g.origin.lat) > 90 || std::abs(g.origin.lon) > 180) r.fail("origin_latlon", "out of range");

    const json& names = r.column(doc, "names", "file", Reader::npos);
    if (names.empty() || names[0] != "") r.fail("names", "must start with the empty name");
    g.names.clear();
    for (std::size_t i = 0; i < names.size(); ++i) {
        if (!names[i].is_string()) r.fail(at("names", i), "must be a string");
        g.names.push_back(names[i].get<std::string>());
    }

    const json& vertices = r.member(doc, "vertices", "file");
    const json& x = r.column(vertices, "x", "vertices", Reader::npos);
    const std::size_t n = x.size();
    const json& y = r.column(vertices, "y", "vertices", n);
    const json& osm = r.column(vertices, "osm_id", "vertices", n);
    g.reserve(n, 0, 0);
    for (std::size_t v = 0; v < n; ++v) {
        g.add_vertex({r.number(x[v], "vertices." + at("x", v)), r.number(y[v], "vertices." + at("y", v))},
                     r.integer(osm[v], "vertices." + at("osm_id", v), std::numeric_limits<std::int64_t>::min(),
                               std::numeric_limits<std::int64_t>::max()));
    }
    if (vertices.contains("symbol")) {
        const json& s = r.column(vertices, "symbol", "vertices", n);
        for (std::size_t v = 0; v < n; ++v) g.symbols[v] = static_cast<std::uint32_t>(r.integer(s[v], "vertices." + at("symbol", v), 0, std::numeric_limits<std::uint32_t>::max()));
    }
    if (vertices.contains("frame")) {
        const json& f = r.column(vertices, "frame", "vertices", n);
        for (std::size_t v = 0; v < n; ++v) {
            const std::string where = "vertices." + at("frame", v);
            if (!f[v].is_array() || f[v].size() != 4) r.fail(where, "must be [a, b, tx, ty]");
            g.frames[v] = {r.number(f[v][0], where), r.number(f[v][1], where), {r.number(f[v][2], where), r.number(f[v][3], where)}};
            if (g.frames[v].a == 0 && g.frames[v].b == 0) r.fail(where, "a frame must not have zero scale");
        }
    }
    if (vertices.contains("more_rewrites")) {
        const json& more = r.member(vertices, "more_rewrites", "vertices");
        const json& at_vertex = r.column(more, "vertex", "vertices.more_rewrites", Reader::npos);
        const std::size_t k = at_vertex.size();
        const json& symbol = r.column(more, "symbol", "vertices.more_rewrites", k);
        const json& frame = r.column(more, "frame", "vertices.more_rewrites", k);
        const auto last = static_cast<std::int64_t>(n) - 1;
        for (std::size_t i = 0; i < k; ++i) {
            PendingRewrite pr;
            pr.vertex = static_cast<VertexId>(r.integer(at_vertex[i], "vertices.more_rewrites." + at("vertex", i), 0, last));
            if (i > 0 && pr.vertex < g.more_rewrites.back().vertex) r.fail("vertices.more_rewrites." + at("vertex", i), "must be in vertex order");
            pr.symbol = static_cast<std::uint32_t>(
                r.integer(symbol[i], "vertices.more_rewrites." + at("symbol", i), 1, std::numeric_limits<std::uint32_t>::max()));
            if (g.symbols[static_cast<std::size_t>(pr.vertex)] == 0) {
                r.fail("vertices.more_rewrites." + at("vertex", i), "vertex " + std::to_string(pr.vertex) + " is not a nonterminal");
            }
            const std::string where = "vertices.more_rewrites." + at("frame", i);
            if (!frame[i].is_array() || frame[i].size() != 4) r.fail(where, "must be [a, b, tx, ty]");
            pr.frame = {r.number(frame[i][0], where), r.number(frame[i][1], where), {r.number(frame[i][2], where), r.number(frame[i][3], where)}};
            if (pr.frame.a == 0 && pr.frame.b == 0) r.fail(where, "a frame must not have zero scale");
            g.more_rewrites.push_back(pr);
        }
    }

    const json& edges = r.member(doc, "edges", "file");
    const json& u = r.column(edges, "u", "edges", Reader::npos);
    const std::size_t m = u.size();
    const json& v = r.column(edges, "v", "edges", m);
    const json& highway = r.column(edges, "highway", "edges", m);
    const json& oneway = r.column(edges, "oneway", "edges", m);
    const json& lanes = r.column(edges, "lanes", "edges", m);
    const json& width = r.column(edges, "width", "edges", m);
    const json& way = r.column(edges, "way_id", "edges", m);
    const json& name_index = r.column(edges, "name", "edges", m);
    const json& shape = r.column(edges, "shape", "edges", m);
    const auto last_vertex = static_cast<std::int64_t>(n) - 1;
    std::vector<Vec2> line;
    std::unordered_set<std::uint64_t> edge_keys;
    for (std::size_t e = 0; e < m; ++e) {
        const auto a = static_cast<VertexId>(r.integer(u[e], "edges." + at("u", e), 0, last_vertex));
        const auto b = static_cast<VertexId>(r.integer(v[e], "edges." + at("v", e), 0, last_vertex));
        EdgeAttributes attributes;
        attributes.highway = static_cast<HighwayClass>(r.integer(highway[e], "edges." + at("highway", e), 0, highway_class_count - 1));
        attributes.oneway = static_cast<std::int8_t>(r.integer(oneway[e], "edges." + at("oneway", e), -1, 1));
        attributes.lanes = static_cast<std::int16_t>(r.integer(lanes[e], "edges." + at("lanes", e), 0, 50));
        if (!width[e].is_null()) {
            attributes.width_m = r.number(width[e], "edges." + at("width", e));
            if (attributes.width_m <= 0) r.fail("edges." + at("width", e), "a width must be > 0 (or null)");
        }
        if (a == b) r.fail("edges." + at("v", e), "an edge must join two different vertices");
        if (!edge_keys.insert((static_cast<std::uint64_t>(std::min(a, b)) << 32) | static_cast<std::uint32_t>(std::max(a, b))).second) {
            r.fail("edges." + at("v", e), "a second edge between vertices " + std::to_string(a) + " and " + std::to_string(b));
        }
        attributes.way_id = r.integer(way[e], "edges." + at("way_id", e), std::numeric_limits<std::int64_t>::min(), std::numeric_limits<std::int64_t>::max());
        attributes.name = g.names[static_cast<std::size_t>(r.integer(name_index[e], "edges." + at("name", e), 0, static_cast<std::int64_t>(g.names.size()) - 1))];
        const json& points = shape[e];
        const std::string where = "edges." + at("shape", e);
        if (!points.is_array() || points.size() % 2 != 0) r.fail(where, "must be a flat array [x0, y0, x1, y1, ...]");
        line.clear();
        line.push_back(g.positions[static_cast<std::size_t>(a)]);
        for (std::size_t i = 0; i < points.size(); i += 2) line.emplace_back(r.number(points[i], where), r.number(points[i + 1], where));
        line.push_back(g.positions[static_cast<std::size_t>(b)]);
        g.add_edge(a, b, attributes, line);
    }
    return g;
}

void write_graph_file(const GeometricGraph& g, const std::string& path) {
    const std::string text = io_detail::dump(graph_to_json(g));
    io_detail::write_file(path, [&](std::ostream& out) { out << text << '\n'; });
}

GeometricGraph read_graph_file(const std::string& path) {
    return graph_from_json(io_detail::parse<InputError>(io_detail::read_json_text<InputError>(path), path), path);
}

} // namespace ggg
