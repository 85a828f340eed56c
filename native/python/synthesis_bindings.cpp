// ggg.grow_region (streets grown into a region with a grammar), ggg.replace_isogroup
// (terminal replacement) and ggg.compare (how alike two street networks are); and the
// JSON-to-Python conversion the bindings that return reports share.
#include <pybind11/stl.h>

#include "common.hpp"
#include "ggg/error.hpp"
#include "ggg/grammar/grammar.hpp"
#include "ggg/measures/network_comparison.hpp"
#include "ggg/analysis/analyzer.hpp"
#include "ggg/io/reports.hpp"
#include "ggg/synthesis/growth.hpp"
#include "ggg/synthesis/replacement.hpp"
#include "ggg/synthesis/street_hierarchy.hpp"

namespace ggg::python {

// nlohmann::json -> Python objects (dicts, lists, numbers, strings).
py::object to_python(const nlohmann::json& j) {
    switch (j.type()) {
    case nlohmann::json::value_t::object: {
        py::dict d;
        for (const auto& [key, value] : j.items()) d[py::str(key)] = to_python(value);
        return std::move(d);
    }
    case nlohmann::json::value_t::array: {
        py::list l;
        for (const auto& value : j) l.append(to_python(value));
        return std::move(l);
    }
    case nlohmann::json::value_t::string: return py::str(j.get<std::string>());
    case nlohmann::json::value_t::boolean: return py::bool_(j.get<bool>());
    case nlohmann::json::value_t::number_integer: return py::int_(j.get<std::int64_t>());
    case nlohmann::json::value_t::number_unsigned: return py::int_(j.get<std::uint64_t>());
    case nlohmann::json::value_t::number_float: return py::float_(j.get<double>());
    default: return py::none();
    }
}


void bind_synthesis(py::module_& m) {
    using DoubleArray = py::array_t<double, py::array::c_style | py::array::forcecast>;
    m.def(
        "grow_region",
        [](const GeometricGraph& base, const Grammar& grammar, DoubleArray region, const py::int_& seed, std::int64_t max_placements,
           std::int64_t max_vertices, std::int64_t patience, std::optional<std::vector<std::tuple<Symbol, double, double, double, double>>> placements,
           double border_m, bool hierarchy, bool trace_streets, std::optional<py::function> progress) {
            if (region.ndim() != 2 || region.shape(1) != 2) throw UsageError("region must have shape (N, 2): the polygon's corners in metres");
            std::vector<Vec2> ring;
            const auto r = region.unchecked<2>();
            for (py::ssize_t i = 0; i < r.shape(0); ++i) ring.emplace_back(r(i, 0), r(i, 1));
            GrowOptions o;
            o.seed = seed_arg(seed);
            o.max_placements = count_arg("max_placements", max_placements, 1);
            o.max_vertices = count_arg("max_vertices", max_vertices, 1);
            o.patience = count_arg("patience", patience); // 0: only the rules placed by hand
            o.border_m = border_m;
            o.continue_hierarchy = hierarchy;
            o.trace_streets = trace_streets;
            if (placements) {
                for (const auto& [symbol, x, y, scale, rotation] : *placements) o.placements.push_back({symbol, Vec2(x, y), Frame{scale, rotation}});
            }
            PythonProgress reporter(std::move(progress));
            GrowReport report;
            GeometricGraph grown = reporter.run([&](const ProgressCallback& cb) { return grow_region(base, grammar, ring, o, &report, cb); });
            py::object d = to_python(growth_report_json(report));
            return py::make_tuple(std::move(grown), d);
        },
        py::arg("base"), py::arg("grammar"), py::arg("region"), py::arg("seed") = GrowOptions{}.seed, py::arg("max_placements") = GrowOptions{}.max_placements,
        py::arg("max_vertices") = GrowOptions{}.max_vertices, py::arg("patience") = GrowOptions{}.patience,
        py::arg("placements") = py::none(), py::arg("border_m") = GrowOptions{}.border_m,
        py::arg("continue_hierarchy") = GrowOptions{}.continue_hierarchy, py::arg("trace_streets") = GrowOptions{}.trace_streets,
        py::arg("progress") = py::none(),
        "Grow streets into `region` ((N,2) polygon corners in the base graph's metres) with the grammar's rules, from the\n"
        "streets of `base` that reach it (or the region's middle). placements: rules placed by hand, (symbol, x, y, scale,\n"
        "rotation_deg) each (scale <= 0: the rule's learned size), grown from first. border_m: how near the region a base\n"
        "street must end to be grown from (< 0: 5 % of the region's size). continue_hierarchy: continue the main roads\n"
        "through the grown streets at the end (see continue_hierarchy). trace_streets: first trace the streets that reach\n"
        "the region on into it, each new junction shaped like one of the city's (rules then fill what is left). Returns (Graph, report dict): the base\n"
        "with the grown streets after its own vertices and edges. Deterministic for a seed.");

    m.def(
        "continue_hierarchy",
        [](const GeometricGraph& g, std::int64_t first_new_edge, double max_detour, std::optional<DoubleArray> region,
           double border_m) {
            GeometricGraph out = g;
            HierarchyOptions o;
            o.max_detour = max_detour;
            if (region) {
                if (region->ndim() != 2 || region->shape(1) != 2 || region->shape(0) < 3) {
                    throw UsageError("region must have shape (N, 2), N >= 3: the polygon's corners in metres");
                }
                const auto r = region->unchecked<2>();
                for (py::ssize_t i = 0; i < r.shape(0); ++i) o.region.emplace_back(r(i, 0), r(i, 1));
                o.border_m = border_m;
            }
            HierarchyReport report;
            {
                py::gil_scoped_release release;
                report = continue_hierarchy(out, static_cast<EdgeId>(first_new_edge), o);
            }
            return py::make_tuple(std::move(out), to_python(hierarchy_report_json(report)));
        },
        py::arg("graph"), py::arg("first_new_edge"), py::arg("max_detour") = HierarchyOptions{}.max_detour,
        py::arg("region") = py::none(), py::arg("border_m") = HierarchyOptions{}.border_m,
        "Continue the main roads that reach the grown streets (edges from first_new_edge on) through them: each is\n"
        "joined to another main road as directly as the grown streets allow (at most max_detour times the straight\n"
        "line), and the grown streets on the way take the less important of the two classes. grow_region does this\n"
        "itself; call it again after several growths into one region (Stitch Cities). region ((N,2), optional): the\n"
        "region grown into; main roads that end in it (or within border_m; < 0: 5 % of its size) count even where no grown street reaches\n"
        "them, and straight connectors stay in it. Returns (Graph, report dict).");

    using IndexArray = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>;
    m.def(
        "replace_isogroup",
        [](const GeometricGraph& g, const AnalyzedIsogroup& isogroup, DoubleArray positions, IndexArray edges,
           std::optional<IndexArray> edge_highway, std::optional<IndexArray> occurrences, bool fit) {
            if (positions.ndim() != 2 || positions.shape(1) != 2) throw UsageError("replacement positions must have shape (N, 2)");
            if (edges.ndim() != 2 || edges.shape(1) != 2) throw UsageError("replacement edges must have shape (M, 2)");
            ReplacementGraph r;
            const auto p = positions.unchecked<2>();
            for (py::ssize_t i = 0; i < p.shape(0); ++i) r.positions.emplace_back(p(i, 0), p(i, 1));
            const auto e = edges.unchecked<2>();
            for (py::ssize_t i = 0; i < e.shape(0); ++i) r.edges.push_back({static_cast<int>(e(i, 0)), static_cast<int>(e(i, 1))});
            if (edge_highway) {
                const auto h = edge_highway->unchecked<1>();
                for (py::ssize_t i = 0; i < h.shape(0); ++i) {
                    if (h(i) < 0 || h(i) >= highway_class_count) throw UsageError("a replacement edge's road class is out of range");
                    r.edge_highway.push_back(static_cast<HighwayClass>(h(i)));
                }
            }
            std::vector<std::uint32_t> chosen = isogroup.selection.non_overlapping;
            if (occurrences) {
                chosen.clear();
                const auto o = occurrences->unchecked<1>();
                for (py::ssize_t i = 0; i < o.shape(0); ++i) {
                    if (o(i) < 0) throw UsageError("occurrence indices must be >= 0");
                    chosen.push_back(static_cast<std::uint32_t>(o(i)));
                }
            }
            if (fit) r = fit_replacement(r, isogroup.group.pattern);
            ReplaceReport report;
            GeometricGraph out;
            {
                py::gil_scoped_release release;
                out = replace_occurrences(g, isogroup.group, chosen, r, &report);
            }
            return py::make_tuple(std::move(out), to_python(replacement_report_json(report)));
        },
        py::arg("graph"), py::arg("isogroup"), py::arg("positions"), py::arg("edges"), py::arg("edge_highway") = py::none(),
        py::arg("occurrences") = py::none(), py::arg("fit") = true,
        "Terminal replacement (paper Fig. 1): the isogroup's occurrences (default: its non-overlapping ones) replaced by the\n"
        "piece of network (positions (N,2), edges (M,2), optional road classes (M,)), scaled and turned by each occurrence's\n"
        "transform and joined to the streets around by the relaxed embedding. fit=True centres and scales the piece to the\n"
        "pattern (draw it anywhere, at any size); fit=False takes it in the pattern's canonical coordinates.\n"
        "Returns (Graph, report dict).");
    m.def(
        "compare",
        [](const GeometricGraph& a, const GeometricGraph& b) {
            nlohmann::json result;
            {
                py::gil_scoped_release release;
                result = compare_networks(a, b);
            }
            return to_python(result);
        },
        py::arg("a"), py::arg("b"),
        "How alike two street networks are (as `ggg compare`): a dict with 'distances' (degree, edge_length,\n"
        "orientation, block_area, each 0 for the same distribution and at most 1, and their mean) and a summary\n"
        "of each network under 'a' and 'b' (orientation entropy and order, median edge length and block area, ...).");
}

} // namespace ggg::python
