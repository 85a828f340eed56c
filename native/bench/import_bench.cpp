// Import speed on real extracts (../shared/osm). Figures are written in docs/benchmarks.md.
// Run: build/bin/ggg_bench [--benchmark_filter=porto]
#include <sys/resource.h>

#include <filesystem>

#include <benchmark/benchmark.h>

#include "ggg/io/read_graph.hpp"
#include "ggg/osm/highway_filter.hpp"

namespace {

double peak_memory_mb() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return static_cast<double>(usage.ru_maxrss) / 1024.0;
}

void import_file(benchmark::State& state, const std::string& file, const std::string& highways, double consolidate_m) {
    const std::string path = std::string(GGG_SHARED_OSM_DIR) + "/" + file;
    if (!std::filesystem::exists(path)) {
        state.SkipWithError(("../shared/osm/" + file + " not found").c_str());
        return;
    }
    ggg::ImportOptions options;
    options.highways = ggg::HighwayFilter::parse(highways);
    options.topology.consolidate_m = consolidate_m;
    std::size_t vertices = 0, edges = 0;
    for (auto _ : state) {
        const ggg::GeometricGraph g = ggg::read_graph(path, options);
        vertices = g.vertex_count();
        edges = g.edge_count();
        benchmark::DoNotOptimize(g.positions.data());
    }
    state.counters["vertices"] = static_cast<double>(vertices);
    state.counters["edges"] = static_cast<double>(edges);
    state.counters["peak_MB"] = peak_memory_mb();
}

} // namespace

BENCHMARK_CAPTURE(import_file, porto_all, "porto_metro.osm.pbf", "all", 0.0)->Unit(benchmark::kMillisecond)->MinTime(3);
BENCHMARK_CAPTURE(import_file, porto_drivable, "porto_metro.osm.pbf", "drivable", 0.0)->Unit(benchmark::kMillisecond)->MinTime(3);
BENCHMARK_CAPTURE(import_file, porto_all_consolidate_10m, "porto_metro.osm.pbf", "all", 10.0)->Unit(benchmark::kMillisecond)->MinTime(3);
BENCHMARK_CAPTURE(import_file, rhein_neckar_all, "rhein_neckar_roads.osm.pbf", "all", 0.0)->Unit(benchmark::kMillisecond)->MinTime(3);
BENCHMARK_CAPTURE(import_file, barcelona_all, "barcelona_eixample.osm", "all", 0.0)->Unit(benchmark::kMillisecond)->MinTime(1);
BENCHMARK_CAPTURE(import_file, paris_all, "paris_marais.osm.pbf", "all", 0.0)->Unit(benchmark::kMillisecond)->MinTime(1);
// Text formats are read whole and checked (coordinates, token lengths) before libosmium parses them.
BENCHMARK_CAPTURE(import_file, rome_all_xml, "rome_centre.osm", "all", 0.0)->Unit(benchmark::kMillisecond)->MinTime(1);
BENCHMARK_CAPTURE(import_file, krems_all_xml_gz, "krems_at.osm.gz", "all", 0.0)->Unit(benchmark::kMillisecond)->MinTime(1);

BENCHMARK_MAIN();
