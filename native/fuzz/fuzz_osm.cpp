// OpenStreetMap import (ggg::import_osm) of every format libosmium reads here. The first
// byte picks the format and options, the rest is the file:
//   byte % 5:        .osm (XML), .osm.pbf, .opl, .osm.gz (gzip XML), .osm.bz2 (bzip2 XML)
//   byte / 5 % 2:    1 = all highway classes (else drivable ones)
//   byte / 10 % 2:   1 = keep shape nodes
//   byte / 20 % 2:   1 = consolidate vertices within 5 m
// A graph that comes back must be simple (topology.hpp); an InputError is a correct outcome.
//
// The file must be closed again whatever happened: a descriptor left open on it is a finding
// (libosmium's PBF reader used to leave it open on corrupt data; a Blender session would pile
// them up).
#include <dirent.h>
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "fuzz_common.hpp"
#include "ggg/error.hpp"
#include "ggg/osm/osm_import.hpp"
#include "ggg/osm/highway_filter.hpp"

namespace {

// Closes the descriptors still open on `path`; returns how many there were.
std::size_t close_descriptors_of(const std::string& path) {
    DIR* dir = ::opendir("/proc/self/fd");
    if (!dir) return 0;
    std::vector<int> found;
    while (const dirent* entry = ::readdir(dir)) {
        char target[4096];
        const std::string link = std::string("/proc/self/fd/") + entry->d_name;
        const ssize_t n = ::readlink(link.c_str(), target, sizeof target - 1);
        if (n <= 0) continue;
        target[n] = 0;
        if (path == target) found.push_back(std::atoi(entry->d_name));
    }
    ::closedir(dir);
    for (int fd : found) ::close(fd);
    return found.size();
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 1) return 0;
    static constexpr const char* suffixes[] = {".osm", ".osm.pbf", ".opl", ".osm.gz", ".osm.bz2"};
    const unsigned selector = data[0];
    ggg::ImportOptions options;
    if (selector / 5 % 2) options.highways = ggg::HighwayFilter::all();
    options.topology.keep_shape_nodes = selector / 10 % 2;
    if (selector / 20 % 2) options.topology.consolidate_m = 5.0;
    const ggg_fuzz::TempFile file(data + 1, size - 1, suffixes[selector % 5]);
    try {
        ggg::ImportReport report;
        const ggg::GeometricGraph graph = ggg::import_osm(file.path(), options, &report);
        if (const std::string problem = ggg::check_simple(graph); !problem.empty()) {
            ggg_fuzz::fail("import_osm returned a graph that is not simple: " + problem);
        }
    } catch (const ggg::Error&) {
    }
    if (const std::size_t leaked = close_descriptors_of(file.path())) {
        ggg_fuzz::fail("import_osm left " + std::to_string(leaked) + " descriptor(s) of its file open");
    }
    return 0;
}
