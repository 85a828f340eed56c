#include "ggg/osm/osm_import.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <unordered_map>

#include <osmium/io/any_input.hpp>
#include <osmium/osm/location.hpp>
#include <osmium/osm/node.hpp>
#include <osmium/osm/way.hpp>

#include "ggg/error.hpp"
#include "ggg/files.hpp"
#include "ggg/osm/projection.hpp"
#include "osm_text.hpp"

namespace ggg {
namespace {

bool ends_with(const std::string& s, std::string_view suffix) {
    return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

struct RawWay {
    std::int64_t id;
    std::int64_t first_ref; // into refs
    std::int64_t ref_count;
    EdgeAttributes attributes;
};

// The value of `key` among `tags`, read within the list's own bytes. A PBF string that holds a
// NUL byte (corrupt data libosmium does not refuse) misaligns the list's key\0value\0 pairs, and
// libosmium's own lookup then reads past the list's end (fuzzing finding).
const char* tag_value(const osmium::TagList& tags, const char* key) {
    // A TagList is its Collection header followed by the strings (as Collection::cbegin has it).
    static_assert(sizeof(osmium::TagList) == sizeof(osmium::memory::Collection<osmium::Tag, osmium::item_type::tag_list>));
    const char* p = reinterpret_cast<const char*>(tags.data()) + sizeof(osmium::TagList);
    const char* end = reinterpret_cast<const char*>(tags.data()) + tags.byte_size();
    while (p < end) {
        const char* key_end = static_cast<const char*>(std::memchr(p, 0, static_cast<std::size_t>(end - p)));
        if (!key_end || key_end + 1 >= end) return nullptr;
        const char* value = key_end + 1;
        const char* value_end = static_cast<const char*>(std::memchr(value, 0, static_cast<std::size_t>(end - value)));
        if (!value_end) return nullptr;
        if (std::strcmp(p, key) == 0) return value;
        p = value_end + 1;
    }
    return nullptr;
}

void check_readable(const std::string& path) {
    std::error_code ec;
    const auto status = std::filesystem::status(path, ec);
    if (ec || !std::filesystem::exists(status)) throw InputError(path + ": no such file");
    if (std::filesystem::is_directory(status)) throw InputError(path + ": is a folder, not an OSM file");
    // A pipe or a device is read with a bound (osm_text.hpp, files.hpp); a regular file must hold something.
    if (std::filesystem::is_regular_file(status) && std::filesystem::file_size(path, ec) == 0) throw InputError(path + ": the file is empty");
}

} // namespace

bool is_osm_path(const std::string& path) {
    for (std::string_view suffix : {".osm", ".osm.pbf", ".pbf", ".osm.bz2", ".osm.gz", ".opl", ".osm.opl"}) {
        if (ends_with(path, suffix)) return true;
    }
    return false;
}

std::int8_t parse_oneway(const char* oneway, const char* junction, HighwayClass highway) noexcept {
    if (oneway) {
        if (!std::strcmp(oneway, "yes") || !std::strcmp(oneway, "true") || !std::strcmp(oneway, "1")) return 1;
        if (!std::strcmp(oneway, "-1") || !std::strcmp(oneway, "reverse")) return -1;
        if (!std::strcmp(oneway, "no") || !std::strcmp(oneway, "false") || !std::strcmp(oneway, "0")) return 0;
    }
    if (junction && (!std::strcmp(junction, "roundabout") || !std::strcmp(junction, "circular"))) return 1;
    if (highway == HighwayClass::motorway) return 1; // implied by OSM convention
    return 0;
}

std::int16_t parse_lanes(const char* lanes) noexcept {
    if (!lanes) return 0;
    char* end = nullptr;
    const long n = std::strtol(lanes, &end, 10);
    if (end == lanes || n <= 0 || n > 50) return 0;
    return static_cast<std::int16_t>(n);
}

double parse_width_m(const char* width) noexcept {
    constexpr double none = std::numeric_limits<double>::quiet_NaN();
    if (!width) return none;
    std::string text(width);
    std::replace(text.begin(), text.end(), ',', '.');
    char* end = nullptr;
    const double w = std::strtod(text.c_str(), &end);
    if (end == text.c_str() || !std::isfinite(w) || w <= 0 || w > 200) return none;
    std::string_view unit(end);
    while (!unit.empty() && unit.front() == ' ') unit.remove_prefix(1);
    if (unit.empty() || unit == "m") return w;
    if (unit == "ft" || unit == "'") return w * 0.3048;
    return none; // an unknown unit is not a width we can trust
}

GeometricGraph import_osm(const std::string& path, const ImportOptions& options, ImportReport* report_out,
                          const ProgressCallback& progress) {
    check_readable(path);
    ImportReport stats;
    std::vector<std::pair<std::int64_t, osmium::Location>> nodes;
    std::vector<std::int64_t> refs;
    std::vector<RawWay> ways;

    report(progress, 0.0, "reading " + std::filesystem::path(path).filename().string());
    try {
        osmium::io::File file(path);
        std::error_code ec;
        // Text formats are read whole and checked first (osm_text.hpp); PBF goes to libosmium.
        std::string text;
        if (file.format() == osmium::io::file_format::xml || file.format() == osmium::io::file_format::opl) {
            const bool xml = file.format() == osmium::io::file_format::xml;
            text = osm_detail::read_osm_text(path);
            osm_detail::check_osm_text(text, xml ? osm_detail::TextFormat::xml : osm_detail::TextFormat::opl, path);
            file = osmium::io::File(text.data(), text.size(), xml ? "osm" : "opl");
        } else if (file.format() == osmium::io::file_format::pbf) {
            // Read whole, so that libosmium holds no file open: its PBF reader leaves the file's
            // descriptor open when the data is corrupt (fuzzing), which a long-lived Blender
            // session would pile up.
            text = read_text_file(path);
            osm_detail::check_pbf(text, path);
            file = osmium::io::File(text.data(), text.size(), "pbf");
        }
        const auto file_size = static_cast<double>(!text.empty() ? text.size() : std::max<std::uintmax_t>(1, std::filesystem::file_size(path, ec)));
        // Metadata (versions, timestamps, users) is not part of a road graph: not decoding it is faster
        // and avoids libosmium's delta decoding of timestamps, which overflows on corrupt PBF (fuzzing).
        osmium::io::Reader reader(file, osmium::osm_entity_bits::node | osmium::osm_entity_bits::way, osmium::io::read_meta::no);
        std::size_t buffers = 0;
        while (osmium::memory::Buffer buffer = reader.read()) {
            for (const auto& item : buffer) {
                if (item.type() == osmium::item_type::node) {
                    const auto& node = static_cast<const osmium::Node&>(item);
                    // A node without a location (deleted, in history files) is skipped; one with
                    // coordinates out of range is an error, not a node silently lost.
                    if (node.location() && !node.location().valid()) {
                        throw InputError(path + ": node " + std::to_string(node.id()) + ": coordinates out of range (latitude -90 to 90, longitude -180 to 180)");
                    }
                    nodes.emplace_back(node.id(), node.location());
                } else if (item.type() == osmium::item_type::way) {
                    const auto& way = static_cast<const osmium::Way&>(item);
                    const osmium::TagList& tags = way.tags();
                    const char* highway = tag_value(tags, "highway");
                    if (!highway || !*highway) continue;
                    ++stats.highway_ways;
                    if (!options.highways.accepts(highway)) continue;
                    EdgeAttributes a;
                    a.highway = highway_from_name(highway);
                    a.oneway = parse_oneway(tag_value(tags, "oneway"), tag_value(tags, "junction"), a.highway);
                    a.lanes = parse_lanes(tag_value(tags, "lanes"));
                    a.width_m = parse_width_m(tag_value(tags, "width"));
                    a.way_id = way.id();
                    if (const char* name = tag_value(tags, "name")) a.name = name;
                    RawWay raw{way.id(), static_cast<std::int64_t>(refs.size()), 0, std::move(a)};
                    for (const auto& ref : way.nodes()) refs.push_back(ref.ref());
                    raw.ref_count = static_cast<std::int64_t>(refs.size()) - raw.first_ref;
                    ways.push_back(std::move(raw));
                }
            }
            if (++buffers % 16 == 0) {
                report(progress, 0.45 * std::min(1.0, static_cast<double>(reader.offset()) / file_size), "reading");
            }
        }
        reader.close();
    } catch (const Error&) {
        throw;
    } catch (const std::bad_alloc&) {
        throw Error(path + ": out of memory while reading");
    } catch (const std::exception& e) {
        throw InputError(path + ": not a readable OSM file (" + e.what() + ")");
    }
    stats.nodes_read = nodes.size();
    stats.ways_kept = ways.size();
    if (ways.empty()) {
        std::string message = path + ": no roads: the file has no highway ways";
        if (stats.highway_ways > 0) {
            message += " of the classes '" + options.highways.description() + "' (it has " +
                       std::to_string(stats.highway_ways) + " highway ways of other classes; import all classes to include them)";
        }
        throw InputError(message);
    }

    // Unsorted files and repeated ids: order nodes by id, the last version of an id wins.
    report(progress, 0.45, "resolving nodes");
    std::stable_sort(nodes.begin(), nodes.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    {
        std::vector<std::pair<std::int64_t, osmium::Location>> unique;
        unique.reserve(nodes.size());
        for (const auto& n : nodes) {
            if (!unique.empty() && unique.back().first == n.first) unique.back() = n;
            else unique.push_back(n);
        }
        nodes.swap(unique);
    }
    // The last version of a way id wins, as for nodes.
    std::stable_sort(ways.begin(), ways.end(), [](const RawWay& a, const RawWay& b) { return a.id < b.id; });
    {
        std::vector<RawWay> unique;
        unique.reserve(ways.size());
        for (auto& w : ways) {
            if (!unique.empty() && unique.back().id == w.id) unique.back() = std::move(w);
            else unique.push_back(std::move(w));
        }
        ways.swap(unique);
    }

    // Distinct referenced ids, each mapped to a place; nodes at the same place are one node.
    std::vector<std::int64_t> referenced(refs);
    std::sort(referenced.begin(), referenced.end());
    referenced.erase(std::unique(referenced.begin(), referenced.end()), referenced.end());
    stats.referenced_nodes = referenced.size();

    constexpr std::int32_t missing = -1;
    std::vector<std::int32_t> place_of(referenced.size(), missing);
    TopologyInput input;
    std::unordered_map<std::uint64_t, std::int32_t> place_index;
    place_index.reserve(referenced.size());
    std::vector<Vec2> lonlat;
    double min_lon = 180, max_lon = -180, min_lat = 90, max_lat = -90;
    auto node_it = nodes.begin();
    for (std::size_t i = 0; i < referenced.size(); ++i) {
        const std::int64_t id = referenced[i];
        node_it = std::lower_bound(node_it, nodes.end(), id, [](const auto& n, std::int64_t value) { return n.first < value; });
        if (node_it == nodes.end() || node_it->first != id) {
            ++stats.missing_nodes;
            continue;
        }
        const osmium::Location loc = node_it->second;
        if (!loc.valid()) {
            ++stats.invalid_locations;
            continue;
        }
        const std::uint64_t key = (static_cast<std::uint64_t>(static_cast<std::uint32_t>(loc.x())) << 32) |
                                  static_cast<std::uint32_t>(loc.y());
        const auto [it, inserted] = place_index.emplace(key, static_cast<std::int32_t>(lonlat.size()));
        if (inserted) {
            lonlat.emplace_back(loc.lon(), loc.lat());
            input.node_osm_ids.push_back(id);
            min_lon = std::min(min_lon, loc.lon());
            max_lon = std::max(max_lon, loc.lon());
            min_lat = std::min(min_lat, loc.lat());
            max_lat = std::max(max_lat, loc.lat());
        }
        place_of[i] = it->second;
    }
    if (lonlat.empty()) {
        throw InputError(path + ": no roads: none of the " + std::to_string(stats.referenced_nodes) +
                         " nodes the highway ways reference is in the file with valid coordinates");
    }

    // Ways as runs of present nodes; a missing node splits the way.
    std::vector<std::int32_t> run;
    for (const RawWay& way : ways) {
        run.clear();
        auto flush = [&] {
            if (run.size() >= 2) input.add_way(run, way.attributes);
            run.clear();
        };
        for (std::int64_t r = way.first_ref; r < way.first_ref + way.ref_count; ++r) {
            const auto pos = std::lower_bound(referenced.begin(), referenced.end(), refs[static_cast<std::size_t>(r)]);
            const std::int32_t place = place_of[static_cast<std::size_t>(pos - referenced.begin())];
            if (place == missing) flush();
            else run.push_back(place);
        }
        flush();
    }
    if (input.way_count() == 0) {
        throw InputError(path + ": no roads: every highway way lacks the nodes it needs (a clipped extract?)");
    }

    report(progress, 0.5, "projecting");
    const GeoOrigin origin = options.origin.value_or(GeoOrigin{(min_lat + max_lat) / 2, (min_lon + max_lon) / 2});
    LocalProjection projection(origin);
    try {
        projection.forward(std::span<Vec2>(lonlat));
    } catch (const InputError& e) {
        throw InputError(path + ": " + e.what());
    }
    input.node_positions = std::move(lonlat);

    GeometricGraph graph;
    try {
        graph = build_graph(input, origin, options.topology, &stats.topology, progress);
    } catch (const InputError& e) {
        throw InputError(path + ": " + e.what());
    }
    report(progress, 1.0, "done");
    if (report_out) *report_out = stats;
    return graph;
}

} // namespace ggg
