#include "osm_text.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <cstdint>
#include <fstream>
#include <memory>
#include <utility>
#include <vector>

#include <osmium/io/any_compression.hpp>
#include <osmium/io/file.hpp>
#include <protozero/exception.hpp>
#include <protozero/pbf_reader.hpp>

#include "ggg/error.hpp"
#include "ggg/io/files.hpp"

namespace ggg::osm_detail {
namespace {

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; }
bool is_digit(char c) { return c >= '0' && c <= '9'; }

// The number of a coordinate, or NaN when it is not one: [-]digits[.digits][e[+-]digits], the
// forms OSM files use. Anything else is refused here rather than half-read by libosmium.
double coordinate_value(std::string_view text) {
    std::size_t i = 0;
    if (i < text.size() && text[i] == '-') ++i;
    std::size_t digits = 0;
    while (i < text.size() && is_digit(text[i])) ++i, ++digits;
    if (i < text.size() && text[i] == '.') {
        ++i;
        while (i < text.size() && is_digit(text[i])) ++i, ++digits;
    }
    if (digits == 0 || digits > 40) return std::nan("");
    if (i < text.size() && (text[i] == 'e' || text[i] == 'E')) {
        ++i;
        if (i < text.size() && (text[i] == '-' || text[i] == '+')) ++i;
        std::size_t exponent_digits = 0;
        while (i < text.size() && is_digit(text[i])) ++i, ++exponent_digits;
        if (exponent_digits == 0 || exponent_digits > 4) return std::nan("");
    }
    if (i != text.size()) return std::nan("");
    const std::string copy(text);
    return std::strtod(copy.c_str(), nullptr);
}

class Checker {
public:
    explicit Checker(const std::string& name) : name_(name) {}

    // `where`: "node 42", "bounds", ...; `attribute`: its name, "lat", "minlon", ...
    void coordinate(const std::string& where, std::string_view attribute, std::string_view value, bool latitude) const {
        const double x = coordinate_value(value);
        const std::string what = attribute == "lat" || attribute == "lon" ? std::string(latitude ? "latitude" : "longitude")
                                                                           : std::string(latitude ? "latitude " : "longitude ") + std::string(attribute);
        const double limit = latitude ? 90.0 : 180.0;
        std::string shown(value.substr(0, 40));
        if (value.size() > 40) shown += "...";
        const std::string& node = where;
        if (std::isnan(x)) throw InputError(name_ + ": " + node + ": " + what + " '" + shown + "' is not a number");
        if (!(std::abs(x) <= limit)) {
            throw InputError(name_ + ": " + node + ": " + what + " '" + shown + "' is out of range (" + std::to_string(static_cast<int>(-limit)) +
                             " to " + std::to_string(static_cast<int>(limit)) + ")");
        }
    }

    [[noreturn]] void too_long(const char* what, std::size_t offset) const {
        throw InputError(name_ + ": " + what + " at byte " + std::to_string(offset) + " is longer than " +
                         std::to_string(max_xml_token_bytes >> 20) + " MiB (OSM tag values hold at most 255 characters)");
    }

private:
    const std::string& name_;
};

bool is_latitude(std::string_view a) { return a == "lat" || a == "minlat" || a == "maxlat" || a == "min_lat" || a == "max_lat"; }
bool is_longitude(std::string_view a) { return a == "lon" || a == "minlon" || a == "maxlon" || a == "min_lon" || a == "max_lon"; }

// The coordinates among the attributes of one XML start tag (a node's lat and lon, the
// bounds' and a changeset's corners), between the element's name and the closing '>'.
void check_xml_coordinates(std::string_view name, std::string_view element, const Checker& checker) {
    std::string_view id;
    std::vector<std::pair<std::string_view, std::string_view>> coordinates;
    std::size_t i = 0;
    while (i < element.size()) {
        while (i < element.size() && is_space(element[i])) ++i;
        const std::size_t name_begin = i;
        while (i < element.size() && element[i] != '=' && !is_space(element[i]) && element[i] != '/' && element[i] != '>') ++i;
        const std::string_view attribute = element.substr(name_begin, i - name_begin);
        while (i < element.size() && is_space(element[i])) ++i;
        if (i >= element.size() || element[i] != '=') {
            if (attribute.empty()) ++i; // '/' or a stray character: expat will judge the syntax
            continue;
        }
        ++i;
        while (i < element.size() && is_space(element[i])) ++i;
        if (i >= element.size() || (element[i] != '"' && element[i] != '\'')) break;
        const char quote = element[i++];
        const std::size_t value_begin = i;
        while (i < element.size() && element[i] != quote) ++i;
        const std::string_view value = element.substr(value_begin, i - value_begin);
        ++i;
        if (attribute == "id") id = value;
        else if (is_latitude(attribute) || is_longitude(attribute)) coordinates.emplace_back(attribute, value);
    }
    const std::string what = std::string(name.substr(0, 16)) + (id.empty() ? std::string() : " " + std::string(id.substr(0, 24)));
    for (const auto& [attribute, value] : coordinates) checker.coordinate(what, attribute, value, is_latitude(attribute));
}

void check_xml(std::string_view text, const Checker& checker) {
    std::size_t i = 0;
    while (i < text.size()) {
        const std::size_t open = text.find('<', i);
        const std::size_t text_end = open == std::string_view::npos ? text.size() : open;
        if (text_end - i > max_xml_token_bytes) checker.too_long("text between elements", i);
        if (open == std::string_view::npos) break;
        const std::size_t close = text.find('>', open);
        const std::size_t end = close == std::string_view::npos ? text.size() : close;
        if (end - open > max_xml_token_bytes) checker.too_long("an XML element", open);
        if (close == std::string_view::npos) break; // truncated: expat reports it
        const std::string_view element = text.substr(open + 1, close - open - 1);
        // Only start tags that hold a coordinate attribute are taken apart.
        if (!element.empty() && element[0] != '/' && element[0] != '?' && element[0] != '!' &&
            (element.find("lat") != std::string_view::npos || element.find("lon") != std::string_view::npos)) {
            std::size_t name_end = 0;
            while (name_end < element.size() && !is_space(element[name_end]) && element[name_end] != '/') ++name_end;
            check_xml_coordinates(element.substr(0, name_end), element.substr(name_end), checker);
        }
        i = close + 1;
    }
}

// OPL: one object per line, `n<id> ... x<lon> y<lat> ...` for nodes.
void check_opl(std::string_view text, const Checker& checker) {
    std::size_t i = 0;
    while (i < text.size()) {
        std::size_t end = text.find('\n', i);
        if (end == std::string_view::npos) end = text.size();
        if (end - i > max_xml_token_bytes) checker.too_long("a line", i);
        const std::string_view line = text.substr(i, end - i);
        if (!line.empty() && line[0] == 'n') {
            std::string_view id;
            std::size_t t = 0;
            while (t < line.size()) {
                std::size_t stop = line.find(' ', t);
                if (stop == std::string_view::npos) stop = line.size();
                const std::string_view token = line.substr(t, stop - t);
                if (t == 0) id = token.substr(1);
                else if (!token.empty() && (token[0] == 'x' || token[0] == 'y') && token.size() > 1) {
                    checker.coordinate("node " + std::string(id.substr(0, 24)), token[0] == 'y' ? "lat" : "lon", token.substr(1), token[0] == 'y');
                }
                t = stop + 1;
            }
        }
        i = end + 1;
    }
}

} // namespace

std::string read_osm_text(const std::string& path) {
    const osmium::io::File file(path);
    if (file.compression() == osmium::io::file_compression::none) return read_text_file(path);
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NOCTTY);
    if (fd < 0) throw InputError(path + ": cannot open (" + std::strerror(errno) + ")");
    std::unique_ptr<osmium::io::Decompressor> decompressor;
    try {
        decompressor = osmium::io::CompressionFactory::instance().create_decompressor(file.compression(), fd);
    } catch (...) {
        ::close(fd);
        throw;
    }
    // From a pipe or a device (whose length is unknown), as much as read_text_file takes.
    struct stat info {};
    const bool regular = ::fstat(fd, &info) == 0 && S_ISREG(info.st_mode);
    const std::size_t limit = regular ? max_text_file_bytes : max_stream_bytes;
    std::string text;
    while (true) {
        const std::string chunk = decompressor->read();
        if (chunk.empty()) break;
        if (text.size() + chunk.size() > limit) {
            throw InputError(path + ": decompresses to more than " + std::to_string(limit >> 20) +
                             " MiB, the most the project reads" + (regular ? " (convert it to .osm.pbf)" : " from anything but a regular file"));
        }
        text += chunk;
    }
    decompressor->close();
    return text;
}

void check_pbf_framing(std::string_view data, const std::string& name) {
    const std::uint64_t size = data.size();
    std::uint64_t offset = 0;
    while (offset + 4 <= size) {
        const auto* b = reinterpret_cast<const unsigned char*>(data.data() + offset);
        const std::uint32_t length = (std::uint32_t{b[0]} << 24) | (std::uint32_t{b[1]} << 16) | (std::uint32_t{b[2]} << 8) | std::uint32_t{b[3]};
        if (length == 0 || length > 64 * 1024 || offset + 4 + length > size) return; // libosmium reports these itself
        bool typed = false;
        std::int64_t datasize = 0;
        try {
            protozero::pbf_reader message(data.data() + offset + 4, length);
            while (message.next()) {
                if (message.tag() == 1 && message.wire_type() == protozero::pbf_wire_type::length_delimited) {
                    typed = message.get_view().size() > 0;
                } else if (message.tag() == 3 && message.wire_type() == protozero::pbf_wire_type::varint) {
                    datasize = message.get_int32();
                } else {
                    message.skip();
                }
            }
        } catch (const protozero::exception&) {
            return; // a malformed header: libosmium reports it
        }
        if (!typed) {
            throw InputError(name + ": not a readable OSM file (PBF error: the blob header at byte " + std::to_string(offset) +
                             " has no type)");
        }
        if (datasize <= 0) return;
        offset += 4 + length + static_cast<std::uint64_t>(datasize);
    }
}

void check_osm_text(std::string_view text, TextFormat format, const std::string& name) {
    const Checker checker(name);
    if (format == TextFormat::xml) check_xml(text, checker);
    else check_opl(text, checker);
}

} // namespace ggg::osm_detail
