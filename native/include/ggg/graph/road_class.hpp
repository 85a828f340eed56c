#pragma once
// Road classes: the class of every edge of a road graph (named after the OSM `highway`
// values they come from), their importance and typical width. The class code is what crosses into Python and Blender (an edge attribute), so the
// order of the enum is part of the file formats: append, never reorder, and bump the
// .ggraph version when appending so that older readers say "newer file" rather than fail
// on a code they do not know.
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace ggg {

// The same codes are stored in packed grammar files (version 2, docs/grammar-format.md).
enum class HighwayClass : std::uint8_t {
    motorway, trunk, primary, secondary, tertiary, unclassified, residential, living_street,
    motorway_link, trunk_link, primary_link, secondary_link, tertiary_link,
    service, pedestrian, track, road, busway, footway, cycleway, path, steps, bridleway,
    other,
};
inline constexpr int highway_class_count = static_cast<int>(HighwayClass::other) + 1;

std::string_view highway_name(HighwayClass c) noexcept;
// Any highway value not in the enum maps to `other` (e.g. "proposed", "corridor").
HighwayClass highway_from_name(std::string_view value) noexcept;
std::optional<HighwayClass> highway_from_known_name(std::string_view value) noexcept;

// 1 = most important (motorway). Links rank one below their road.
int highway_rank(HighwayClass c) noexcept;
// Typical paved width in metres when neither `width` nor `lanes` is tagged.
double highway_default_width(HighwayClass c) noexcept;

} // namespace ggg
