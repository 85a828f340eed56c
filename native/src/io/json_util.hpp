#pragma once
// Shared by the file formats: JSON written safely (invalid UTF-8 in OSM names is replaced,
// not fatal) and files written whole or not at all.
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <functional>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "ggg/error.hpp"
#include "ggg/files.hpp"

namespace ggg::io_detail {

inline bool has_format(const nlohmann::json& doc, std::string_view format) {
    if (!doc.is_object()) return false;
    const auto it = doc.find("format");
    return it != doc.end() && it->is_string() && it->get_ref<const std::string&>() == format;
}

inline std::string dump(const nlohmann::json& value, int indent = -1) {
    return value.dump(indent, ' ', false, nlohmann::json::error_handler_t::replace);
}

// Reads a parsed document member by member; every problem is an `ErrorType` that names
// the file and the place ("edges.u[12]: 99 out of range").
template <typename ErrorType>
class JsonReader {
public:
    using json = nlohmann::json;
    static constexpr std::size_t any_size = static_cast<std::size_t>(-1);

    explicit JsonReader(const std::string& name) : name_(name) {}

    [[noreturn]] void fail(const std::string& where, const std::string& what) const {
        throw ErrorType(name_ + ": " + where + ": " + what);
    }
    const json& member(const json& object, const char* key, const std::string& where) const {
        if (!object.is_object()) fail(where, "must be an object");
        const auto it = object.find(key);
        if (it == object.end()) fail(where, std::string("missing \"") + key + "\"");
        return *it;
    }
    const json* optional(const json& object, const char* key) const {
        const auto it = object.find(key);
        return it == object.end() ? nullptr : &*it;
    }
    const json& array(const json& value, const std::string& where, std::size_t size = any_size) const {
        if (!value.is_array()) fail(where, "must be an array");
        if (size != any_size && value.size() != size) {
            fail(where, "has " + std::to_string(value.size()) + " entries, expected " + std::to_string(size));
        }
        return value;
    }
    double number(const json& value, const std::string& where) const {
        if (!value.is_number()) fail(where, "must be a number");
        const double d = value.get<double>();
        if (!std::isfinite(d)) fail(where, "must be finite");
        return d;
    }
    std::int64_t integer(const json& value, const std::string& where, std::int64_t lo, std::int64_t hi) const {
        if (!value.is_number_integer()) fail(where, "must be an integer");
        const auto i = value.get<std::int64_t>();
        if (i < lo || i > hi) fail(where, std::to_string(i) + " out of range [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
        return i;
    }

private:
    const std::string& name_;
};

// No file of the project nests deeper than a dozen levels or holds a string longer than a
// street name; these bounds keep a hostile file from exhausting the stack or the time of
// the readers that walk the document.
inline constexpr int max_json_depth = 64;
inline constexpr std::size_t max_json_string_bytes = std::size_t{1} << 20;

// Parses JSON text; any failure (syntax, a number too large for a double, nesting deeper
// than max_json_depth, a string longer than max_json_string_bytes) becomes `ErrorType`
// naming the file.
template <typename ErrorType, typename Input>
nlohmann::json parse(Input&& input, const std::string& name) {
    using json = nlohmann::json;
    const json::parser_callback_t guard = [&name](int depth, json::parse_event_t event, json& parsed) {
        if (depth > max_json_depth) {
            throw ErrorType(name + ": not valid input (nested more than " + std::to_string(max_json_depth) + " deep)");
        }
        if ((event == json::parse_event_t::value || event == json::parse_event_t::key) && parsed.is_string() &&
            parsed.get_ref<const std::string&>().size() > max_json_string_bytes) {
            throw ErrorType(name + ": not valid input (a string longer than " + std::to_string(max_json_string_bytes >> 20) + " MiB)");
        }
        return true;
    };
    try {
        return json::parse(std::forward<Input>(input), guard);
    } catch (const json::parse_error& e) {
        throw ErrorType(name + ": not valid JSON (byte " + std::to_string(e.byte) + ")");
    } catch (const json::exception& e) {
        std::string what = e.what();
        const auto bracket = what.find("] ");
        if (bracket != std::string::npos) what = what.substr(bracket + 2);
        throw ErrorType(name + ": not valid JSON (" + what + ")");
    }
}

// The whole text of a JSON file, bounded (files.hpp), any failure an `ErrorType`.
template <typename ErrorType>
std::string read_json_text(const std::string& path) {
    std::string text;
    try {
        text = read_text_file(path);
    } catch (const Error& e) {
        throw ErrorType(e.what());
    }
    if (text.find_first_not_of(" \t\r\n") == std::string::npos) throw ErrorType(path + ": the file is empty");
    return text;
}

// Writes the whole output through write_text_file (files.hpp): a unique temporary file
// beside `path`, renamed over it, so a failure leaves no half-written file behind.
inline void write_file(const std::string& path, const std::function<void(std::ostream&)>& write) {
    std::ostringstream out;
    write(out);
    if (!out) throw InputError(path + ": cannot write (the output could not be formatted)");
    write_text_file(path, out.view());
}

} // namespace ggg::io_detail
