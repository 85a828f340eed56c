// Non-overlapping selection (maximum independent set of the overlap graph) on synthetic
// occurrence sets of the sizes seen on real cities (30k and 160k occurrences).
// Run: build/bin/ggg_selection_bench [--benchmark_filter=random5]
// Counters: chosen = occurrences selected, bound = upper bound on the optimum,
// gap_pct = 100 * (bound - chosen) / bound (an over-estimate of the distance to optimal),
// overlaps = edges of the overlap graph.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <random>
#include <vector>

#include <benchmark/benchmark.h>

#include "ggg/analysis/non_overlapping.hpp"

namespace {

using ggg::VertexId;

// `count` random connected 5-vertex subsets of a side x side grid graph (random growth
// from a random start vertex), like the occurrences of one order-5 isogroup in a
// grid-like street network. Fixed seed, so every run sees the same input.
std::vector<VertexId> random_connected_subsets(int side, std::size_t count, std::size_t k = 5) {
    std::mt19937_64 rng(42);
    std::uniform_int_distribution<int> coordinate(0, side - 1);
    std::vector<VertexId> occ;
    occ.reserve(count * k);
    std::vector<VertexId> members, frontier;
    for (std::size_t i = 0; i < count; ++i) {
        members.assign(1, coordinate(rng) * side + coordinate(rng));
        while (members.size() < k) {
            const VertexId from = members[std::uniform_int_distribution<std::size_t>(0, members.size() - 1)(rng)];
            const int r = from / side, c = from % side;
            frontier.clear();
            if (r > 0) frontier.push_back(from - side);
            if (r + 1 < side) frontier.push_back(from + side);
            if (c > 0) frontier.push_back(from - 1);
            if (c + 1 < side) frontier.push_back(from + 1);
            const VertexId next = frontier[std::uniform_int_distribution<std::size_t>(0, frontier.size() - 1)(rng)];
            if (std::find(members.begin(), members.end(), next) == members.end()) members.push_back(next);
        }
        occ.insert(occ.end(), members.begin(), members.end());
    }
    return occ;
}

// All unit squares of a side x side grid graph, plus (when `triangles`) both triangles
// of every square once a diagonal is added: one large, dense component, the hard case.
std::vector<VertexId> squares_and_triangles(int side, bool triangles, std::size_t& k) {
    std::vector<VertexId> occ;
    k = triangles ? 3 : 4;
    for (int r = 0; r + 1 < side; ++r) {
        for (int c = 0; c + 1 < side; ++c) {
            const VertexId a = r * side + c, b = a + 1, d = a + side, e = d + 1;
            if (triangles) {
                occ.insert(occ.end(), {a, b, e});
                occ.insert(occ.end(), {a, e, d});
            } else {
                occ.insert(occ.end(), {a, b, e, d});
            }
        }
    }
    return occ;
}

void run(benchmark::State& state, const std::vector<VertexId>& occ, std::size_t k, const ggg::SelectionOptions& options) {
    ggg::SelectionResult result;
    for (auto _ : state) {
        result = ggg::select_non_overlapping(occ, k, options);
        benchmark::DoNotOptimize(result.chosen.data());
    }
    state.counters["occurrences"] = static_cast<double>(occ.size() / k);
    state.counters["chosen"] = static_cast<double>(result.chosen.size());
    state.counters["bound"] = static_cast<double>(result.upper_bound);
    state.counters["gap_pct"] = result.upper_bound == 0
        ? 0.0
        : 100.0 * static_cast<double>(result.upper_bound - result.chosen.size()) / static_cast<double>(result.upper_bound);
    state.counters["exact"] = result.exact ? 1 : 0;
}

// Random connected 5-vertex occurrences on a square grid with `vertices_per_occurrence`
// grid vertices per occurrence: 5 gives a sparse overlap graph with many components (each
// vertex in one occurrence on average), 1 one giant component (each vertex in five), like a
// frequent small pattern. Arguments: occurrences, local search rounds, exact limit.
void random_subsets(benchmark::State& state, double vertices_per_occurrence) {
    const auto count = static_cast<std::size_t>(state.range(0));
    const int side = static_cast<int>(std::sqrt(vertices_per_occurrence * static_cast<double>(count)));
    static std::map<std::pair<int, std::size_t>, std::vector<VertexId>> cache;
    auto& occ = cache[{side, count}];
    if (occ.empty()) occ = random_connected_subsets(side, count);
    ggg::SelectionOptions options;
    options.local_search_rounds = static_cast<int>(state.range(1));
    options.exact_limit = static_cast<std::size_t>(state.range(2));
    run(state, occ, 5, options);
}

void random5(benchmark::State& state) { random_subsets(state, 5.0); }
void random5_dense(benchmark::State& state) { random_subsets(state, 1.0); }

void grid_squares(benchmark::State& state) {
    std::size_t k = 0;
    const auto occ = squares_and_triangles(static_cast<int>(state.range(0)), false, k);
    ggg::SelectionOptions options;
    options.local_search_rounds = static_cast<int>(state.range(1));
    run(state, occ, k, options);
}

void grid_triangles(benchmark::State& state) {
    std::size_t k = 0;
    const auto occ = squares_and_triangles(static_cast<int>(state.range(0)), true, k);
    ggg::SelectionOptions options;
    options.local_search_rounds = static_cast<int>(state.range(1));
    run(state, occ, k, options);
}

void build_overlap_graph(benchmark::State& state) {
    const auto count = static_cast<std::size_t>(state.range(0));
    const auto occ = random_connected_subsets(static_cast<int>(std::sqrt(static_cast<double>(count))), count);
    std::size_t edges = 0;
    for (auto _ : state) {
        const ggg::OverlapGraph g = ggg::build_overlap_graph(occ, 5);
        edges = g.edge_count();
        benchmark::DoNotOptimize(g.neighbors.data());
    }
    state.counters["occurrences"] = static_cast<double>(count);
    state.counters["overlaps"] = static_cast<double>(edges);
}

} // namespace

BENCHMARK(random5)->ArgNames({"n", "rounds", "exact"})
    ->Args({30'000, 0, 64})->Args({30'000, 1, 64})->Args({30'000, 1, 0})
    ->Args({160'000, 0, 64})->Args({160'000, 1, 64})->Args({160'000, 1, 0})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(random5_dense)->ArgNames({"n", "rounds", "exact"})
    ->Args({30'000, 0, 64})->Args({30'000, 1, 64})->Args({30'000, 4, 64})
    ->Args({160'000, 0, 64})->Args({160'000, 1, 64})->Args({160'000, 4, 64})
    ->Unit(benchmark::kMillisecond);
// 174^2 -> 30k squares, 401^2 -> 160k squares; 123 and 284 -> 30k and 160k triangles.
BENCHMARK(grid_squares)->ArgNames({"side", "rounds"})
    ->Args({174, 1})->Args({401, 1})->Unit(benchmark::kMillisecond);
BENCHMARK(grid_triangles)->ArgNames({"side", "rounds"})
    ->Args({123, 0})->Args({123, 1})->Args({284, 0})->Args({284, 1})->Unit(benchmark::kMillisecond);
BENCHMARK(build_overlap_graph)->Arg(30'000)->Arg(160'000)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
