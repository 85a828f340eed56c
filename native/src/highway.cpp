#include "ggg/highway.hpp"

#include <algorithm>

#include "ggg/error.hpp"

namespace ggg {
namespace {

struct ClassInfo {
    std::string_view name;
    int rank;
    double width_m;
};

constexpr std::array<ClassInfo, highway_class_count> class_info{{
    {"motorway", 1, 14.0},     {"trunk", 2, 12.0},         {"primary", 3, 10.0},
    {"secondary", 4, 9.0},     {"tertiary", 5, 8.0},       {"unclassified", 6, 6.0},
    {"residential", 7, 6.0},   {"living_street", 8, 5.0},  {"motorway_link", 2, 6.0},
    {"trunk_link", 3, 6.0},    {"primary_link", 4, 6.0},   {"secondary_link", 5, 5.5},
    {"tertiary_link", 6, 5.5}, {"service", 9, 4.0},        {"pedestrian", 10, 4.0},
    {"track", 10, 3.0},        {"road", 7, 6.0},           {"busway", 9, 4.0},
    {"footway", 11, 2.0},      {"cycleway", 11, 2.0},      {"path", 11, 1.5},
    {"steps", 11, 2.0},        {"bridleway", 11, 2.0},     {"other", 12, 3.0},
}};

constexpr std::array<std::string_view, 13> drivable_values{
    "motorway",      "trunk",      "primary",      "secondary",      "tertiary",
    "unclassified",  "residential", "living_street", "motorway_link", "trunk_link",
    "primary_link",  "secondary_link", "tertiary_link"};

} // namespace

std::string_view highway_name(HighwayClass c) noexcept {
    return class_info[static_cast<std::size_t>(c)].name;
}

std::optional<HighwayClass> highway_from_known_name(std::string_view value) noexcept {
    for (int i = 0; i < highway_class_count; ++i) {
        if (class_info[static_cast<std::size_t>(i)].name == value) {
            return static_cast<HighwayClass>(i);
        }
    }
    return std::nullopt;
}

HighwayClass highway_from_name(std::string_view value) noexcept {
    return highway_from_known_name(value).value_or(HighwayClass::other);
}

int highway_rank(HighwayClass c) noexcept { return class_info[static_cast<std::size_t>(c)].rank; }

double highway_default_width(HighwayClass c) noexcept {
    return class_info[static_cast<std::size_t>(c)].width_m;
}

HighwayFilter HighwayFilter::drivable() {
    HighwayFilter f;
    f.values_.assign(drivable_values.begin(), drivable_values.end());
    f.description_ = "drivable";
    return f;
}

HighwayFilter HighwayFilter::all() {
    HighwayFilter f;
    f.all_ = true;
    f.description_ = "all";
    return f;
}

HighwayFilter HighwayFilter::parse(std::string_view spec) {
    if (spec == "drivable") return drivable();
    if (spec == "all") return all();
    HighwayFilter f;
    f.description_ = std::string(spec);
    std::size_t start = 0;
    while (start <= spec.size()) {
        const std::size_t comma = std::min(spec.find(',', start), spec.size());
        std::string_view item = spec.substr(start, comma - start);
        while (!item.empty() && item.front() == ' ') item.remove_prefix(1);
        while (!item.empty() && item.back() == ' ') item.remove_suffix(1);
        if (!item.empty()) {
            if (!highway_from_known_name(item)) {
                std::string known;
                for (int c = 0; c < highway_class_count; ++c) {
                    known += (c ? ", " : "") + std::string(highway_name(static_cast<HighwayClass>(c)));
                }
                throw UsageError("unknown highway class '" + std::string(item) +
                                 "' in the filter (use drivable, all, or a comma-separated list of: " + known + ")");
            }
            f.values_.emplace_back(item);
        }
        start = comma + 1;
    }
    if (f.values_.empty()) {
        throw UsageError("empty highway filter (use drivable, all, or a list of highway values)");
    }
    return f;
}

bool HighwayFilter::accepts(std::string_view highway_value) const noexcept {
    if (all_) return !highway_value.empty();
    if (highway_value.empty()) return false;
    const std::string_view key = highway_from_known_name(highway_value) ? highway_value : std::string_view("other");
    return std::find(values_.begin(), values_.end(), key) != values_.end();
}

} // namespace ggg
