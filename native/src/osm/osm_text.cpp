#include "osm_text.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <cstdint>
#include <algorithm>
#include <fstream>
#include <memory>
#include <utility>
#include <vector>

#include <osmium/io/any_compression.hpp>
#include <osmium/io/file.hpp>
#include <protozero/exception.hpp>
#include <protozero/pbf_reader.hpp>
#include <zlib.h>

#include "ggg/error.hpp"
#include "ggg/files.hpp"

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

namespace {

// protozero's own view type, as a standard one and back.
std::string_view view(protozero::data_view d) { return {d.data(), d.size()}; }
protozero::pbf_reader reader(std::string_view v) { return {v.data(), v.size()}; }

// The most a PBF blob may hold once decompressed (the format's own limit is 32 MiB).
constexpr std::size_t max_pbf_blob_bytes = std::size_t{32} << 20;

[[noreturn]] void pbf_error(const std::string& name, const std::string& what) {
    throw InputError(name + ": not a readable OSM file (PBF error: " + what + ")");
}

// The decompressed bytes of one Blob, or false when the blob is of a kind libosmium reports
// itself (an unknown compression, a size that does not match).
bool blob_bytes(std::string_view blob, std::string& out) {
    std::string_view raw, zlib_data;
    std::int64_t raw_size = -1;
    protozero::pbf_reader message = reader(blob);
    while (message.next()) {
        if (message.tag() == 1 && message.wire_type() == protozero::pbf_wire_type::length_delimited) raw = view(message.get_view());
        else if (message.tag() == 2 && message.wire_type() == protozero::pbf_wire_type::varint) raw_size = message.get_int32();
        else if (message.tag() == 3 && message.wire_type() == protozero::pbf_wire_type::length_delimited) zlib_data = view(message.get_view());
        else message.skip();
    }
    if (raw.data() != nullptr) {
        out.assign(raw.data(), raw.size());
        return true;
    }
    if (zlib_data.data() == nullptr || raw_size <= 0 || static_cast<std::size_t>(raw_size) > max_pbf_blob_bytes) return false;
    out.resize(static_cast<std::size_t>(raw_size));
    uLongf length = static_cast<uLongf>(raw_size);
    if (::uncompress(reinterpret_cast<Bytef*>(out.data()), &length, reinterpret_cast<const Bytef*>(zlib_data.data()),
                     static_cast<uLong>(zlib_data.size())) != Z_OK ||
        length != static_cast<uLongf>(raw_size)) {
        return false;
    }
    return true;
}

// Coordinates of one PrimitiveBlock: libosmium computes value * granularity + offset, and adds
// up the deltas of ids and coordinates, in 64 bits without checking (undefined behaviour, then
// a wrong location). Each step is checked here, and every coordinate must land within the
// world, so that what reaches libosmium is arithmetic it can do.
class BlockChecker {
public:
    BlockChecker(const std::string& name, std::string_view block) : name_(name) {
        protozero::pbf_reader message = reader(block);
        while (message.next()) {
            if (message.tag() == 17 && message.wire_type() == protozero::pbf_wire_type::varint) granularity_ = message.get_int32();
            else if (message.tag() == 19 && message.wire_type() == protozero::pbf_wire_type::varint) lat_offset_ = message.get_int64();
            else if (message.tag() == 20 && message.wire_type() == protozero::pbf_wire_type::varint) lon_offset_ = message.get_int64();
            else message.skip();
        }
        protozero::pbf_reader groups = reader(block);
        while (groups.next(2, protozero::pbf_wire_type::length_delimited)) {
            protozero::pbf_reader group = groups.get_message();
            while (group.next()) {
                if (group.tag() == 1 && group.wire_type() == protozero::pbf_wire_type::length_delimited) node(view(group.get_view()));
                else if (group.tag() == 2 && group.wire_type() == protozero::pbf_wire_type::length_delimited) dense(view(group.get_view()));
                else if (group.tag() == 3 && group.wire_type() == protozero::pbf_wire_type::length_delimited) way(view(group.get_view()));
                else group.skip();
            }
        }
    }

private:
    std::int64_t add(std::int64_t a, std::int64_t b, const std::string& what) const {
        std::int64_t sum = 0;
        if (__builtin_add_overflow(a, b, &sum)) pbf_error(name_, what + ": a delta runs past 64 bits");
        return sum;
    }

    void coordinate(std::int64_t value, bool latitude, const std::string& what) const {
        std::int64_t scaled = 0;
        std::int64_t placed = 0;
        if (__builtin_mul_overflow(value, static_cast<std::int64_t>(granularity_), &scaled) ||
            __builtin_add_overflow(scaled, latitude ? lat_offset_ : lon_offset_, &placed)) {
            pbf_error(name_, what + ": its " + (latitude ? "latitude" : "longitude") + " runs past 64 bits");
        }
        // In nanodegrees.
        const std::int64_t limit = latitude ? std::int64_t{90'000'000'000} : std::int64_t{180'000'000'000};
        if (placed < -limit || placed > limit) {
            pbf_error(name_, what + ": its " + (latitude ? "latitude" : "longitude") + " is out of range (" +
                                 (latitude ? "-90 to 90" : "-180 to 180") + ")");
        }
    }

    void node(std::string_view data) const {
        protozero::pbf_reader message = reader(data);
        std::int64_t id = 0, lat = 0, lon = 0;
        while (message.next()) {
            if (message.tag() == 1 && message.wire_type() == protozero::pbf_wire_type::varint) id = message.get_sint64();
            else if (message.tag() == 8 && message.wire_type() == protozero::pbf_wire_type::varint) lat = message.get_sint64();
            else if (message.tag() == 9 && message.wire_type() == protozero::pbf_wire_type::varint) lon = message.get_sint64();
            else message.skip();
        }
        const std::string what = "node " + std::to_string(id);
        coordinate(lat, true, what);
        coordinate(lon, false, what);
    }

    void dense(std::string_view data) const {
        std::string_view ids, lats, lons;
        protozero::pbf_reader message = reader(data);
        while (message.next()) {
            if (message.wire_type() != protozero::pbf_wire_type::length_delimited) message.skip();
            else if (message.tag() == 1) ids = view(message.get_view());
            else if (message.tag() == 8) lats = view(message.get_view());
            else if (message.tag() == 9) lons = view(message.get_view());
            else message.skip();
        }
        std::vector<std::int64_t> id_deltas = packed(ids), lat_deltas = packed(lats), lon_deltas = packed(lons);
        // libosmium decodes node after node and stops at the first whose coordinates are missing.
        const std::size_t count = std::min({id_deltas.size(), lat_deltas.size(), lon_deltas.size()});
        std::int64_t id = 0, lat = 0, lon = 0;
        for (std::size_t i = 0; i < count; ++i) {
            const std::string previous = "dense node " + std::to_string(i);
            id = add(id, id_deltas[i], previous);
            const std::string what = "node " + std::to_string(id);
            lat = add(lat, lat_deltas[i], what);
            lon = add(lon, lon_deltas[i], what);
            coordinate(lat, true, what);
            coordinate(lon, false, what);
        }
    }

    void way(std::string_view data) const {
        std::int64_t id = 0;
        std::string_view refs, lats, lons;
        protozero::pbf_reader message = reader(data);
        while (message.next()) {
            if (message.tag() == 1 && message.wire_type() == protozero::pbf_wire_type::varint) id = message.get_int64();
            else if (message.wire_type() != protozero::pbf_wire_type::length_delimited) message.skip();
            else if (message.tag() == 8) refs = view(message.get_view());
            else if (message.tag() == 9) lats = view(message.get_view());
            else if (message.tag() == 10) lons = view(message.get_view());
            else message.skip();
        }
        const std::string what = "way " + std::to_string(id);
        std::int64_t ref = 0;
        for (const std::int64_t delta : packed(refs)) ref = add(ref, delta, what);
        // Locations on ways (an osmium extension) are decoded only while refs, lats and lons last.
        const std::vector<std::int64_t> lat_deltas = packed(lats), lon_deltas = packed(lons);
        std::int64_t lat = 0, lon = 0;
        for (std::size_t i = 0; i < std::min(lat_deltas.size(), lon_deltas.size()); ++i) {
            lat = add(lat, lat_deltas[i], what);
            lon = add(lon, lon_deltas[i], what);
            coordinate(lat, true, what);
            coordinate(lon, false, what);
        }
    }

    static std::vector<std::int64_t> packed(std::string_view data) {
        std::vector<std::int64_t> values;
        if (data.data() == nullptr || data.empty()) return values;
        const char* p = data.data();
        const char* end = p + data.size();
        try {
            while (p != end) {
                const std::uint64_t raw = protozero::decode_varint(&p, end);
                values.push_back(protozero::decode_zigzag64(raw));
            }
        } catch (const protozero::exception&) {
            // Truncated: libosmium decodes up to here, then reports it.
        }
        return values;
    }

    const std::string& name_;
    std::int32_t granularity_ = 100;
    std::int64_t lat_offset_ = 0;
    std::int64_t lon_offset_ = 0;
};

} // namespace

void check_pbf(std::string_view data, const std::string& name) {
    const std::uint64_t size = data.size();
    std::uint64_t offset = 0;
    std::string block;
    while (offset + 4 <= size) {
        const auto* b = reinterpret_cast<const unsigned char*>(data.data() + offset);
        const std::uint32_t length = (std::uint32_t{b[0]} << 24) | (std::uint32_t{b[1]} << 16) | (std::uint32_t{b[2]} << 8) | std::uint32_t{b[3]};
        if (length == 0 || length > 64 * 1024 || offset + 4 + length > size) return; // libosmium reports these itself
        bool typed = false;
        bool osm_data = false;
        std::int64_t datasize = 0;
        try {
            protozero::pbf_reader message(data.data() + offset + 4, length);
            while (message.next()) {
                if (message.tag() == 1 && message.wire_type() == protozero::pbf_wire_type::length_delimited) {
                    const std::string_view type = view(message.get_view());
                    typed = !type.empty();
                    osm_data = type == "OSMData";
                } else if (message.tag() == 3 && message.wire_type() == protozero::pbf_wire_type::varint) {
                    datasize = message.get_int32();
                } else {
                    message.skip();
                }
            }
        } catch (const protozero::exception&) {
            return; // a malformed header: libosmium reports it
        }
        if (!typed) pbf_error(name, "the blob header at byte " + std::to_string(offset) + " has no type");
        if (datasize <= 0) return;
        const std::uint64_t blob_start = offset + 4 + length;
        if (blob_start + static_cast<std::uint64_t>(datasize) > size) return;
        if (osm_data) {
            try {
                if (blob_bytes(data.substr(blob_start, static_cast<std::size_t>(datasize)), block)) BlockChecker(name, block);
            } catch (const protozero::exception&) {
                return; // malformed protobuf: libosmium reports it
            }
        }
        offset = blob_start + static_cast<std::uint64_t>(datasize);
    }
}

void check_osm_text(std::string_view text, TextFormat format, const std::string& name) {
    const Checker checker(name);
    if (format == TextFormat::xml) check_xml(text, checker);
    else check_opl(text, checker);
}

} // namespace ggg::osm_detail
