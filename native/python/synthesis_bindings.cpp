// ggg.grow_region (streets grown into a region with a grammar), ggg.replace_isogroup
// (terminal replacement) and ggg.compare (how alike two street networks are); and the
// JSON-to-Python conversion the bindings that return reports share; the graph surgery around
// a growth (ggg.induced_subgraph, ggg.with_grown).
#include <limits>
#include <string_view>
#include <type_traits>

#include <pybind11/stl.h>

#include "common.hpp"
#include "ggg/error.hpp"
#include "ggg/grammar/grammar.hpp"
#include "ggg/graph/graph_surgery.hpp"
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


namespace {

using BoolArray = py::array_t<bool, py::array::c_style | py::array::forcecast>;
using IdArray = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>;

std::vector<bool> keep_arg(const BoolArray& keep) {
    if (keep.ndim() != 1) throw UsageError("keep: a 1-D array of one bool per vertex is needed");
    return std::vector<bool>(keep.data(), keep.data() + keep.size());
}

template <typename Id>
std::vector<Id> ids_arg(const char* name, const IdArray& ids) {
    if (ids.ndim() != 1) throw UsageError(std::string(name) + ": a 1-D array of ids is needed");
    std::vector<Id> out;
    out.reserve(static_cast<std::size_t>(ids.size()));
    for (py::ssize_t i = 0; i < ids.size(); ++i) {
        const std::int64_t id = ids.data()[i];
        if (id < 0 || id > std::numeric_limits<Id>::max()) throw UsageError(std::string(name) + ": id out of range: " + std::to_string(id));
        out.push_back(static_cast<Id>(id));
    }
    return out;
}

void bind_graph_surgery(py::module_& m) {
    m.def(
        "induced_subgraph",
        [](const GeometricGraph& graph, const BoolArray& keep) {
            std::vector<bool> k = keep_arg(keep);
            Subgraph part;
            {
                py::gil_scoped_release release;
                part = induced_subgraph(graph, k);
            }
            return py::make_tuple(std::move(part.graph), column_as<std::int64_t>(part.vertex_ids), column_as<std::int64_t>(part.edge_ids));
        },
        py::arg("graph"), py::arg("keep"),
        "The part of graph on the vertices where keep (N,) is True and the edges between them, with every column, in\n"
        "graph's order: (subgraph, its vertices' ids in graph (int64), its edges' ids in graph (int64)).");
    m.def(
        "with_grown",
        [](const GeometricGraph& graph, const BoolArray& keep, const IdArray& part_vertex_ids, const IdArray& part_edge_ids,
           const GeometricGraph& grown) {
            std::vector<bool> k = keep_arg(keep);
            Subgraph part;
            part.vertex_ids = ids_arg<VertexId>("part_vertex_ids", part_vertex_ids);
            part.edge_ids = ids_arg<EdgeId>("part_edge_ids", part_edge_ids);
            Regrown out;
            {
                py::gil_scoped_release release;
                out = with_grown(graph, k, part, grown);
            }
            return py::make_tuple(std::move(out.graph), column_as<std::int64_t>(out.source_vertex));
        },
        py::arg("graph"), py::arg("keep"), py::arg("part_vertex_ids"), py::arg("part_edge_ids"), py::arg("grown"),
        "graph cut down to the vertices where keep is True (and the edges between them), followed by what growth added\n"
        "to a part of it: grown was grown (ggg.grow_region) from ggg.induced_subgraph(graph, ...), whose vertex and edge\n"
        "ids are part_vertex_ids and part_edge_ids (all kept). An edge of the part that the growth split comes back\n"
        "split. Returns (graph, source_vertex): per vertex of the result its id in graph, -1 for a grown one.");
}

// GrowOptions from ggg.grow_region's keywords (visit_grow_options names them); an unknown
// keyword or a value of the wrong kind is a UsageError naming it.
GrowOptions grow_options_from(const py::kwargs& keywords) {
    GrowOptions o;
    for (const auto& [key, value] : keywords) {
        const std::string name = py::str(key);
        bool known = false;
        visit_grow_options(o, [&](std::string_view keyword, std::string_view, std::string_view, auto& field) {
            if (keyword != name) return;
            known = true;
            using Field = std::remove_reference_t<decltype(field)>;
            if constexpr (std::is_same_v<Field, bool>) {
                try {
                    field = value.template cast<bool>();
                } catch (const py::cast_error&) {
                    throw UsageError(name + ": must be True or False");
                }
            } else if constexpr (std::is_floating_point_v<Field>) {
                try {
                    field = value.template cast<double>();
                } catch (const py::cast_error&) {
                    throw UsageError(name + ": must be a number");
                }
            } else {
                const py::object whole = py::reinterpret_steal<py::object>(PyNumber_Index(value.ptr()));
                const unsigned long long n = whole ? PyLong_AsUnsignedLongLong(whole.ptr()) : 0;
                if (!whole || PyErr_Occurred()) {
                    PyErr_Clear();
                    throw UsageError(name + ": must be a whole number from 0 to " + std::to_string(std::numeric_limits<Field>::max()) +
                                     ", got " + py::repr(value).cast<std::string>());
                }
                if (n > std::numeric_limits<Field>::max()) {
                    throw UsageError(name + ": must be a whole number from 0 to " + std::to_string(std::numeric_limits<Field>::max()));
                }
                field = static_cast<Field>(n);
            }
        });
        if (!known) {
            std::string names;
            visit_grow_options(o, [&](std::string_view keyword, auto&&...) { names += (names.empty() ? "" : ", ") + std::string(keyword); });
            throw UsageError("grow_region has no option '" + name + "' (its options: " + names + ")");
        }
    }
    return o;
}

template <typename Field>
py::object python_value(const Field& value) {
    if constexpr (std::is_same_v<Field, bool>) return py::bool_(value);
    else if constexpr (std::is_floating_point_v<Field>) return py::float_(value);
    else return py::int_(value);
}

// The docstring of ggg.grow_region, its options listed from visit_grow_options.
const std::string& grow_region_doc() {
    static const std::string doc = [] {
        std::string text =
            "Grow streets into `region` ((N,2) polygon corners in the base graph's metres) with the grammar's rules, from the\n"
            "streets of `base` that reach it (or the region's middle). placements: rules placed by hand, (symbol, x, y, scale,\n"
            "rotation_deg) each (scale <= 0: the rule's learned size), grown from first. progress(fraction, message) may return\n"
            "False to cancel. Returns (Graph, report dict): the base with the grown streets after its own vertices and edges.\n"
            "Deterministic for a seed. UsageError for a region that crosses itself, has no area, or lies more than " +
            std::to_string(static_cast<int>(max_distance_from_base_m / 1000.0)) +
            " km\nfrom every street of a base that has any. The options, keywords only (keyword = default: what it sets; `ggg "
            "grow`'s\nflags):\n";
        const GrowOptions defaults;
        visit_grow_options(defaults, [&](std::string_view keyword, std::string_view flag, std::string_view help, const auto& field) {
            text += "  " + std::string(keyword) + " = " + std::string(py::str(py::repr(python_value(field)))) + ": " + std::string(help) +
                    " (" + std::string(flag) + ")\n";
        });
        return text;
    }();
    return doc;
}

} // namespace

// The defaults of ggg.grow_region's options (ggg.option_defaults()["growth"]).
py::dict grow_option_defaults() {
    py::dict out;
    const GrowOptions defaults;
    visit_grow_options(defaults, [&](std::string_view keyword, std::string_view, std::string_view, const auto& field) {
        out[py::str(std::string(keyword))] = python_value(field);
    });
    return out;
}

void bind_synthesis(py::module_& m) {
    using DoubleArray = py::array_t<double, py::array::c_style | py::array::forcecast>;
    bind_graph_surgery(m);
    m.def(
        "grow_region",
        [](const GeometricGraph& base, const Grammar& grammar, DoubleArray region,
           std::optional<std::vector<std::tuple<Symbol, double, double, double, double>>> placements,
           std::optional<py::function> progress, const py::kwargs& options) {
            if (region.ndim() != 2 || region.shape(1) != 2) throw UsageError("region must have shape (N, 2): the polygon's corners in metres");
            std::vector<Vec2> ring;
            const auto r = region.unchecked<2>();
            for (py::ssize_t i = 0; i < r.shape(0); ++i) ring.emplace_back(r(i, 0), r(i, 1));
            GrowOptions o = grow_options_from(options);
            if (placements) {
                for (const auto& [symbol, x, y, scale, rotation] : *placements) o.placements.push_back({symbol, Vec2(x, y), Frame{scale, rotation}});
            }
            check_options(o);
            PythonProgress reporter(std::move(progress));
            GrowReport report;
            GeometricGraph grown = reporter.run([&](const ProgressCallback& cb) { return grow_region(base, grammar, ring, o, &report, cb); });
            py::object d = to_python(growth_report_json(report));
            return py::make_tuple(std::move(grown), d);
        },
        py::arg("base"), py::arg("grammar"), py::arg("region"), py::kw_only(), py::arg("placements") = py::none(),
        py::arg("progress") = py::none(), grow_region_doc().c_str());

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
        "piece of network (positions (N,2), edges (M,2), optional road classes (M,)), fitted into each occurrence (its\n"
        "transform, inside its area, clear of the streets around) and joined to the junctions the occurrence keeps (its\n"
        "vertices where other streets meet); a new street that still crosses one makes an intersection. fit=True centres\n"
        "and scales the piece to the pattern first (draw it anywhere, at any size); fit=False takes it in the pattern's\n"
        "canonical coordinates. Returns (Graph, report dict: replaced, removed_vertices, added_vertices, joined_streets,\n"
        "intersections).");
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
