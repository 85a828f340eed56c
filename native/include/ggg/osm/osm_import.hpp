#pragma once
// OpenStreetMap roads -> GeometricGraph, with libosmium (.osm, .osm.pbf, .osm.bz2, .osm.gz).
// Files need not be sorted, and ways may reference nodes the extract does not hold
// (clipped extracts): such a way is split at the missing nodes, not rejected.
#include <cstdint>
#include <optional>
#include <string>

#include "ggg/graph/geometric_graph.hpp"
#include "ggg/graph/road_class.hpp"
#include "ggg/osm/highway_filter.hpp"
#include "ggg/progress.hpp"
#include "ggg/osm/topology.hpp"

namespace ggg {

struct ImportOptions {
    HighwayFilter highways = HighwayFilter::drivable();
    TopologyOptions topology;
    // Project into the frame of this origin instead of one centred on the data (to line up
    // with a graph already in a scene).
    std::optional<GeoOrigin> origin;
};

// Counts of what was read, checked by tests against an independent count of the raw file.
struct ImportReport {
    std::size_t nodes_read = 0;            // node objects in the file
    std::size_t highway_ways = 0;          // ways with any highway=* tag
    std::size_t ways_kept = 0;             // of those, accepted by the filter
    std::size_t referenced_nodes = 0;      // distinct node ids referenced by the kept ways
    std::size_t missing_nodes = 0;         // of those, not in the file
    std::size_t invalid_locations = 0;     // of those, present with coordinates out of range
    TopologyReport topology;
};

// Throws InputError for a missing, unreadable or corrupt file and for a file without any
// road the filter accepts; Cancelled when the progress callback says stop.
GeometricGraph import_osm(const std::string& path, const ImportOptions& options = {},
                          ImportReport* report = nullptr, const ProgressCallback& progress = {});

// True for the file names libosmium reads (.osm, .osm.pbf, .pbf, .osm.bz2, .osm.gz, .opl).
bool is_osm_path(const std::string& path);

// Tag values to attributes ("yes"/"-1"/"reverse" oneway, "3.5 m" width, ...).
std::int8_t parse_oneway(const char* oneway, const char* junction, HighwayClass highway) noexcept;
std::int16_t parse_lanes(const char* lanes) noexcept;
double parse_width_m(const char* width) noexcept;

} // namespace ggg
