#pragma once
// Which `highway=*` values an OSM import keeps: the drivable roads, all of them, or a list.
#include <string>
#include <string_view>
#include <vector>

namespace ggg {

// Which `highway=*` values an import keeps.
class HighwayFilter {
public:
    // Motorway … residential, living_street, unclassified and their _link roads.
    static HighwayFilter drivable();
    static HighwayFilter all();
    // "drivable", "all" or a comma-separated list of class names ("primary,secondary");
    // "other" stands for every highway value that is not one of the named classes
    // (construction, proposed, raceway, ...). Throws UsageError naming an unknown class.
    static HighwayFilter parse(std::string_view spec);

    bool accepts(std::string_view highway_value) const noexcept;
    const std::string& description() const noexcept { return description_; }

private:
    bool all_ = false;
    std::vector<std::string> values_;
    std::string description_;
};

} // namespace ggg
