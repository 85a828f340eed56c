#pragma once
// Shared by the file formats: JSON written safely (invalid UTF-8 in OSM names is replaced,
// not fatal) and files written whole or not at all.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "ggg/error.hpp"

namespace ggg::io_detail {

inline bool has_format(const nlohmann::json& doc, std::string_view format) {
    if (!doc.is_object()) return false;
    const auto it = doc.find("format");
    return it != doc.end() && it->is_string() && it->get_ref<const std::string&>() == format;
}

inline std::string dump(const nlohmann::json& value, int indent = -1) {
    return value.dump(indent, ' ', false, nlohmann::json::error_handler_t::replace);
}

// Parses JSON text; any failure (syntax, a number too large for a double, ...) becomes
// `ErrorType` naming the file.
template <typename ErrorType, typename Input>
nlohmann::json parse(Input&& input, const std::string& name) {
    try {
        return nlohmann::json::parse(std::forward<Input>(input));
    } catch (const nlohmann::json::parse_error& e) {
        throw ErrorType(name + ": not valid JSON (byte " + std::to_string(e.byte) + ")");
    } catch (const nlohmann::json::exception& e) {
        std::string what = e.what();
        const auto bracket = what.find("] ");
        if (bracket != std::string::npos) what = what.substr(bracket + 2);
        throw ErrorType(name + ": not valid JSON (" + what + ")");
    }
}

// Writes through a temporary file beside `path` and renames it into place, so a failure
// leaves no half-written file behind.
inline void write_file(const std::string& path, const std::function<void(std::ostream&)>& write) {
    const std::string temporary = path + ".partial";
    try {
        {
            std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
            if (!out) throw InputError(path + ": cannot open for writing");
            write(out);
            out.flush();
            if (!out) throw InputError(path + ": write failed (disk full?)");
        }
        std::filesystem::rename(temporary, path);
    } catch (const InputError&) {
        std::error_code ec;
        std::filesystem::remove(temporary, ec);
        throw;
    } catch (const std::exception& e) {
        std::error_code ec;
        std::filesystem::remove(temporary, ec);
        throw InputError(path + ": cannot write (" + e.what() + ")");
    }
}

} // namespace ggg::io_detail
