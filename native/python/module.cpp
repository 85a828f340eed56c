// The Python face of the library: numpy arrays in and out, the GIL released on long calls,
// progress through a callback, and C++ errors as Python exceptions with the user's message.
#include <cstring>
#include <limits>
#include <optional>
#include <unordered_set>

#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "ggg/synthesis/city_layout.hpp"
#include "ggg/graph/road_widths.hpp"
#include "ggg/error.hpp"
#include "ggg/io/graph_info.hpp"
#include "ggg/io/grammar_file.hpp"
#include "ggg/io/read_graph.hpp"
#include "ggg/graph/planar_faces.hpp"
#include "ggg/osm/projection.hpp"
#include "ggg/encoding/decoding.hpp"
#include "ggg/grammar/rewriting.hpp"
#include "ggg/osm/highway_filter.hpp"
#include "ggg/io/reports.hpp"

#include <nlohmann/json.hpp>

#include "common.hpp"

namespace py = pybind11;

using ggg::python::column;
using ggg::python::column_as;
using ggg::python::points;
using ggg::python::PythonProgress;

namespace {

ggg::GeometricGraph read_graph(const std::string& path, const std::string& highways, bool keep_shape_nodes,
                               double consolidate_m, std::optional<std::pair<double, double>> origin_latlon,
                               std::optional<py::function> progress) {
    ggg::ImportOptions options;
    if (origin_latlon) options.origin = ggg::GeoOrigin{origin_latlon->first, origin_latlon->second};
    options.highways = ggg::HighwayFilter::parse(highways);
    options.topology.keep_shape_nodes = keep_shape_nodes;
    options.topology.consolidate_m = consolidate_m;
    PythonProgress reporter(std::move(progress));
    return reporter.run([&](const ggg::ProgressCallback& cb) { return ggg::read_graph(path, options, nullptr, cb); });
}

using DoubleArray = py::array_t<double, py::array::c_style | py::array::forcecast>;
using IntArray = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>;

// Optional per-edge columns of Graph.from_arrays, each (M,) or None.
struct EdgeColumns {
    std::optional<IntArray> highway, lanes, oneway, way_ids;
    std::optional<DoubleArray> width;
    std::optional<std::vector<std::string>> names;
    std::optional<std::pair<IntArray, DoubleArray>> geometry; // (offsets (M+1,), points (P,2))
};

// Graph.more_rewrites: (vertices (K,), symbols (K,), frames (K,4)).
using MoreRewrites = std::tuple<IntArray, IntArray, DoubleArray>;

void set_more_rewrites(ggg::GeometricGraph& g, const MoreRewrites& more) {
    const auto& [at, symbols, frames] = more;
    if (at.ndim() != 1 || symbols.ndim() != 1 || symbols.shape(0) != at.shape(0) || frames.ndim() != 2 ||
        frames.shape(0) != at.shape(0) || frames.shape(1) != 4) {
        throw ggg::UsageError("more_rewrites must be (vertices (K,), symbols (K,), frames (K, 4))");
    }
    const auto f = frames.unchecked<2>();
    for (py::ssize_t i = 0; i < at.shape(0); ++i) {
        const std::string where = "more_rewrites[" + std::to_string(i) + "]";
        const auto v = at.at(i), s = symbols.at(i);
        if (v < 0 || v >= static_cast<py::ssize_t>(g.vertex_count())) throw ggg::InputError(where + " refers to a vertex out of range");
        if (g.symbols[static_cast<std::size_t>(v)] == 0) throw ggg::InputError(where + ": vertex " + std::to_string(v) + " is not a nonterminal");
        if (s < 1 || s > std::numeric_limits<ggg::Symbol>::max()) throw ggg::InputError(where + " has no nonterminal symbol");
        ggg::Similarity2 frame{f(i, 0), f(i, 1), {f(i, 2), f(i, 3)}};
        if (!std::isfinite(frame.a) || !std::isfinite(frame.b) || !frame.t.allFinite() || frame.scale() <= 0) {
            throw ggg::InputError(where + " has no valid frame");
        }
        g.more_rewrites.push_back({static_cast<ggg::VertexId>(v), static_cast<ggg::Symbol>(s), frame});
    }
    std::stable_sort(g.more_rewrites.begin(), g.more_rewrites.end(),
                     [](const ggg::PendingRewrite& a, const ggg::PendingRewrite& b) { return a.vertex < b.vertex; });
}

ggg::GeometricGraph graph_from_arrays(const DoubleArray& positions, const IntArray& edges, std::pair<double, double> origin_latlon,
                                      std::optional<IntArray> symbols, std::optional<DoubleArray> frames,
                                      std::optional<IntArray> osm_ids, const EdgeColumns& columns,
                                      const std::optional<MoreRewrites>& more_rewrites = std::nullopt) {
    const auto& highway = columns.highway;
    if (positions.ndim() != 2 || positions.shape(1) != 2) throw ggg::UsageError("positions must have shape (N, 2)");
    if (edges.ndim() != 2 || edges.shape(1) != 2) throw ggg::UsageError("edges must have shape (M, 2)");
    const py::ssize_t n = positions.shape(0);
    const py::ssize_t m = edges.shape(0);
    if (symbols && (symbols->ndim() != 1 || symbols->shape(0) != n)) throw ggg::UsageError("vertex_symbols must have shape (N,)");
    if (frames && (frames->ndim() != 2 || frames->shape(0) != n || frames->shape(1) != 4)) throw ggg::UsageError("vertex_frames must have shape (N, 4)");
    auto check_column = [&](const auto& column, const char* name) {
        if (column && (column->ndim() != 1 || column->shape(0) != m)) throw ggg::UsageError(std::string(name) + " must have shape (M,)");
    };
    check_column(highway, "edge_highway");
    check_column(columns.lanes, "edge_lanes");
    check_column(columns.oneway, "edge_oneway");
    check_column(columns.way_ids, "edge_way_ids");
    check_column(columns.width, "edge_width");
    if (columns.names && static_cast<py::ssize_t>(columns.names->size()) != m) throw ggg::UsageError("edge_names must have M entries");
    if (osm_ids && (osm_ids->ndim() != 1 || osm_ids->shape(0) != n)) throw ggg::UsageError("vertex_osm_ids must have shape (N,)");
    if (columns.geometry) {
        const auto& [offsets, points] = *columns.geometry;
        if (offsets.ndim() != 1 || offsets.shape(0) != m + 1) throw ggg::UsageError("edge_geometry offsets must have shape (M+1,)");
        if (points.ndim() != 2 || points.shape(1) != 2) throw ggg::UsageError("edge_geometry points must have shape (P, 2)");
    }
    ggg::GeometricGraph g;
    g.origin = {origin_latlon.first, origin_latlon.second};
    if (!std::isfinite(g.origin.lat) || !std::isfinite(g.origin.lon) || std::abs(g.origin.lat) > 90 || std::abs(g.origin.lon) > 180) {
        throw ggg::InputError("origin_latlon must be (latitude, longitude) in degrees");
    }
    const auto p = positions.unchecked<2>();
    for (py::ssize_t i = 0; i < n; ++i) {
        if (!std::isfinite(p(i, 0)) || !std::isfinite(p(i, 1))) throw ggg::InputError("positions[" + std::to_string(i) + "] is not finite");
        g.add_vertex({p(i, 0), p(i, 1)}, osm_ids ? osm_ids->at(i) : 0);
        if (symbols) {
            const auto s = symbols->at(i);
            if (s < 0 || s > std::numeric_limits<ggg::Symbol>::max()) {
                throw ggg::InputError("vertex_symbols[" + std::to_string(i) + "] is not a symbol number");
            }
            g.symbols.back() = static_cast<ggg::Symbol>(s);
        }
        if (frames) {
            const auto f = frames->unchecked<2>();
            ggg::Similarity2 frame{f(i, 0), f(i, 1), {f(i, 2), f(i, 3)}};
            if (!std::isfinite(frame.a) || !std::isfinite(frame.b) || !frame.t.allFinite() || frame.scale() <= 0) {
                throw ggg::InputError("vertex_frames[" + std::to_string(i) + "] is not a valid frame");
            }
            g.frames.back() = frame;
        }
    }
    const auto e = edges.unchecked<2>();
    std::unordered_set<std::uint64_t> seen;
    for (py::ssize_t i = 0; i < m; ++i) {
        const auto u = e(i, 0), v = e(i, 1);
        if (u < 0 || v < 0 || u >= n || v >= n) throw ggg::InputError("edges[" + std::to_string(i) + "] refers to a vertex out of range");
        if (u == v) throw ggg::InputError("edges[" + std::to_string(i) + "] joins a vertex to itself");
        if (!seen.insert((static_cast<std::uint64_t>(std::min(u, v)) << 32) | static_cast<std::uint64_t>(std::max(u, v))).second) {
            throw ggg::InputError("edges[" + std::to_string(i) + "] repeats an edge between vertices " + std::to_string(u) + " and " +
                                  std::to_string(v));
        }
        ggg::EdgeAttributes a{ggg::HighwayClass::road};
        const std::string at = "[" + std::to_string(i) + "]";
        if (highway) {
            const auto c = highway->at(i);
            if (c < 0 || c >= ggg::highway_class_count) throw ggg::InputError("edge_highway" + at + " is not a class code");
            a.highway = static_cast<ggg::HighwayClass>(c);
        }
        if (columns.lanes) {
            const auto lanes = columns.lanes->at(i);
            if (lanes < 0 || lanes > 50) throw ggg::InputError("edge_lanes" + at + " must be in [0, 50]");
            a.lanes = static_cast<std::int16_t>(lanes);
        }
        if (columns.oneway) {
            const auto oneway = columns.oneway->at(i);
            if (oneway < -1 || oneway > 1) throw ggg::InputError("edge_oneway" + at + " must be -1, 0 or 1");
            a.oneway = static_cast<std::int8_t>(oneway);
        }
        if (columns.way_ids) a.way_id = columns.way_ids->at(i);
        if (columns.width) {
            const double w = columns.width->at(i);
            if (!std::isnan(w) && !(w > 0 && std::isfinite(w))) throw ggg::InputError("edge_width" + at + " must be > 0 or NaN");
            a.width_m = w;
        }
        if (columns.names) a.name = (*columns.names)[static_cast<std::size_t>(i)];
        std::vector<ggg::Vec2> line;
        if (columns.geometry) {
            const auto& [offsets, points] = *columns.geometry;
            const auto begin = offsets.at(i), end = offsets.at(i + 1);
            if (begin < 0 || end < begin + 2 || end > points.shape(0)) throw ggg::InputError("edge_geometry offsets" + at + " are out of range");
            const auto pts = points.unchecked<2>();
            for (auto k = begin; k < end; ++k) {
                if (!std::isfinite(pts(k, 0)) || !std::isfinite(pts(k, 1))) throw ggg::InputError("edge_geometry points[" + std::to_string(k) + "] is not finite");
                line.emplace_back(pts(k, 0), pts(k, 1));
            }
            if ((line.front() - g.positions[static_cast<std::size_t>(u)]).norm() > 1e-6 ||
                (line.back() - g.positions[static_cast<std::size_t>(v)]).norm() > 1e-6) {
                throw ggg::InputError("edge_geometry" + at + " does not start and end at the edge's vertices");
            }
            line.front() = g.positions[static_cast<std::size_t>(u)];
            line.back() = g.positions[static_cast<std::size_t>(v)];
        }
        g.add_edge(static_cast<ggg::VertexId>(u), static_cast<ggg::VertexId>(v), a, line);
    }
    if (more_rewrites) set_more_rewrites(g, *more_rewrites);
    return g;
}

py::object json_to_python(const nlohmann::json& j) { return py::module_::import("json").attr("loads")(j.dump()); }

py::list rule_summaries(const ggg::Grammar& g) {
    py::list out;
    const std::vector<int> levels = ggg::rule_levels(g);
    for (std::size_t i = 0; i < g.rules.size(); ++i) {
        const ggg::Rule& r = g.rules[i];
        py::dict d;
        d["level"] = levels[i];
        d["symbol"] = r.symbol;
        d["name"] = g.symbol_name(r.symbol);
        d["vertices"] = r.vertices.size();
        d["edges"] = r.edges.size();
        d["uses"] = r.uses;
        std::size_t nonterminals = 0, embedding = 0;
        for (const auto& v : r.vertices) {
            nonterminals += v.symbol != 0;
            embedding += v.embedding.size();
        }
        d["nonterminals"] = nonterminals;
        d["embedding_points"] = embedding;
        out.append(d);
    }
    return out;
}

py::tuple derive(const ggg::Grammar& grammar, std::optional<ggg::GeometricGraph> start, int steps, std::int64_t max_vertices,
                 double tolerance, std::optional<double> tolerance_m, bool strict, std::optional<py::function> progress) {
    ggg::DeriveOptions options;
    options.max_steps = steps;
    options.max_vertices = ggg::python::count_arg("max_vertices", max_vertices, 1);
    options.tolerance = tolerance_m ? *tolerance_m : tolerance;
    options.tolerance_relative = !tolerance_m;
    options.strict = strict;
    ggg::GeometricGraph graph = start ? std::move(*start) : grammar.axiom_graph();
    PythonProgress reporter(std::move(progress));
    const ggg::DeriveReport report =
        reporter.run([&](const ggg::ProgressCallback& cb) { return ggg::derive(graph, grammar, options, cb); });
    py::dict r = ggg::python::to_python(ggg::derive_report_json(graph, report));
    r["source_vertex"] = column(report.source_vertex);
    return py::make_tuple(std::move(graph), r);
}

} // namespace

PYBIND11_MODULE(ggg, m) {
    m.doc() = "Geometric graph grammars of road networks (native library)";
    m.attr("__version__") = GGG_VERSION;

    static py::exception<ggg::Error> error(m, "Error", PyExc_Exception);
    static py::exception<ggg::InputError> input_error(m, "InputError", error.ptr());
    static py::exception<ggg::GrammarError> grammar_error(m, "GrammarError", error.ptr());
    static py::exception<ggg::Cancelled> cancelled(m, "Cancelled", error.ptr());
    // Bad usage is also a ValueError, what Python code expects of an argument out of range.
    static py::exception<ggg::UsageError> usage_error(m, "UsageError", py::make_tuple(error, py::handle(PyExc_ValueError)));
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const ggg::InputError& e) {
            input_error(e.what());
        } catch (const ggg::GrammarError& e) {
            grammar_error(e.what());
        } catch (const ggg::Cancelled& e) {
            cancelled(e.what());
        } catch (const ggg::UsageError& e) {
            usage_error(e.what());
        } catch (const ggg::Error& e) {
            error(e.what());
        }
    });

    m.def("highway_classes", [] {
        std::vector<std::string> names;
        for (int c = 0; c < ggg::highway_class_count; ++c) names.emplace_back(ggg::highway_name(static_cast<ggg::HighwayClass>(c)));
        return names;
    }, "Highway class names; the index is the class code used in edge_highway.");
    m.def("highway_ranks", [] {
        std::vector<int> ranks;
        for (int c = 0; c < ggg::highway_class_count; ++c) ranks.push_back(ggg::highway_rank(static_cast<ggg::HighwayClass>(c)));
        return ranks;
    }, "Importance rank per class code (1 = most important).");
    m.def(
        "road_widths",
        [](const ggg::GeometricGraph& g, std::optional<std::vector<double>> class_widths, double lane_width) {
            ggg::RoadWidthRule rule;
            rule.lane_width_m = lane_width;
            if (class_widths) rule.class_widths_m = *class_widths;
            return column(ggg::road_widths(g, rule));
        },
        py::arg("graph"), py::arg("class_widths") = py::none(), py::arg("lane_width") = ggg::RoadWidthRule{}.lane_width_m,
        "Width in metres of each edge (M,): its `width` tag where that is a positive number, else its lanes times\n"
        "lane_width, else the width of its class (class_widths: one per class code, as ggg.highway_classes(); default:\n"
        "ggg.default_widths()). The rule of the imported road surfaces and of ggg.city_layout.");
    m.def("default_widths", [] {
        py::dict widths;
        for (int c = 0; c < ggg::highway_class_count; ++c) {
            const auto cls = static_cast<ggg::HighwayClass>(c);
            widths[py::str(std::string(ggg::highway_name(cls)))] = ggg::highway_default_width(cls);
        }
        return widths;
    }, "Default paved width in metres per highway class.");

    py::class_<ggg::GeometricGraph>(m, "Graph", "A road graph: vertices in metres of a local frame, edges with road attributes")
        .def_static("from_arrays",
                    [](const DoubleArray& positions, const IntArray& edges, std::pair<double, double> origin_latlon,
                       std::optional<IntArray> symbols, std::optional<DoubleArray> frames, std::optional<IntArray> osm_ids,
                       std::optional<IntArray> highway, std::optional<DoubleArray> width, std::optional<IntArray> lanes,
                       std::optional<IntArray> oneway, std::optional<IntArray> way_ids, std::optional<std::vector<std::string>> names,
                       std::optional<std::pair<IntArray, DoubleArray>> geometry, std::optional<MoreRewrites> more_rewrites) {
                        return graph_from_arrays(positions, edges, origin_latlon, std::move(symbols), std::move(frames), std::move(osm_ids),
                                                 EdgeColumns{std::move(highway), std::move(lanes), std::move(oneway), std::move(way_ids),
                                                             std::move(width), std::move(names), std::move(geometry)},
                                                 more_rewrites);
                    },
                    py::arg("positions"), py::arg("edges"), py::arg("origin_latlon") = std::pair<double, double>{0.0, 0.0},
                    py::arg("vertex_symbols") = py::none(), py::arg("vertex_frames") = py::none(), py::arg("vertex_osm_ids") = py::none(),
                    py::arg("edge_highway") = py::none(), py::arg("edge_width") = py::none(), py::arg("edge_lanes") = py::none(),
                    py::arg("edge_oneway") = py::none(), py::arg("edge_way_ids") = py::none(), py::arg("edge_names") = py::none(),
                    py::arg("edge_geometry") = py::none(), py::arg("more_rewrites") = py::none(),
                    "A graph from (N,2) positions in metres and (M,2) vertex index pairs. Optional columns as the Graph\n"
                    "properties of the same names: vertex_symbols (N,), vertex_frames (N,4), vertex_osm_ids (N,),\n"
                    "edge_highway (M,) (else 'road'), edge_width (M,) (NaN = untagged), edge_lanes, edge_oneway,\n"
                    "edge_way_ids (M,), edge_names (M strings), edge_geometry (offsets (M+1,), points (P,2)),\n"
                    "more_rewrites (vertices (K,), symbols (K,), frames (K,4)).")
        .def_property_readonly("vertex_symbols", [](const ggg::GeometricGraph& g) { return column(g.symbols); })
        .def_property_readonly("vertex_frames", [](const ggg::GeometricGraph& g) {
            py::array_t<double> out({static_cast<py::ssize_t>(g.vertex_count()), py::ssize_t{4}});
            auto view = out.mutable_unchecked<2>();
            for (std::size_t v = 0; v < g.vertex_count(); ++v) {
                const auto i = static_cast<py::ssize_t>(v);
                view(i, 0) = g.frames[v].a;
                view(i, 1) = g.frames[v].b;
                view(i, 2) = g.frames[v].t.x();
                view(i, 3) = g.frames[v].t.y();
            }
            return out;
        }, "(N,4) frames a, b, tx, ty: x -> [[a,-b],[b,a]] x + t, with scale hypot(a,b) and angle atan2(b,a)")
        .def_property_readonly("more_rewrites", [](const ggg::GeometricGraph& g) {
            const auto k = static_cast<py::ssize_t>(g.more_rewrites.size());
            py::array_t<std::int32_t> at(k);
            py::array_t<std::int64_t> symbols(k);
            py::array_t<double> frames({k, py::ssize_t{4}});
            auto a = at.mutable_unchecked<1>();
            auto s = symbols.mutable_unchecked<1>();
            auto f = frames.mutable_unchecked<2>();
            for (py::ssize_t i = 0; i < k; ++i) {
                const ggg::PendingRewrite& r = g.more_rewrites[static_cast<std::size_t>(i)];
                a(i) = r.vertex;
                s(i) = r.symbol;
                f(i, 0) = r.frame.a;
                f(i, 1) = r.frame.b;
                f(i, 2) = r.frame.t.x();
                f(i, 3) = r.frame.t.y();
            }
            return py::make_tuple(at, symbols, frames);
        }, "Rewrites pending at a vertex besides its own symbol and frame, where rules placed nonterminals with\n"
           "different frames at one place: (vertices (K,), symbols (K,), frames (K,4)), in vertex order")
        .def_property_readonly("vertex_count", &ggg::GeometricGraph::vertex_count)
        .def_property_readonly("edge_count", &ggg::GeometricGraph::edge_count)
        .def_property_readonly("positions", [](const ggg::GeometricGraph& g) { return points(g.positions); })
        .def_property_readonly("edges", [](const ggg::GeometricGraph& g) {
            py::array_t<std::int32_t> out({static_cast<py::ssize_t>(g.edge_count()), py::ssize_t{2}});
            if (g.edge_count()) std::memcpy(out.mutable_data(), g.edges.data(), g.edge_count() * 2 * sizeof(std::int32_t));
            return out;
        })
        .def_property_readonly("vertex_osm_ids", [](const ggg::GeometricGraph& g) { return column(g.vertex_osm_ids); })
        .def_property_readonly("edge_highway", [](const ggg::GeometricGraph& g) { return column_as<std::int32_t>(g.edge_highway); })
        .def_property_readonly("edge_rank", [](const ggg::GeometricGraph& g) {
            py::array_t<std::int32_t> out(static_cast<py::ssize_t>(g.edge_count()));
            auto view = out.mutable_unchecked<1>();
            for (std::size_t e = 0; e < g.edge_count(); ++e) view(static_cast<py::ssize_t>(e)) = ggg::highway_rank(g.edge_highway[e]);
            return out;
        })
        .def_property_readonly("edge_width", [](const ggg::GeometricGraph& g) { return column(g.edge_width_m); })
        .def_property_readonly("edge_lanes", [](const ggg::GeometricGraph& g) { return column_as<std::int32_t>(g.edge_lanes); })
        .def_property_readonly("edge_oneway", [](const ggg::GeometricGraph& g) { return column(g.edge_oneway); })
        .def_property_readonly("edge_way_ids", [](const ggg::GeometricGraph& g) { return column(g.edge_way_ids); })
        .def_property_readonly("edge_names", [](const ggg::GeometricGraph& g) {
            std::vector<std::string> names;
            names.reserve(g.edge_count());
            for (std::size_t e = 0; e < g.edge_count(); ++e) names.emplace_back(g.edge_name(static_cast<ggg::EdgeId>(e)));
            return names;
        })
        .def("edge_geometry", [](const ggg::GeometricGraph& g) { return py::make_tuple(column(g.geometry_offsets), points(g.geometry)); },
             "(offsets (M+1,) int64, points (P,2) float64): edge i runs through points[offsets[i]:offsets[i+1]]")
        .def_property_readonly("origin_latlon", [](const ggg::GeometricGraph& g) { return py::make_tuple(g.origin.lat, g.origin.lon); })
        .def_property_readonly("total_length_m", &ggg::GeometricGraph::total_length)
        .def_property_readonly("crs", [](const ggg::GeometricGraph& g) { return ggg::local_crs(g.origin); },
                               "PROJ string of the local frame (transverse Mercator on origin_latlon)")
        .def("info", [](const ggg::GeometricGraph& g) {
            return py::module_::import("json").attr("loads")(ggg::graph_info(g).dump());
        }, "The summary `ggg info` prints, as a dict.")
        .def("write", [](const ggg::GeometricGraph& g, const std::string& path) {
            py::gil_scoped_release release;
            ggg::write_graph(g, path);
        }, py::arg("path"), "Write as GeoJSON (.geojson) or the project's own format (.ggraph).")
        .def("__repr__", [](const ggg::GeometricGraph& g) {
            return "<ggg.Graph " + std::to_string(g.vertex_count()) + " vertices, " + std::to_string(g.edge_count()) + " edges>";
        });

    py::class_<ggg::Grammar>(m, "Grammar", "A geometric graph grammar: rules and an axiom")
        .def_property_readonly("name", [](const ggg::Grammar& g) { return g.name; })
        .def_property_readonly("symbols", [](const ggg::Grammar& g) { return g.symbol_names; },
                               "Nonterminal names; symbol k is symbols[k-1] (0 is the terminal)")
        .def_property_readonly("rules", &rule_summaries, "One dict per rule: symbol, name, level, vertices, edges, nonterminals, embedding_points, uses")
        .def_property_readonly("origin_latlon", [](const ggg::Grammar& g) { return py::make_tuple(g.origin.lat, g.origin.lon); })
        .def_property_readonly("learned", [](const ggg::Grammar& g) { return !g.encoding.empty(); },
                               "True for a grammar learned from a graph (ggg.learn), which ggg.decode turns back into it")
        .def_property_readonly("mode", [](const ggg::Grammar& g) { return g.encoding.mode; }, "'paper', 'lossless' or '' (not learned)")
        .def_property_readonly("levels", [](const ggg::Grammar& g) { return g.encoding.levels; }, "Levels of hierarchy of a learned grammar")
        .def_property_readonly("instance_count", [](const ggg::Grammar& g) { return g.encoding.instances.size(); })
        .def("axiom_graph", &ggg::Grammar::axiom_graph, "The axiom as a Graph (nonterminal vertices carry their frames)")
        .def("rule_graph", [](const ggg::Grammar& g, ggg::Symbol symbol) {
            const ggg::Rule* rule = g.rule_for(symbol);
            if (!rule) throw ggg::UsageError("no rule for symbol " + std::to_string(symbol));
            ggg::GeometricGraph out;
            for (const auto& v : rule->vertices) {
                out.add_vertex(v.position);
                out.symbols.back() = v.symbol;
                out.frames.back() = v.transform.at(v.position);
            }
            for (const auto& e : rule->edges) out.add_edge(e.a, e.b, ggg::EdgeAttributes{e.highway});
            return out;
        }, py::arg("symbol"), "The right side S of the rule for `symbol`, in the rule's frame (unit scale, no rotation)")
        .def("to_json", [](const ggg::Grammar& g) { return ggg::grammar_to_json(g).dump(1); })
        .def("write", [](const ggg::Grammar& g, const std::string& path) { ggg::write_grammar(g, path); }, py::arg("path"))
        .def("__repr__", [](const ggg::Grammar& g) {
            return "<ggg.Grammar '" + g.name + "' " + std::to_string(g.rules.size()) + " rules>";
        });
    m.def("read_grammar", &ggg::read_grammar, py::arg("path"), "Read a grammar file (raises ggg.GrammarError naming the place of a problem)");
    m.def("parse_grammar", &ggg::parse_grammar, py::arg("text"), py::arg("name") = "grammar", "A grammar from JSON text");
    m.def("derive", &derive, py::arg("grammar"), py::arg("graph") = py::none(), py::arg("steps") = ggg::DeriveOptions{}.max_steps,
          py::arg("max_vertices") = ggg::DeriveOptions{}.max_vertices, py::arg("tolerance") = ggg::DeriveOptions{}.tolerance,
          py::arg("tolerance_m") = py::none(), py::arg("strict") = ggg::DeriveOptions{}.strict, py::arg("progress") = py::none(),
          "Derive up to `steps` parallel rewriting steps from `graph` (default: the grammar's axiom).\n"
          "Returns (Graph, report dict with vertices, edges, steps, stopped_by_budget, converged, ...).\n"
          "`tolerance` is relative to the rewritten vertex's scale; `tolerance_m` (metres) replaces it.");

    ggg::python::bind_analysis(m);
    ggg::python::bind_learning(m);
    ggg::python::bind_synthesis(m);

    m.def("read_graph", &read_graph, py::arg("path"), py::arg("highways") = "drivable", py::arg("keep_shape_nodes") = false,
          py::arg("consolidate_m") = 0.0, py::arg("origin_latlon") = py::none(), py::arg("progress") = py::none(),
          "Read a road graph from an OSM file (.osm, .osm.pbf, .osm.bz2, .osm.gz), GeoJSON or .ggraph.\n"
          "origin_latlon=(lat, lon) puts it in the local frame of that origin (default: centred on the data).\n"
          "progress(fraction, message) may return False to cancel (raises ggg.Cancelled).");

    // --- City blocks and the 3-D city's ground plan (planar_faces.hpp, city_layout.hpp) ---
    {
        auto face_arrays = [](const ggg::PlanarFaces& f, py::dict& d) {
            d["ring_offsets"] = column(f.ring_offsets);
            d["points"] = points(f.points);
            d["ring_face"] = column(f.ring_face);
            d["face_area"] = column(f.face_area);
            d["face_component"] = column(f.face_component);
            d["face_dangling"] = column(f.face_dangling);
            d["face_edge_offsets"] = column(f.face_edge_offsets);
            d["face_edges"] = column(f.face_edges);
            d["face_edge_reversed"] = column(f.face_edge_reversed);
            d["components"] = f.components;
            d["traced_faces"] = f.traced_faces;
            d["outer_dropped"] = f.outer_dropped;
            d["nonpositive_dropped"] = f.nonpositive_dropped;
            d["dangling_edges"] = f.dangling_edges;
            d["genus"] = f.genus;
        };
        m.def("planar_faces", [face_arrays](const ggg::GeometricGraph& g, bool remove_dangling, bool keep_outer) {
            ggg::PlanarFaceOptions options;
            options.remove_dangling = remove_dangling;
            options.keep_outer = keep_outer;
            ggg::PlanarFaces faces;
            {
                py::gil_scoped_release release;
                faces = ggg::planar_faces(g, options);
            }
            py::dict d;
            face_arrays(faces, d);
            return d;
        }, py::arg("graph"), py::arg("remove_dangling") = true, py::arg("keep_outer") = false,
           "The faces (city blocks) of the graph drawn in the plane, using the edge polylines.\n"
           "Returns a dict of numpy arrays: ring_offsets (R+1,), points (P,2) (rings not closed, bounded faces\n"
           "counter-clockwise, holes clockwise), ring_face (R,), face_area (F,) signed m^2, face_component,\n"
           "face_dangling (dead ends and other bridges inside each face), face_edge_offsets/face_edges/\n"
           "face_edge_reversed (each face's boundary walk), and counts: components, traced_faces, outer_dropped,\n"
           "nonpositive_dropped, dangling_edges, genus (> 0 where roads cross without a vertex).\n"
           "remove_dangling cuts bridges out of the rings; keep_outer keeps each component's outer face.");

        m.def("city_layout", [face_arrays](const ggg::GeometricGraph& g, std::optional<DoubleArray> half_widths, double sidewalk_m,
                                           double lot_min_m, double lot_max_m, double depth_min_m, double depth_max_m, double gap_m,
                                           double min_building_area_m2, double max_block_area_m2, double min_yard_area_m2, double floor_height_m,
                                           const py::int_& seed, unsigned threads,
                                           std::optional<py::function> progress) {
            ggg::CityLayoutOptions options;
            if (half_widths) {
                if (half_widths->ndim() != 1 || static_cast<std::size_t>(half_widths->shape(0)) != g.edge_count()) {
                    throw ggg::UsageError("half_widths must have shape (M,) for M = " + std::to_string(g.edge_count()) + " edges");
                }
                options.half_widths.assign(half_widths->data(), half_widths->data() + half_widths->shape(0));
            }
            options.sidewalk_m = sidewalk_m;
            options.lot_min_m = lot_min_m;
            options.lot_max_m = lot_max_m;
            options.depth_min_m = depth_min_m;
            options.depth_max_m = depth_max_m;
            options.gap_m = gap_m;
            options.min_building_area_m2 = min_building_area_m2;
            options.max_block_area_m2 = max_block_area_m2;
            options.min_yard_area_m2 = min_yard_area_m2;
            options.floor_height_m = floor_height_m;
            options.seed = ggg::python::seed_arg(seed);
            options.threads = threads;
            PythonProgress reporter(std::move(progress));
            const ggg::CityLayout layout =
                reporter.run([&](const ggg::ProgressCallback& cb) { return ggg::city_layout(g, options, cb); });
            py::dict d;
            auto polygons = [&d](const char* name, const ggg::PolygonSet& set, const char* owner) {
                d[(std::string(name) + "_offsets").c_str()] = column(set.offsets);
                d[(std::string(name) + "_points").c_str()] = points(set.points);
                d[(std::string(name) + "_" + owner).c_str()] = column(set.owner);
            };
            polygons("road", layout.roads, "edge");
            d["road_piece"] = column_as<std::uint8_t>(layout.road_piece);
            polygons("block", layout.blocks, "face");
            polygons("yard", layout.yards, "face");
            polygons("building", layout.buildings, "face");
            d["building_depth"] = column(layout.building_depth);
            d["building_height"] = column(layout.building_height_m);
            d["building_tint"] = column(layout.building_tint);
            d["empty_blocks"] = layout.empty_blocks;
            py::dict faces;
            face_arrays(layout.faces, faces);
            d["faces"] = faces;
            return d;
        }, py::arg("graph"), py::arg("half_widths") = py::none(), py::arg("sidewalk_m") = 3.0, py::arg("lot_min_m") = 9.0,
           py::arg("lot_max_m") = 26.0, py::arg("depth_min_m") = 10.0, py::arg("depth_max_m") = 18.0, py::arg("gap_m") = 0.6,
           py::arg("min_building_area_m2") = 30.0, py::arg("max_block_area_m2") = 250000.0, py::arg("min_yard_area_m2") = 400.0,
           py::arg("floor_height_m") = ggg::CityLayoutOptions{}.floor_height_m, py::arg("seed") = 1, py::arg("threads") = 0, py::arg("progress") = py::none(),
           "The ground plan of a 3-D city: road pieces (segment rectangles, bend triangles, junction discs; road_piece 0/1/2,\n"
           "road_edge the edge, for a junction its most important one), block kerb outlines, yards (blocks inset by the\n"
           "sidewalk) and building footprints (lots of seeded frontage in a band along each yard), all as simple\n"
           "counter-clockwise polygons: <name>_offsets (K+1,), <name>_points (P,2), <name>_face / road_edge (K,).\n"
           "Faces larger than max_block_area_m2 (fields, forests) and yards smaller than min_yard_area_m2 (traffic\n"
           "islands) get no buildings.\n"
           "half_widths (M,) in metres (default: half the class default width). 'faces' holds planar_faces().");
    }
}
