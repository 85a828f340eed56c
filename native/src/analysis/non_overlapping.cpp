// The non-overlapping selection, one connected component of the overlap graph at a time:
// the solvers are in local_search.cpp and branch_and_bound.cpp.
#include "ggg/analysis/non_overlapping.hpp"

#include <algorithm>
#include <string>

#include "ggg/error.hpp"
#include "independent_set.hpp"

namespace ggg {

namespace {

using namespace non_overlapping_detail; // LocalGraph, the solvers, the bounds, kNone

// The branch and bound keeps an s x s bit matrix of the component and one bit row per
// recursion level; beyond this size that is tens of megabytes and the search would not
// finish anyway (exact solvers stop being practical at a few thousand occurrences).
constexpr std::size_t kMaxExactComponent = 16384;

const std::string kExactMethod = "exact branch and bound";
const std::string kHeuristicMethod = "greedy min-degree + local search";

// Seeded per component (by its first occurrence), so that a component's result does not
// depend on the others.
Random component_rng(std::uint64_t seed, std::uint32_t root) {
    return Random{seed ^ (0x9E3779B97F4A7C15ULL * (static_cast<std::uint64_t>(root) + 1))};
}

std::vector<std::uint32_t> to_members(const std::vector<std::uint8_t>& flags) {
    std::vector<std::uint32_t> members;
    for (std::uint32_t v = 0; v < flags.size(); ++v) {
        if (flags[v]) members.push_back(v);
    }
    return members;
}

std::vector<std::uint8_t> to_flags(const std::vector<std::uint32_t>& members, std::uint32_t s) {
    std::vector<std::uint8_t> flags(s, 0);
    for (const std::uint32_t v : members) flags[v] = 1;
    return flags;
}

SelectionResult select(const OverlapGraph& graph, const SelectionOptions& options) {
    if (options.local_search_rounds < 0) {
        throw UsageError("non-overlapping selection: local_search_rounds must be >= 0");
    }
    const std::size_t exact_limit = std::min(options.exact_limit, kMaxExactComponent);
    const auto n = static_cast<std::uint32_t>(graph.size());
    SelectionResult result;
    bool heuristic_used = false;

    std::vector<std::uint8_t> visited(n, 0);
    std::vector<std::uint32_t> component, local(n, kNone);
    LocalGraph g;
    for (std::uint32_t root = 0; root < n; ++root) {
        if (visited[root]) continue;
        // The component of `root`, by breadth-first search.
        component.clear();
        component.push_back(root);
        visited[root] = 1;
        for (std::size_t head = 0; head < component.size(); ++head) {
            for (const std::uint32_t j : graph.neighbours_of(component[head])) {
                if (!visited[j]) {
                    visited[j] = 1;
                    component.push_back(j);
                }
            }
        }
        if (component.size() == 1) {
            result.chosen.push_back(root);
            ++result.upper_bound;
            continue;
        }
        if (component.size() == 2) { // one overlapping pair
            result.chosen.push_back(root);
            ++result.upper_bound;
            continue;
        }
        std::sort(component.begin(), component.end());
        const auto s = static_cast<std::uint32_t>(component.size());
        for (std::uint32_t a = 0; a < s; ++a) local[component[a]] = a;
        g.offsets.assign(1, 0);
        g.nbrs.clear();
        for (const std::uint32_t v : component) {
            for (const std::uint32_t j : graph.neighbours_of(v)) g.nbrs.push_back(local[j]);
            g.offsets.push_back(g.nbrs.size());
        }

        const bool small = s <= exact_limit;
        LocalSearch search(g, greedy_min_degree(g));
        search.descend();
        if (!options.prove) {
            heuristic_used = true;
            result.exact = false;
            result.upper_bound += s;
            for (const std::uint32_t a : to_members(search.solution())) result.chosen.push_back(component[a]);
            continue;
        }
        std::uint32_t bound = index_cover_bound(g);
        if (!small && search.count() < bound) {
            bound = std::min(bound, guided_cover_bound(g, search.solution()));
        }
        if (!small && search.count() < bound) {
            Random random = component_rng(options.seed, root);
            search.iterate(static_cast<std::uint64_t>(options.local_search_rounds) * s, bound, random);
            bound = std::min(bound, guided_cover_bound(g, search.solution()));
        }
        std::vector<std::uint32_t> best = to_members(search.solution());

        bool proven = best.size() == bound;
        if (!proven && small) {
            BranchAndBound exact(g, options.node_budget);
            proven = exact.solve(best);
            // A search cut short may end on a set that is not maximal; fill it up.
            std::vector<std::uint8_t> blocked(s, 0);
            for (const std::uint32_t a : best) {
                blocked[a] = 1;
                for (const std::uint32_t* p = g.begin(a); p != g.end(a); ++p) blocked[*p] = 1;
            }
            for (std::uint32_t a = 0; a < s; ++a) {
                if (!blocked[a]) {
                    best.push_back(a);
                    for (const std::uint32_t* p = g.begin(a); p != g.end(a); ++p) blocked[*p] = 1;
                }
            }
            if (!proven) {
                // Cut short: polish its best set as a large component would be.
                LocalSearch polish(g, to_flags(best, s));
                polish.descend();
                Random random = component_rng(options.seed, root);
                polish.iterate(static_cast<std::uint64_t>(options.local_search_rounds) * s, bound, random);
                best = to_members(polish.solution());
                bound = std::min(bound, guided_cover_bound(g, polish.solution()));
            }
        }
        if (!small || !proven) heuristic_used = true;
        result.exact = result.exact && proven;
        result.upper_bound += proven ? best.size() : bound;
        for (const std::uint32_t a : best) result.chosen.push_back(component[a]);
    }
    std::sort(result.chosen.begin(), result.chosen.end());
    result.method = heuristic_used ? (options.prove ? kHeuristicMethod : "greedy min-degree + swaps, unproven")
                                   : kExactMethod;
    return result;
}

} // namespace

SelectionResult select_independent_set(const OverlapGraph& graph, const SelectionOptions& options) {
    non_overlapping_detail::check_graph(graph);
    return select(graph, options);
}

SelectionResult select_non_overlapping(std::span<const VertexId> vertices, std::size_t k,
                                       const SelectionOptions& options) {
    if (options.local_search_rounds < 0) {
        throw UsageError("non-overlapping selection: local_search_rounds must be >= 0");
    }
    return select(build_overlap_graph(vertices, k), options);
}

} // namespace ggg
