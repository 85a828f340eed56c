// The Python face of the library: numpy arrays in and out, the GIL released on long calls,
// progress through a callback, and C++ errors as Python exceptions with the user's message.
#include <cstring>
#include <optional>

#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "ggg/error.hpp"
#include "ggg/graph_info.hpp"
#include "ggg/io/read_graph.hpp"

namespace py = pybind11;

namespace {

template <typename T>
py::array_t<T> column(const std::vector<T>& values) {
    py::array_t<T> out(static_cast<py::ssize_t>(values.size()));
    if (!values.empty()) std::memcpy(out.mutable_data(), values.data(), values.size() * sizeof(T));
    return out;
}

template <typename Out, typename In>
py::array_t<Out> column_as(const std::vector<In>& values) {
    py::array_t<Out> out(static_cast<py::ssize_t>(values.size()));
    auto view = out.template mutable_unchecked<1>();
    for (std::size_t i = 0; i < values.size(); ++i) view(static_cast<py::ssize_t>(i)) = static_cast<Out>(values[i]);
    return out;
}

py::array_t<double> points(const std::vector<ggg::Vec2>& values) {
    py::array_t<double> out({static_cast<py::ssize_t>(values.size()), py::ssize_t{2}});
    auto view = out.mutable_unchecked<2>();
    for (std::size_t i = 0; i < values.size(); ++i) {
        view(static_cast<py::ssize_t>(i), 0) = values[i].x();
        view(static_cast<py::ssize_t>(i), 1) = values[i].y();
    }
    return out;
}

// Wraps a Python callable so that C++ can call it from a thread without the GIL. An
// exception inside the callable cancels the operation and is re-raised afterwards.
class PythonProgress {
public:
    explicit PythonProgress(std::optional<py::function> callable) : callable_(std::move(callable)) {}

    ggg::ProgressCallback callback() {
        if (!callable_) return {};
        return [this](double fraction, std::string_view message) {
            py::gil_scoped_acquire gil;
            try {
                py::object result = (*callable_)(fraction, std::string(message));
                return result.is_none() || result.cast<bool>();
            } catch (py::error_already_set& e) {
                error_ = std::move(e);
                return false;
            }
        };
    }

    void rethrow() {
        if (error_) {
            py::error_already_set e = std::move(*error_);
            error_.reset();
            throw e;
        }
    }

private:
    std::optional<py::function> callable_;
    std::optional<py::error_already_set> error_;
};

ggg::GeometricGraph read_graph(const std::string& path, const std::string& highways, bool keep_shape_nodes,
                               double consolidate_m, std::optional<py::function> progress) {
    ggg::ImportOptions options;
    options.highways = ggg::HighwayFilter::parse(highways);
    options.topology.keep_shape_nodes = keep_shape_nodes;
    options.topology.consolidate_m = consolidate_m;
    PythonProgress reporter(std::move(progress));
    std::optional<ggg::GeometricGraph> graph;
    try {
        py::gil_scoped_release release;
        graph = ggg::read_graph(path, options, nullptr, reporter.callback());
    } catch (const ggg::Cancelled&) {
        reporter.rethrow();
        throw;
    }
    return std::move(*graph);
}

ggg::GeometricGraph graph_from_arrays(const py::array_t<double, py::array::c_style | py::array::forcecast>& positions,
                                      const py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>& edges,
                                      std::pair<double, double> origin_latlon) {
    if (positions.ndim() != 2 || positions.shape(1) != 2) throw ggg::UsageError("positions must have shape (N, 2)");
    if (edges.ndim() != 2 || edges.shape(1) != 2) throw ggg::UsageError("edges must have shape (M, 2)");
    ggg::GeometricGraph g;
    g.origin = {origin_latlon.first, origin_latlon.second};
    const auto p = positions.unchecked<2>();
    for (py::ssize_t i = 0; i < p.shape(0); ++i) {
        if (!std::isfinite(p(i, 0)) || !std::isfinite(p(i, 1))) {
            throw ggg::InputError("positions[" + std::to_string(i) + "] is not finite");
        }
        g.add_vertex({p(i, 0), p(i, 1)});
    }
    const auto e = edges.unchecked<2>();
    const auto n = static_cast<std::int64_t>(g.vertex_count());
    for (py::ssize_t i = 0; i < e.shape(0); ++i) {
        const auto u = e(i, 0), v = e(i, 1);
        if (u < 0 || v < 0 || u >= n || v >= n) {
            throw ggg::InputError("edges[" + std::to_string(i) + "] refers to a vertex out of range");
        }
        g.add_edge(static_cast<ggg::VertexId>(u), static_cast<ggg::VertexId>(v), ggg::EdgeAttributes{ggg::HighwayClass::road});
    }
    return g;
}

} // namespace

PYBIND11_MODULE(ggg, m) {
    m.doc() = "Geometric graph grammars of road networks (native library)";
    m.attr("__version__") = GGG_VERSION;

    static py::exception<ggg::Error> error(m, "Error", PyExc_Exception);
    static py::exception<ggg::InputError> input_error(m, "InputError", error.ptr());
    static py::exception<ggg::GrammarError> grammar_error(m, "GrammarError", error.ptr());
    static py::exception<ggg::Cancelled> cancelled(m, "Cancelled", error.ptr());
    static py::exception<ggg::UsageError> usage_error(m, "UsageError", error.ptr());
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
    m.def("default_widths", [] {
        py::dict widths;
        for (int c = 0; c < ggg::highway_class_count; ++c) {
            const auto cls = static_cast<ggg::HighwayClass>(c);
            widths[py::str(std::string(ggg::highway_name(cls)))] = ggg::highway_default_width(cls);
        }
        return widths;
    }, "Default paved width in metres per highway class.");

    py::class_<ggg::GeometricGraph>(m, "Graph", "A road graph: vertices in metres of a local frame, edges with road attributes")
        .def_static("from_arrays", &graph_from_arrays, py::arg("positions"), py::arg("edges"),
                    py::arg("origin_latlon") = std::pair<double, double>{0.0, 0.0},
                    "A graph from (N,2) positions in metres and (M,2) vertex index pairs (class 'road').")
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

    m.def("read_graph", &read_graph, py::arg("path"), py::arg("highways") = "drivable", py::arg("keep_shape_nodes") = false,
          py::arg("consolidate_m") = 0.0, py::arg("progress") = py::none(),
          "Read a road graph from an OSM file (.osm, .osm.pbf, .osm.bz2, .osm.gz), GeoJSON or .ggraph.\n"
          "progress(fraction, message) may return False to cancel (raises ggg.Cancelled).");
}
