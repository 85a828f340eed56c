// The analyzer in Python: ggg.analyze and ggg.find_similar. Occurrences come out as one
// (n, k) int32 array per isogroup, never as Python objects per occurrence.
#include <chrono>
#include <optional>

#include <pybind11/stl.h>

#include "common.hpp"
#include "ggg/io/reports.hpp"
#include "ggg/analysis/analyzer.hpp"
#include "ggg/encoding/grammar_encoder.hpp"
#include "ggg/graph/road_widths.hpp"
#include "ggg/grammar/rewriting.hpp"
#include "ggg/synthesis/city_layout.hpp"
#include "ggg/synthesis/growth.hpp"
#include "ggg/error.hpp"

namespace ggg::python {

namespace {

std::vector<VertexId> vertex_list(const py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>& ids,
                                  const GeometricGraph& g) {
    if (ids.ndim() != 1) throw UsageError("seed: expected a 1-D array of vertex ids");
    std::vector<VertexId> out;
    const auto view = ids.unchecked<1>();
    for (py::ssize_t i = 0; i < view.shape(0); ++i) {
        const std::int64_t v = view(i);
        if (v < 0 || static_cast<std::size_t>(v) >= g.vertex_count()) {
            throw UsageError("seed: vertex " + std::to_string(v) + " is not in the graph (" +
                             std::to_string(g.vertex_count()) + " vertices)");
        }
        out.push_back(static_cast<VertexId>(v));
    }
    return out;
}

py::array_t<std::int32_t> occurrence_array(const Isogroup& g) {
    const auto n = static_cast<py::ssize_t>(g.frequency());
    const auto k = static_cast<py::ssize_t>(g.order());
    py::array_t<std::int32_t> out({n, k});
    if (!g.vertices.empty()) std::memcpy(out.mutable_data(), g.vertices.data(), g.vertices.size() * sizeof(std::int32_t));
    return out;
}

py::array_t<double> transform_array(const std::vector<Similarity2>& transforms) {
    py::array_t<double> out({static_cast<py::ssize_t>(transforms.size()), py::ssize_t{4}});
    auto view = out.mutable_unchecked<2>();
    for (std::size_t i = 0; i < transforms.size(); ++i) {
        const auto r = static_cast<py::ssize_t>(i);
        view(r, 0) = transforms[i].a;
        view(r, 1) = transforms[i].b;
        view(r, 2) = transforms[i].t.x();
        view(r, 3) = transforms[i].t.y();
    }
    return out;
}

py::array_t<std::int32_t> edge_array(const Pattern& p) {
    py::array_t<std::int32_t> out({static_cast<py::ssize_t>(p.edges.size()), py::ssize_t{2}});
    auto view = out.mutable_unchecked<2>();
    for (std::size_t e = 0; e < p.edges.size(); ++e) {
        view(static_cast<py::ssize_t>(e), 0) = p.edges[e][0];
        view(static_cast<py::ssize_t>(e), 1) = p.edges[e][1];
    }
    return out;
}

} // namespace

void bind_analysis(py::module_& m) {
    py::class_<AnalyzedIsogroup>(m, "Isogroup",
                                 "A street pattern and every place it occurs (paper 3.1), with its non-overlapping selection")
        .def_property_readonly("order", [](const AnalyzedIsogroup& a) { return a.group.order(); }, "Vertices in the pattern")
        .def_property_readonly("edge_count", [](const AnalyzedIsogroup& a) { return a.group.pattern.edges.size(); })
        .def_property_readonly("frequency", [](const AnalyzedIsogroup& a) { return a.group.frequency(); }, "Number of occurrences")
        .def("__len__", [](const AnalyzedIsogroup& a) { return a.group.frequency(); })
        .def_property_readonly("occurrences", [](const AnalyzedIsogroup& a) { return occurrence_array(a.group); },
                               "(n, k) int32: graph vertex of pattern vertex j in occurrence i")
        .def_property_readonly("transforms", [](const AnalyzedIsogroup& a) { return transform_array(a.group.transforms); },
                               "(n, 4) float64 (a, b, tx, ty): pattern coordinates -> graph metres, x -> (a -b; b a) x + t")
        .def_property_readonly("non_overlapping", [](const AnalyzedIsogroup& a) { return column(a.selection.non_overlapping); },
                               "Indices of the largest set of occurrences sharing no vertex")
        .def_property_readonly("selection_exact", [](const AnalyzedIsogroup& a) { return a.selection.exact; })
        .def_property_readonly("selection_method", [](const AnalyzedIsogroup& a) { return a.selection.method; })
        .def_property_readonly("gain", [](const AnalyzedIsogroup& a) { return a.selection.gain; },
                               "Description-length gain of encoding the non-overlapping occurrences")
        .def_property_readonly("score", [](const AnalyzedIsogroup& a) { return a.score; },
                               "Frequency x convex-hull area added by the last vertex (paper 5.1)")
        .def_property_readonly("recounted", [](const AnalyzedIsogroup& a) { return a.recounted; },
                               "True when the occurrences are every copy within the tolerance of their mean pattern (exact recount)")
        .def_property_readonly("parent", [](const AnalyzedIsogroup& a) { return a.parent; },
                               "Index of the isogroup this one grew from, or -1")
        .def_property_readonly("pattern_positions", [](const AnalyzedIsogroup& a) { return points(a.group.pattern.positions); },
                               "(k, 2) canonical coordinates: centroid 0, RMS radius 1")
        .def_property_readonly("pattern_edges", [](const AnalyzedIsogroup& a) { return edge_array(a.group.pattern); })
        .def_property_readonly("pattern_symbols", [](const AnalyzedIsogroup& a) { return column(a.group.pattern.symbols); })
        .def_property_readonly("size_m", [](const AnalyzedIsogroup& a) { return a.group.pattern.metres_per_unit; },
                               "Mean RMS radius of the occurrences in metres")
        .def_property_readonly("aspect", [](const AnalyzedIsogroup& a) { return a.selection.shape.aspect; })
        .def_property_readonly("leaves", [](const AnalyzedIsogroup& a) { return a.selection.shape.leaves; })
        .def_property_readonly("irregularity_deg", [](const AnalyzedIsogroup& a) { return a.selection.shape.irregularity_deg; })
        .def("__repr__", [](const AnalyzedIsogroup& a) {
            return "<ggg.Isogroup order " + std::to_string(a.group.order()) + ", " + std::to_string(a.group.frequency()) +
                   " occurrences, " + std::to_string(a.selection.non_overlapping.size()) + " non-overlapping>";
        });

    py::class_<Analysis>(m, "Analysis", "The result of ggg.analyze")
        .def_readonly("isogroups", &Analysis::isogroups, "Best gain first (with a seed: the seed's group first)")
        .def_readonly("detected", &Analysis::detected)
        .def_readonly("stopped_by_budget", &Analysis::stopped_by_budget)
        .def_property_readonly("orders", [](const Analysis& a) { return to_python(detection_orders_json(a.orders)); },
                               "The detection's counts per order: a list of dicts (order, parents, candidates, children, groups,\n"
                               "expanded_next, occurrences)")
        .def(
            "report",
            [](const Analysis& a, const GeometricGraph& graph, std::int64_t top, bool occurrence_osm_nodes, bool orders) {
                AnalysisReportOptions o;
                o.top = count_arg("top", top);
                o.occurrence_osm_nodes = occurrence_osm_nodes;
                o.orders = orders;
                return to_python(analysis_report_json(graph, a, o));
            },
            py::arg("graph"), py::arg("top") = AnalysisReportOptions{}.top,
            py::arg("occurrence_osm_nodes") = AnalysisReportOptions{}.occurrence_osm_nodes,
            py::arg("orders") = AnalysisReportOptions{}.orders,
            "The analysis as `ggg analyze` prints it (docs/cli.md), as a dict: graph, detected, stopped_by_budget and\n"
            "the isogroups (the best `top`; 0 = all), each with order, edge_count, occurrences, non_overlapping, score,\n"
            "gain, selection_exact, parent, size_m and recounted (and occurrence_osm_nodes, the OSM node ids of each\n"
            "occurrence, from `graph`, the graph analysed); with orders, the detection's counts per order.");

    m.def(
        "analyze",
        [](const GeometricGraph& g, std::pair<int, int> grid, double cut, bool full, int max_order, std::int64_t min_count,
           const std::string& scale, std::optional<py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>> seed,
           double tolerance, double min_aspect, std::int64_t min_leaves, double min_irregularity, std::int64_t recount,
           std::pair<double, double> scale_range, double max_seconds, double max_memory_mb, std::optional<py::function> progress) {
            AnalyzeOptions o;
            o.detection.angle_cells = grid.first;
            o.detection.distance_cells = grid.second;
            o.detection.cut = cut;
            o.detection.full = full;
            o.detection.max_order = max_order;
            o.detection.min_count = count_arg("min_count", min_count, 1);
            o.detection.max_seconds = max_seconds;
            o.detection.max_memory_mb = max_memory_mb;
            o.detection.scale_mode = scale_mode_from_name(scale);
            o.detection.min_scale = scale_range.first;
            o.detection.max_scale = scale_range.second;
            if (seed) o.seed = vertex_list(*seed, g);
            o.tolerance = tolerance;
            o.recount_top = count_arg("recount", recount);
            o.constraints.min_aspect = min_aspect;
            o.constraints.min_leaves = count_arg("min_leaves", min_leaves);
            o.constraints.min_irregularity_deg = min_irregularity;
            check_options(o);
            PythonProgress reporter(std::move(progress));
            return reporter.run([&](const ProgressCallback& cb) { return analyze(g, o, cb); });
        },
        py::arg("graph"), py::arg("grid") = std::pair<int, int>{DetectionOptions{}.angle_cells, DetectionOptions{}.distance_cells},
        py::arg("cut") = DetectionOptions{}.cut, py::arg("full") = false,
        py::arg("max_order") = DetectionOptions{}.max_order, py::arg("min_count") = 2, py::arg("scale") = "similarity", py::arg("seed") = py::none(),
        py::arg("tolerance") = AnalyzeOptions{}.tolerance, py::arg("min_aspect") = 0.0, py::arg("min_leaves") = 0,
        py::arg("min_irregularity") = 0.0, py::arg("recount") = 0,
        py::arg("scale_range") = std::pair<double, double>{0.5, 2.0}, py::arg("max_seconds") = DetectionOptions{}.max_seconds,
        py::arg("max_memory_mb") = DetectionOptions{}.max_memory_mb, py::arg("progress") = py::none(),
        "Find the street patterns that repeat (isogroups) and rank them by description-length gain.\n"
        "grid=(angle cells, distance cells) of the vertex expansion; cut: share of the least frequent patterns not grown\n"
        "further; full=True grows all; seed: vertex ids of a connected piece to start from (its isogroup comes first).\n"
        "scale='range': sizes within scale_range=(min, max) of each other (a group spans at most max/min).\n"
        "min_aspect / min_leaves / min_irregularity: selection constraints. recount: the leading N isogroups are counted\n"
        "exactly (every copy within `tolerance`). max_seconds / max_memory_mb: budgets after which\n"
        "patterns stop growing (0 = none; Analysis.stopped_by_budget tells). progress(fraction, message) may return False\n"
        "to cancel (raises ggg.Cancelled).");

    m.def(
        "find_similar",
        [](const GeometricGraph& g, py::array_t<std::int64_t, py::array::c_style | py::array::forcecast> seed, double tolerance,
           const std::string& scale, std::pair<double, double> scale_range, std::pair<int, int> grid, double cut,
           bool include_analysis_group, std::optional<py::function> progress) {
            AnalyzeOptions o;
            o.tolerance = tolerance;
            o.include_analysis_group = include_analysis_group;
            o.detection.scale_mode = scale_mode_from_name(scale);
            o.detection.min_scale = scale_range.first;
            o.detection.max_scale = scale_range.second;
            o.detection.angle_cells = grid.first;
            o.detection.distance_cells = grid.second;
            o.detection.cut = cut;
            const std::vector<VertexId> vertices = vertex_list(seed, g);
            PythonProgress reporter(std::move(progress));
            return reporter.run([&](const ProgressCallback& cb) {
                AnalyzedIsogroup a;
                a.group = find_similar(g, vertices, o, cb);
                std::vector<Isogroup> one{a.group};
                auto selected = select_isogroups(g, one);
                a.selection = std::move(selected.front());
                return a;
            });
        },
        py::arg("graph"), py::arg("seed"), py::arg("tolerance") = AnalyzeOptions{}.tolerance, py::arg("scale") = "similarity",
        py::arg("scale_range") = std::pair<double, double>{DetectionOptions{}.min_scale, DetectionOptions{}.max_scale},
        py::arg("grid") = std::pair<int, int>{DetectionOptions{}.angle_cells, DetectionOptions{}.distance_cells},
        py::arg("cut") = DetectionOptions{}.cut, py::arg("include_analysis_group") = AnalyzeOptions{}.include_analysis_group,
        py::arg("progress") = py::none(),
        "Every place where the piece of network induced by the `seed` vertices occurs again (the seed itself first).\n"
        "tolerance: largest vertex displacement relative to the piece's size. scale='range' accepts copies whose size\n"
        "is within scale_range=(min, max) times the seed's. include_analysis_group: also every copy that ggg.analyze\n"
        "with this grid and cut groups with the seed (it compares the copies with each other, not only with the seed).");

    m.def(
        "option_defaults",
        [] {
            // The analysis's keywords, for ggg.analyze and (with its own defaults) ggg.learn.
            auto analysis_keywords = [](const AnalyzeOptions& analysis) {
                const DetectionOptions& d = analysis.detection;
                py::dict k;
                k["angle_cells"] = d.angle_cells;
                k["distance_cells"] = d.distance_cells;
                k["cut"] = d.cut;
                k["full"] = d.full;
                k["max_order"] = d.max_order;
                k["min_count"] = d.min_count;
                k["tolerance"] = analysis.tolerance;
                k["include_analysis_group"] = analysis.include_analysis_group;
                k["min_aspect"] = analysis.constraints.min_aspect;
                k["min_leaves"] = analysis.constraints.min_leaves;
                k["min_irregularity"] = analysis.constraints.min_irregularity_deg;
                return k;
            };
            const LearnOptions learning;
            py::dict a = analysis_keywords(AnalyzeOptions{});
            py::dict l = analysis_keywords(learning.analysis);
            l["levels"] = learning.max_levels;
            l["complete"] = learning.complete;
            l["max_shape_error"] = learning.max_shape_error;
            l["max_vertex_error"] = learning.max_vertex_error_m;
            py::dict c;
            c["lane_width"] = RoadWidthRule{}.lane_width_m;
            c["floor_height_m"] = CityLayoutOptions{}.floor_height_m;
            c["sidewalk_m"] = CityLayoutOptions{}.sidewalk_m;
            const DeriveOptions derive;
            py::dict de;
            de["steps"] = derive.max_steps;
            de["max_vertices"] = derive.max_vertices;
            de["tolerance"] = derive.tolerance;
            de["strict"] = derive.strict;
            py::dict out;
            out["growth"] = grow_option_defaults();
            out["derive"] = de;
            out["analysis"] = a;
            out["learning"] = l;
            out["city"] = c;
            return out;
        },
        "The library's defaults of the analysis (ggg.analyze, ggg.find_similar), learning (ggg.learn) and the city\n"
        "(ggg.road_widths, ggg.city_layout), growth (ggg.grow_region) and derivation (ggg.derive), by the\n"
        "names of their keyword arguments (grid as angle_cells and distance_cells): the values the CLI, Python and\n"
        "the Blender add-on all start from.");
}

} // namespace ggg::python
