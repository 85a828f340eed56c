// Planar faces and the city ground plan on real extracts (../shared/osm). Figures are in
// docs/benchmarks.md. Run: build/bin/ggg_city_bench [--benchmark_filter=porto]
#include <filesystem>
#include <map>

#include <benchmark/benchmark.h>

#include "ggg/synthesis/city_layout.hpp"
#include "ggg/io/read_graph.hpp"
#include "ggg/graph/planar_faces.hpp"
#include "ggg/osm/highway_filter.hpp"

namespace {

const ggg::GeometricGraph* load(benchmark::State& state, const std::string& file) {
    static std::map<std::string, ggg::GeometricGraph> cache;
    const std::string path = std::string(GGG_SHARED_OSM_DIR) + "/" + file;
    if (!std::filesystem::exists(path)) {
        state.SkipWithError(("../shared/osm/" + file + " not found").c_str());
        return nullptr;
    }
    auto it = cache.find(file);
    if (it == cache.end()) {
        ggg::ImportOptions options;
        options.highways = ggg::HighwayFilter::all();
        it = cache.emplace(file, ggg::read_graph(path, options)).first;
    }
    return &it->second;
}

void faces(benchmark::State& state, const std::string& file) {
    const ggg::GeometricGraph* g = load(state, file);
    if (!g) return;
    std::size_t count = 0;
    for (auto _ : state) {
        const ggg::PlanarFaces f = ggg::planar_faces(*g);
        count = f.face_count();
        benchmark::DoNotOptimize(f.points.data());
    }
    state.counters["edges"] = static_cast<double>(g->edge_count());
    state.counters["faces"] = static_cast<double>(count);
}

void layout(benchmark::State& state, const std::string& file, unsigned threads) {
    const ggg::GeometricGraph* g = load(state, file);
    if (!g) return;
    ggg::CityLayoutOptions options;
    options.threads = threads;
    std::size_t blocks = 0, buildings = 0;
    for (auto _ : state) {
        const ggg::CityLayout plan = ggg::city_layout(*g, options);
        blocks = plan.blocks.size();
        buildings = plan.buildings.size();
        benchmark::DoNotOptimize(plan.buildings.points.data());
    }
    state.counters["edges"] = static_cast<double>(g->edge_count());
    state.counters["blocks"] = static_cast<double>(blocks);
    state.counters["buildings"] = static_cast<double>(buildings);
}

} // namespace

BENCHMARK_CAPTURE(faces, porto_all, "porto_metro.osm.pbf")->Unit(benchmark::kMillisecond)->MinTime(2);
BENCHMARK_CAPTURE(faces, paris_all, "paris_marais.osm.pbf")->Unit(benchmark::kMillisecond)->MinTime(1);
BENCHMARK_CAPTURE(layout, porto_all_1_thread, "porto_metro.osm.pbf", 1u)->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK_CAPTURE(layout, porto_all_2_threads, "porto_metro.osm.pbf", 2u)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();
BENCHMARK_CAPTURE(layout, paris_all_2_threads, "paris_marais.osm.pbf", 2u)->Unit(benchmark::kMillisecond)->MinTime(1)->UseRealTime();

BENCHMARK_MAIN();
