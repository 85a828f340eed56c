#include "ggg/osm/highway_filter.hpp"

#include <algorithm>
#include <array>

#include "ggg/error.hpp"
#include "ggg/graph/road_class.hpp"

namespace ggg {
namespace {

constexpr std::array<std::string_view, 13> drivable_values{
    "motorway",      "trunk",      "primary",      "secondary",      "tertiary",
    "unclassified",  "residential", "living_street", "motorway_link", "trunk_link",
    "primary_link",  "secondary_link", "tertiary_link"};

} // namespace

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
