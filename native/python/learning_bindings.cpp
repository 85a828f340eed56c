// ggg.learn, ggg.decode and ggg.encoded_graph: grammar learning from Python.
#include <optional>
#include <utility>

#include <pybind11/stl.h>

#include "common.hpp"
#include "ggg/encoding/decoding.hpp"
#include "ggg/encoding/grammar_encoder.hpp"
#include "ggg/error.hpp"
#include "ggg/io/reports.hpp"

namespace ggg::python {

void bind_learning(py::module_& m) {
    m.def(
        "learn",
        [](const GeometricGraph& g, bool lossless, bool complete, int levels, std::pair<int, int> grid, double cut, bool full, int max_order,
           std::int64_t min_count, const std::string& scale, double min_aspect, std::int64_t min_leaves, double min_irregularity,
           double max_shape_error, double max_vertex_error, std::optional<py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>> seed,
           double max_seconds, double max_memory_mb, std::optional<py::function> progress) {
            LearnOptions o;
            o.lossless = lossless;
            o.complete = complete;
            o.max_levels = levels;
            o.analysis.detection.angle_cells = grid.first;
            o.analysis.detection.distance_cells = grid.second;
            o.analysis.detection.cut = cut;
            o.analysis.detection.full = full;
            o.analysis.detection.max_order = max_order;
            o.analysis.detection.min_count = count_arg("min_count", min_count, 1);
            o.analysis.detection.max_seconds = max_seconds;
            o.analysis.detection.max_memory_mb = max_memory_mb;
            o.analysis.detection.scale_mode = scale_mode_from_name(scale);
            o.analysis.constraints.min_aspect = min_aspect;
            o.analysis.constraints.min_leaves = count_arg("min_leaves", min_leaves);
            o.analysis.constraints.min_irregularity_deg = min_irregularity;
            o.max_shape_error = max_shape_error;
            o.max_vertex_error_m = max_vertex_error;
            if (seed) {
                const auto s = seed->unchecked<1>();
                for (py::ssize_t i = 0; i < s.shape(0); ++i) {
                    if (s(i) < 0 || static_cast<std::size_t>(s(i)) >= g.vertex_count()) throw UsageError("seed vertex " + std::to_string(s(i)) + " is out of range");
                    o.seed.push_back(static_cast<VertexId>(s(i)));
                }
            }
            check_options(o);
            PythonProgress reporter(std::move(progress));
            LearnResult result = reporter.run([&](const ProgressCallback& cb) { return learn_grammar(g, o, cb); });
            py::object stats = to_python(learn_report(g, result));
            return py::make_tuple(std::move(result.grammar), stats);
        },
        py::arg("graph"), py::arg("lossless") = false, py::arg("complete") = LearnOptions{}.complete,
        py::arg("levels") = LearnOptions{}.max_levels, py::arg("grid") = std::pair<int, int>{12, 10},
        py::arg("cut") = 0.8, py::arg("full") = false, py::arg("max_order") = LearnOptions::default_analysis().detection.max_order,
        py::arg("min_count") = 2, py::arg("scale") = "similarity", py::arg("min_aspect") = 0.0, py::arg("min_leaves") = 0,
        py::arg("min_irregularity") = 0.0, py::arg("max_shape_error") = LearnOptions{}.max_shape_error,
        py::arg("max_vertex_error") = LearnOptions{}.max_vertex_error_m,
        py::arg("seed") = py::none(), py::arg("max_seconds") = DetectionOptions{}.max_seconds,
        py::arg("max_memory_mb") = DetectionOptions{}.max_memory_mb, py::arg("progress") = py::none(),
        "Learn a grammar of the road graph: returns (Grammar, stats dict as `ggg learn` prints it).\n"
        "lossless=True stores per-vertex residuals so that decode() gives back exactly the graph's edges and\n"
        "positions (within 1e-6 m). levels: most passes of the encoder, each adding at most one level of\n"
        "hierarchy (0 = until nothing repeats). complete=True: encode until the axiom is a single vertex (smaller\n"
        "repeating patterns where nothing pays, then one rule used once for what never repeats). The analysis\n"
        "options are those of ggg.analyze; min_aspect / min_leaves / min_irregularity constrain the patterns\n"
        "that become rules. seed: vertex ids of a piece the user picked: its pattern becomes the first rule, with all its\n"
        "copies. max_seconds / max_memory_mb: the analysis budgets (the time is the whole learning's); where\n"
        "they stop it, the grammar holds the levels found so far and stats['stopped_by_budget'] is True.\n"
        "progress(fraction, message) is called per level and may return False to cancel.");

    m.def(
        "decode",
        [](const Grammar& grammar, std::optional<py::function> progress) {
            PythonProgress reporter(std::move(progress));
            return reporter.run([&](const ProgressCallback& cb) { return decode_grammar(grammar, nullptr, cb); });
        },
        py::arg("grammar"), py::arg("progress") = py::none(),
        "The road graph a learned grammar encodes (its axiom derived level by level).");

    m.def(
        "encoded_graph",
        [](const Grammar& grammar, int level, std::optional<py::function> progress) {
            PythonProgress reporter(std::move(progress));
            std::vector<VertexId> image;
            GeometricGraph g = reporter.run([&](const ProgressCallback& cb) { return encoded_graph(grammar, level, cb, &image); });
            return py::make_tuple(std::move(g), column(image));
        },
        py::arg("grammar"), py::arg("level"), py::arg("progress") = py::none(),
        "The graph encoded to `level` (0 = the streets, grammar.levels = the axiom) and, for each vertex of the\n"
        "decoded streets, the vertex of that graph that stands for it (int32). Nonterminal vertices carry their\n"
        "rule's symbol (Graph.vertex_symbols).");
}

} // namespace ggg::python
