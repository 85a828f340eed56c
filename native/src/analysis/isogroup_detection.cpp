// Isogroup detection by vertex expansion (paper 5.1). See the header for the method; the
// notes here are about how it is made fast and deterministic:
//  - occurrences live in flat arrays (Isogroup), candidates in one flat vector per batch;
//  - parallel loops (oneTBB) write only into slots indexed by their input, and every
//    sequential merge walks those slots in index order, so the thread count never changes
//    a result;
//  - parents are processed in batches so that the candidate arrays stay bounded.
// The stages are in detection_stages.hpp; this file runs them, order by order.
#include "ggg/analysis/isogroup_detection.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <utility>

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include "ggg/error.hpp"
#include "detection_stages.hpp"

namespace ggg {

namespace {

using namespace detection_detail; // the stages, Found, Parent, Candidate, PolarGrid

// Runs body(i) for i in [0, n) in parallel, `batch` at a time, calling between(done) on the
// calling thread after each batch: where progress is reported and a cancel can stop it, so
// a long stage never holds a cancel for more than one batch.
template <class Body, class Between>
// False when `between` asked to stop (a budget ran out) before every batch was done.
bool in_batches(std::size_t n, std::size_t batch, Body&& body, Between&& between) {
    for (std::size_t start = 0; start < n; start += batch) {
        const std::size_t end = std::min(n, start + batch);
        tbb::parallel_for(start, end, body);
        if (!between(end)) return false;
    }
    return true;
}

void sort_by_frequency(std::vector<Found>& found) {
    std::stable_sort(found.begin(), found.end(), [](const Found& a, const Found& b) {
        if (a.group.frequency() != b.group.frequency()) return a.group.frequency() > b.group.frequency();
        return score_of(a) > score_of(b);
    });
}

// The time and memory budgets of DetectionOptions. Memory is what the detection holds: the
// groups found, the groups being grown and the candidates of the order at hand.
class Budget {
public:
    explicit Budget(const DetectionOptions& o) : o_(o), start_(std::chrono::steady_clock::now()) {}

    bool out_of_time() const {
        const std::chrono::duration<double> elapsed = std::chrono::steady_clock::now() - start_;
        const double budget = time_budget_seconds(o_);
        return budget > 0 && elapsed.count() > budget;
    }

    bool spent(const DetectionResult& result, const std::vector<Isogroup>& growing, std::size_t extra_bytes) const {
        if (out_of_time()) return true;
        if (o_.max_memory_mb > 0) {
            double bytes = static_cast<double>(extra_bytes);
            for (const auto* list : {&result.isogroups, &growing}) {
                for (const Isogroup& group : *list) bytes += held_bytes(group);
            }
            if (bytes > o_.max_memory_mb * 1024.0 * 1024.0) return true;
        }
        return false;
    }

private:
    static double held_bytes(const Isogroup& group) {
        return static_cast<double>(group.vertices.capacity() * sizeof(VertexId) + group.transforms.capacity() * sizeof(Similarity2) +
                                   group.pattern.size() * (sizeof(Vec2) + sizeof(Symbol)) + group.pattern.edges.size() * 8 + sizeof(Isogroup));
    }

    const DetectionOptions& o_;
    std::chrono::steady_clock::time_point start_;
};

DetectionResult run(const GeometricGraph& g, std::vector<Found> level, const DetectionOptions& o,
                    const ProgressCallback& progress) {
    DetectionResult result;
    const Budget limits(o);
    const Adjacency adjacency(g);
    const PolarGrid grid(o.angle_cells, o.distance_cells);
    const int last_order = o.max_order == 0 ? max_pattern_order : std::min(o.max_order, max_pattern_order);
    const std::string_view message = "finding repeated patterns";

    int order = level.empty() ? 2 : static_cast<int>(level.front().group.order());
    {
        OrderReport r;
        r.order = order;
        r.groups = level.size();
        for (const Found& f : level) r.occurrences += f.group.frequency();
        r.expanded_next = level.size();
        result.orders.push_back(r);
    }
    // Groups of the current order that are expanded: their indices in result.isogroups.
    std::vector<long> expand;
    std::vector<Isogroup> growing; // the groups of `expand`, as they are grown
    for (Found& f : level) {
        growing.push_back(f.group);
        expand.push_back(static_cast<long>(result.isogroups.size()));
        result.isogroups.push_back(std::move(f.group));
        result.parents.push_back(f.parent);
        result.scores.push_back(0.0);
    }

    while (order < last_order && !expand.empty()) {
        report(progress, static_cast<double>(order - 1) / static_cast<double>(last_order - 1), message);
        OrderReport r;
        r.order = order + 1;
        r.parents = expand.size();

        // Bound the work: would the children possibly overflow the budget?
        std::size_t parent_vertices = 0;
        for (const Isogroup& p : growing) parent_vertices += p.vertices.size();
        if (parent_vertices > o.max_occurrence_vertices || limits.spent(result, growing, 0)) {
            result.stopped_by_budget = true;
            break;
        }

        std::vector<Parent> parents(expand.size());
        tbb::parallel_for(std::size_t{0}, expand.size(), [&](std::size_t i) {
            parents[i].group = &growing[i];
            parents[i].index = expand[i];
            parents[i].symmetries = symmetries_of(parents[i].group->pattern, o);
        });

        // Work units: (parent, range of occurrences) of bounded size.
        constexpr std::size_t chunk = 2048;
        struct Unit {
            std::size_t parent, begin, end;
        };
        std::vector<Unit> units;
        for (std::size_t p = 0; p < parents.size(); ++p) {
            const std::size_t n = parents[p].group->frequency();
            for (std::size_t s = 0; s < n; s += chunk) units.push_back({p, s, std::min(n, s + chunk)});
        }
        std::vector<std::vector<Candidate>> unit_candidates(units.size());
        const double step_begin = static_cast<double>(order - 1) / static_cast<double>(last_order - 1);
        const double step_size = 1.0 / static_cast<double>(last_order - 1);
        const bool collected = in_batches(units.size(), 64, [&](std::size_t u) {
            collect_candidates(g, adjacency, parents[units[u].parent], grid, o.respect_symbols, units[u].begin,
                               units[u].end, unit_candidates[u]);
        }, [&](std::size_t done) {
            report(progress, step_begin + step_size * 0.3 * static_cast<double>(done) / static_cast<double>(units.size()), message);
            return !limits.out_of_time();
        });
        if (!collected) {
            result.stopped_by_budget = true;
            break;
        }

        // Gather per parent (units of a parent are consecutive and in occurrence order).
        std::vector<std::vector<Candidate>> per_parent(parents.size());
        for (std::size_t u = 0; u < units.size(); ++u) {
            auto& target = per_parent[units[u].parent];
            r.candidates += unit_candidates[u].size();
            if (target.empty()) {
                target = std::move(unit_candidates[u]);
            } else {
                target.insert(target.end(), unit_candidates[u].begin(), unit_candidates[u].end());
            }
            unit_candidates[u] = {};
        }
        if (limits.spent(result, growing, r.candidates * sizeof(Candidate))) {
            result.stopped_by_budget = true;
            break;
        }
        std::vector<std::vector<Found>> per_parent_children(parents.size());
        const bool grouped = in_batches(parents.size(), 16, [&](std::size_t p) {
            auto& c = per_parent[p];
            if (c.size() > 100'000) {
                tbb::parallel_sort(c.begin(), c.end(), candidate_less);
            } else {
                std::sort(c.begin(), c.end(), candidate_less);
            }
            per_parent_children[p] = children_of(g, parents[p], c, grid, o);
            c = {};
        }, [&](std::size_t done) {
            report(progress, step_begin + step_size * (0.3 + 0.4 * static_cast<double>(done) / static_cast<double>(parents.size())),
                   message);
            return !limits.out_of_time();
        });
        if (!grouped) {
            result.stopped_by_budget = true;
            break;
        }
        std::vector<Found> children;
        for (auto& list : per_parent_children) {
            for (Found& f : list) children.push_back(std::move(f));
        }
        per_parent_children = {};
        r.children = children.size();
        report(progress, step_begin + step_size * 0.7, message);

        tbb::parallel_for(std::size_t{0}, children.size(), [&](std::size_t i) { describe(children[i], o.respect_symbols); });
        report(progress, step_begin + step_size * 0.75, message);
        merge_isomorphic(children, g, o);
        report(progress, step_begin + step_size * 0.85, message);
        if (order == 2) {
            // Groups of two edges: here noise is largest relative to the pattern, and the
            // fragments it makes would cut whole lineages of larger patterns short.
            absorb_fragments(children, g, o, std::vector<char>(children.size(), 0));
            std::erase_if(children, [](const Found& f) { return f.merged_away; });
        }
        assign_to_one_group(children, g);
        report(progress, step_begin + step_size * 0.9, message);
        std::erase_if(children, [&](const Found& f) { return f.group.frequency() < o.min_count; });
        tbb::parallel_for(std::size_t{0}, children.size(), [&](std::size_t i) {
            if (children[i].radii.size() != children[i].group.order()) describe(children[i], o.respect_symbols);
            const auto& p = children[i].group.pattern.positions;
            children[i].added_area = std::max(0.0, hull_area(p) - hull_area(std::span<const Vec2>(p.data(), p.size() - 1)));
        });

        // Frequency cut: rank by frequency x added area (the paper's cell score), so that
        // frequent bifurcations are grown before frequent straight continuations.
        sort_by_frequency(children);
        std::vector<std::size_t> rank(children.size());
        for (std::size_t i = 0; i < rank.size(); ++i) rank[i] = i;
        std::stable_sort(rank.begin(), rank.end(), [&](std::size_t a, std::size_t b) {
            const double sa = score_of(children[a]);
            const double sb = score_of(children[b]);
            if (sa != sb) return sa > sb;
            return a < b; // children are sorted by frequency

        });
        // Of those, grow the best ones until they hold the share (1 - cut) of this order's
        // occurrences (and at most that share of its groups). Counting occurrences, not only
        // groups, is what keeps the work per order bounded on grid cities, where thousands of
        // patches of the same grid all repeat and the few most frequent hold most copies.
        std::size_t keep = children.size();
        std::vector<char> expanded(children.size(), 0);
        if (order + 1 >= last_order) {
            keep = 0; // the last order: nothing is grown
        } else if (o.full) {
            std::fill(expanded.begin(), expanded.end(), 1);
        } else {
            const int step = order - 1; // 1 for the expansion to order 3
            const double share = 1.0 - o.cut * (1.0 - std::pow(0.5, step));
            const auto max_groups = static_cast<std::size_t>(std::ceil(share * static_cast<double>(children.size())));
            std::size_t total = 0;
            for (const Found& f : children) total += f.group.frequency();
            const double budget = share * static_cast<double>(total);
            std::size_t taken = 0;
            keep = 0;
            for (std::size_t i = 0; i < rank.size() && keep < max_groups && static_cast<double>(taken) < budget; ++i) {
                expanded[rank[i]] = 1;
                taken += children[rank[i]].group.frequency();
                ++keep;
            }
        }

        // The groups to grow, as they are before fragments are folded into the reported ones.
        std::vector<Isogroup> next_growing;
        std::vector<long> next_index;
        for (std::size_t i = 0; i < children.size(); ++i) {
            if (expanded[i]) next_growing.push_back(children[i].group);
        }
        report(progress, step_begin + step_size * 0.95, message);
        absorb_fragments(children, g, o, expanded);
        ++order;
        r.expanded_next = std::min(keep, children.size());
        r.groups = 0;
        for (std::size_t i = 0; i < children.size(); ++i) {
            if (children[i].merged_away) continue;
            ++r.groups;
            r.occurrences += children[i].group.frequency();
            if (expanded[i]) next_index.push_back(static_cast<long>(result.isogroups.size()));
            result.scores.push_back(score_of(children[i]));
            result.isogroups.push_back(std::move(children[i].group));
            result.parents.push_back(children[i].parent);
        }
        growing = std::move(next_growing);
        expand = std::move(next_index);
        result.orders.push_back(r);
    }
    report(progress, 1.0, message);
    return result;
}

} // namespace

void check_options(const DetectionOptions& o) {
    // Each message starts with the option's name as the Python module spells it.
    auto fail = [](const std::string& what) { throw UsageError(what); };
    if (o.angle_cells < 1 || o.angle_cells > 360) fail("grid: needs 1 to 360 angle cells, got " + std::to_string(o.angle_cells));
    if (o.distance_cells < 1 || o.distance_cells > 100) fail("grid: needs 1 to 100 distance cells, got " + std::to_string(o.distance_cells));
    if (!(o.cut >= 0.0 && o.cut < 1.0)) fail("cut: the frequency cut must be in [0, 1), got " + std::to_string(o.cut));
    if (o.max_order < 0 || o.max_order == 1) fail("max_order: must be 0 (until nothing repeats) or at least 2, got " + std::to_string(o.max_order));
    if (o.max_order > max_pattern_order) fail("max_order: at most " + std::to_string(max_pattern_order) + ", got " + std::to_string(o.max_order));
    if (o.min_count < 1) fail("min_count: must be at least 1");
    if (!std::isfinite(o.max_seconds)) fail("max_seconds: the time budget must be a number of seconds (0 = none, < 0 = automatic)");
    if (!(std::isfinite(o.max_memory_mb) && o.max_memory_mb >= 0.0)) fail("max_memory_mb: the memory budget must be a number of megabytes >= 0 (0 = none)");
    if (!(o.merge_tolerance >= 0.0 && o.merge_tolerance < 1.0)) fail("merge_tolerance: must be in [0, 1), got " + std::to_string(o.merge_tolerance));
    if (!(o.scale_tolerance > 0.0 && o.scale_tolerance < 1.0)) fail("scale_tolerance: must be in (0, 1), got " + std::to_string(o.scale_tolerance));
    if (o.scale_mode == IsomorphismOptions::Scale::range &&
        !(std::isfinite(o.min_scale) && std::isfinite(o.max_scale) && o.min_scale > 0.0 && o.min_scale < o.max_scale)) {
        fail("scale_range: must satisfy 0 < min < max");
    }
}

DetectionResult detect_isogroups(const GeometricGraph& g, const DetectionOptions& options,
                                 const ProgressCallback& progress) {
    check_options(options);
    return run(g, edge_groups(g, options), options, progress);
}

DetectionResult detect_isogroups_from(const GeometricGraph& g, Isogroup seed, const DetectionOptions& options,
                                      const ProgressCallback& progress) {
    check_options(options);
    if (const std::string problem = check_pattern(seed.pattern); !problem.empty()) {
        throw UsageError("analysis seed: " + problem);
    }
    if (seed.order() > static_cast<std::size_t>(max_pattern_order)) {
        throw UsageError("analysis seed: at most " + std::to_string(max_pattern_order) + " vertices");
    }
    if (seed.vertices.size() != seed.order() * seed.frequency()) throw UsageError("analysis seed: malformed occurrences");
    std::vector<Found> level(1);
    level[0].group = std::move(seed);
    refine(level[0].group, g);
    return run(g, std::move(level), options, progress);
}

} // namespace ggg
