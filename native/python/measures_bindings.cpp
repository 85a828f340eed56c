// ggg.compare: how alike two street networks are; and the JSON-to-Python conversion the
// bindings that return reports share.
#include "common.hpp"
#include "ggg/measures/network_comparison.hpp"

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


void bind_measures(py::module_& m) {
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
