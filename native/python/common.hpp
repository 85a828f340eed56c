#pragma once
// Helpers shared by the binding files: numpy conversions and Python progress callbacks.
#include <cstring>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "ggg/error.hpp"
#include "ggg/progress.hpp"
#include "ggg/graph/similarity.hpp"

namespace ggg::python {

namespace py = pybind11;

// Counts come in as Python ints and are checked here: a negative one would wrap in a size_t,
// and pybind11 would refuse it with a TypeError that does not name the argument.
inline std::size_t count_arg(const char* name, std::int64_t value, std::int64_t lo = 0) {
    if (value < lo) throw UsageError(std::string(name) + ": must be a whole number >= " + std::to_string(lo) + ", got " + std::to_string(value));
    return static_cast<std::size_t>(value);
}

// A random seed: any whole number from 0 to 2**64 - 1.
inline std::uint64_t seed_arg(const py::int_& value) {
    const unsigned long long seed = PyLong_AsUnsignedLongLong(value.ptr());
    if (PyErr_Occurred()) {
        PyErr_Clear();
        throw UsageError("seed: must be a whole number from 0 to 2**64 - 1, got " + py::str(py::handle(value)).cast<std::string>());
    }
    return seed;
}

template <typename T>
inline py::array_t<T> column(const std::vector<T>& values) {
    py::array_t<T> out(static_cast<py::ssize_t>(values.size()));
    if (!values.empty()) std::memcpy(out.mutable_data(), values.data(), values.size() * sizeof(T));
    return out;
}

template <typename Out, typename In>
inline py::array_t<Out> column_as(const std::vector<In>& values) {
    py::array_t<Out> out(static_cast<py::ssize_t>(values.size()));
    auto view = out.template mutable_unchecked<1>();
    for (std::size_t i = 0; i < values.size(); ++i) view(static_cast<py::ssize_t>(i)) = static_cast<Out>(values[i]);
    return out;
}

inline py::array_t<double> points(const std::vector<ggg::Vec2>& values) {
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
                return result.is_none() || static_cast<bool>(py::bool_(result)); // Python truthiness
            } catch (py::error_already_set& e) {
                error_ = std::move(e);
                return false;
            }
        };
    }

    // Runs f(callback) without the GIL. A cancel caused by an exception inside the Python
    // callable re-raises that exception; a cancel by returning False raises ggg.Cancelled.
    template <class F>
    auto run(F&& f) {
        try {
            py::gil_scoped_release release;
            return f(callback());
        } catch (const Cancelled&) {
            rethrow();
            throw;
        }
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

// nlohmann::json -> Python objects (dicts, lists, numbers, strings).
py::object to_python(const nlohmann::json& j);

// The defaults of ggg.grow_region's options, from visit_grow_options (synthesis_bindings.cpp).
py::dict grow_option_defaults();

// Binds the analyzer (analysis_bindings.cpp).
void bind_analysis(py::module_& m);
// Binds grammar learning and decoding (learning_bindings.cpp).
void bind_learning(py::module_& m);
// Binds growth, terminal replacement and the comparison of street networks
// (synthesis_bindings.cpp).
void bind_synthesis(py::module_& m);

} // namespace ggg::python
