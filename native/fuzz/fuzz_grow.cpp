// Growth into a region (ggg::grow_region) over a fuzzed base and region: any graph that
// ggg.Graph.from_arrays accepts (vertices anywhere, several at one place, streets that cross,
// any road class), sometimes with a roundabout (a ring of one-way arcs, streets from it into the
// base), any region of three to eight points, a few options, and a grammar learned
// from a small grid or from the fuzzed base itself. Growth may refuse with a ggg::Error;
// otherwise the base keeps its vertices and edges, every position is finite and the graph
// stays simple.
#include <fuzzer/FuzzedDataProvider.h>

#include <cmath>
#include <cstdint>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "fuzz_common.hpp"
#include "ggg/encoding/grammar_encoder.hpp"
#include "ggg/error.hpp"
#include "ggg/synthesis/growth.hpp"

namespace {

// A 6 x 6 grid of 80 m blocks, a little uneven, learned once: a grammar with rules of a grid.
const ggg::Grammar& grid_grammar() {
    static const ggg::Grammar grammar = [] {
        ggg::GeometricGraph g;
        constexpr int n = 7;
        for (int i = 0; i < n; ++i) {
            for (int j = 0; j < n; ++j) g.add_vertex({80.0 * i + 3.0 * ((i * j) % 3), 80.0 * j + 2.0 * ((i + j) % 2)});
        }
        ggg::EdgeAttributes residential{ggg::HighwayClass::residential};
        for (int i = 0; i < n; ++i) {
            for (int j = 0; j < n; ++j) {
                if (i + 1 < n) g.add_edge(i * n + j, (i + 1) * n + j, residential);
                if (j + 1 < n) g.add_edge(i * n + j, i * n + j + 1, residential);
            }
        }
        return ggg::learn_grammar(g).grammar;
    }();
    return grammar;
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    FuzzedDataProvider in(data, size);
    const double unit = in.ConsumeIntegralInRange<int>(1, 40) * 0.5; // metres per coordinate step
    ggg::GeometricGraph base;
    const int vertices = in.ConsumeIntegralInRange<int>(2, 48);
    for (int i = 0; i < vertices; ++i) {
        const double x = in.ConsumeIntegral<std::int8_t>() * unit;
        const double y = in.ConsumeIntegral<std::int8_t>() * unit;
        base.add_vertex({x, y});
    }
    const int edges = in.ConsumeIntegralInRange<int>(1, 96);
    std::set<std::pair<int, int>> seen;
    for (int k = 0; k < edges; ++k) {
        const int u = in.ConsumeIntegralInRange<int>(0, vertices - 1);
        const int v = in.ConsumeIntegralInRange<int>(0, vertices - 1);
        const auto highway = static_cast<ggg::HighwayClass>(in.ConsumeIntegralInRange<int>(0, ggg::highway_class_count - 1));
        // As Graph.from_arrays: no loops, no edge twice.
        if (u == v || !seen.insert({std::min(u, v), std::max(u, v)}).second) continue;
        base.add_edge(u, v, ggg::EdgeAttributes{highway});
    }
    // Sometimes a roundabout too: a ring of one-way arcs with a street from each of its
    // vertices to a vertex of the base, so that growth makes roundabouts of its own.
    if (in.ConsumeBool()) {
        const ggg::Vec2 centre{in.ConsumeIntegral<std::int8_t>() * unit, in.ConsumeIntegral<std::int8_t>() * unit};
        const double radius = in.ConsumeIntegralInRange<int>(5, 40);
        const int ring = in.ConsumeIntegralInRange<int>(3, 8);
        ggg::EdgeAttributes arc{ggg::HighwayClass::tertiary};
        arc.oneway = in.ConsumeBool() ? 1 : -1;
        const auto first = static_cast<ggg::VertexId>(base.vertex_count());
        for (int k = 0; k < ring; ++k) {
            base.add_vertex(centre + radius * ggg::Vec2(std::cos(2 * M_PI * k / ring), std::sin(2 * M_PI * k / ring)));
        }
        for (int k = 0; k < ring; ++k) {
            std::vector<ggg::Vec2> line;
            for (int s = 0; s <= 4; ++s) {
                const double a = 2 * M_PI * (k + s / 4.0) / ring;
                line.push_back(centre + radius * ggg::Vec2(std::cos(a), std::sin(a)));
            }
            base.add_edge(first + k, first + (k + 1) % ring, arc, line);
            const int to = in.ConsumeIntegralInRange<int>(0, vertices - 1);
            base.add_edge(first + k, to, ggg::EdgeAttributes{ggg::HighwayClass::residential});
        }
    }
    std::vector<ggg::Vec2> region;
    const int corners = in.ConsumeIntegralInRange<int>(3, 8);
    for (int k = 0; k < corners; ++k) {
        const double x = in.ConsumeIntegral<std::int8_t>() * unit;
        const double y = in.ConsumeIntegral<std::int8_t>() * unit;
        region.emplace_back(x, y);
    }
    ggg::GrowOptions options;
    options.seed = in.ConsumeIntegral<std::uint8_t>();
    options.max_placements = 40;
    options.patience = 40;
    options.max_vertices = static_cast<std::size_t>(base.vertex_count()) + 4000;
    options.trace_streets = in.ConsumeBool();
    options.continue_hierarchy = in.ConsumeBool();
    const bool learn_from_base = in.ConsumeBool();

    // (A base with a street of no length is not simple to begin with.)
    const bool base_simple = ggg::check_simple(base).empty();
    ggg::Grammar grammar = grid_grammar();
    if (learn_from_base && base.edge_count() > 0) {
        try {
            grammar = ggg::learn_grammar(base).grammar;
        } catch (const ggg::Error&) {
            grammar = grid_grammar();
        }
    }
    try {
        ggg::GrowReport report;
        const ggg::GeometricGraph grown = ggg::grow_region(base, grammar, region, options, &report);
        if (grown.vertex_count() < base.vertex_count() || grown.edge_count() < base.edge_count()) {
            ggg_fuzz::fail("grow_region lost vertices or edges of the base");
        }
        for (std::size_t e = 0; e < base.edge_count(); ++e) {
            if (grown.edges[e] != base.edges[e]) ggg_fuzz::fail("grow_region changed base edge " + std::to_string(e));
        }
        for (const ggg::Vec2& p : grown.positions) {
            if (!p.allFinite()) ggg_fuzz::fail("grow_region made a vertex that is not finite");
        }
        const std::string problem = base_simple ? ggg::check_simple(grown) : std::string();
        if (!problem.empty()) ggg_fuzz::fail("grow_region made a graph that is not simple: " + problem);
    } catch (const ggg::Error&) {
    }
    return 0;
}
