#include "ggg/graph/road_class.hpp"

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

} // namespace ggg
