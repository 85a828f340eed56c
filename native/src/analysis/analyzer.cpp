// Detection, then selection; see analyzer.hpp.
#include "ggg/analysis/analyzer.hpp"

#include <algorithm>
#include <set>
#include <string>

#include "ggg/analysis/pattern.hpp"

namespace ggg {

namespace {

// Maps a stage's progress 0..1 onto [lo, hi] of the caller's.
ProgressCallback stage(const ProgressCallback& progress, double lo, double hi) {
    if (!progress) return {};
    return [=](double f, std::string_view message) { return progress(lo + (hi - lo) * f, message); };
}

// The seed search and the recount compare sizes as the detection does.
SeedSearchOptions search_options(const AnalyzeOptions& options) {
    SeedSearchOptions s;
    s.tolerance = options.tolerance;
    s.mode = options.detection.scale_mode;
    s.min_scale = options.detection.min_scale;
    s.max_scale = options.detection.max_scale;
    s.respect_symbols = options.detection.respect_symbols;
    return s;
}

} // namespace

void check_options(const AnalyzeOptions& o) {
    check_options(o.detection);
    auto fail = [](const char* name, const std::string& what, double got) {
        throw UsageError(std::string(name) + ": must be " + what + ", got " + std::to_string(got));
    };
    if (!(o.tolerance >= 0.0 && o.tolerance < 1.0)) fail("tolerance", "a number from 0 to below 1", o.tolerance);
    if (!(o.constraints.min_aspect >= 0.0 && o.constraints.min_aspect <= 1.0)) fail("min_aspect", "a number from 0 to 1", o.constraints.min_aspect);
    if (!(o.constraints.min_irregularity_deg >= 0.0 && o.constraints.min_irregularity_deg <= 45.0)) {
        fail("min_irregularity", "a number of degrees from 0 to 45", o.constraints.min_irregularity_deg);
    }
    if (o.recount_top > 100'000) fail("recount", "a count from 0 to 100000", static_cast<double>(o.recount_top));
}

Analysis analyze(const GeometricGraph& g, const AnalyzeOptions& options, const ProgressCallback& progress) {
    check_options(options);
    DetectionResult detected;
    const bool seeded = !options.seed.empty();
    if (seeded) {
        Isogroup seed = find_similar(g, options.seed, options, stage(progress, 0.0, 0.1));
        detected = detect_isogroups_from(g, std::move(seed), options.detection, stage(progress, 0.1, 0.85));
    } else {
        detected = detect_isogroups(g, options.detection, stage(progress, 0.0, 0.85));
    }

    std::vector<SelectedIsogroup> selected =
        select_isogroups(g, detected.isogroups, options.constraints, options.selection, stage(progress, 0.85, 0.9));

    // Recount the leading groups, then the ones that the new ranking brings up (a recount
    // lowers a group's gain when the expansion let loose copies in), until the leading
    // groups are all recounted (at most eight rounds).
    std::vector<char> recounted(detected.isogroups.size(), 0);
    // The seed's group is not recounted: it holds the copies within the tolerance already (and,
    // include_analysis_group, the ones the analysis groups with it, which a recount would drop).
    if (seeded && !detected.isogroups.empty()) recounted[0] = 1;
    const SeedSearchOptions exact = search_options(options);
    for (int round = 0; round < 8 && options.recount_top > 0; ++round) {
        report(progress, 0.9 + 0.01 * round, "counting the leading patterns exactly");
        std::vector<std::size_t> todo;
        for (std::size_t i = 0; i < std::min(options.recount_top, selected.size()); ++i) {
            if (!recounted[selected[i].index]) todo.push_back(selected[i].index);
        }
        if (todo.empty()) break;
        for (std::size_t index : todo) {
            Isogroup& group = detected.isogroups[index];
            if (group.order() < 2 || group.pattern.edges.empty()) {
                recounted[index] = 1;
                continue;
            }
            Isogroup copies = find_settled_pattern(g, group.pattern, exact);
            group.pattern = std::move(copies.pattern);
            group.vertices = std::move(copies.vertices);
            group.transforms = std::move(copies.transforms);
            recounted[index] = 1;
        }
        // Two groups that recount to the same pattern are one: keep the better ranked.
        std::vector<std::size_t> kept;
        for (const SelectedIsogroup& s : selected) {
            if (!recounted[s.index]) continue;
            for (std::size_t other : kept) {
                const Isogroup& a = detected.isogroups[other];
                Isogroup& b = detected.isogroups[s.index];
                if (a.order() == b.order() && a.frequency() == b.frequency() && a.vertices.size() == b.vertices.size()) {
                    IsomorphismOptions iso;
                    iso.tolerance = options.detection.merge_tolerance;
                    iso.respect_symbols = options.detection.respect_symbols;
                    if (geometrically_isomorphic(a.pattern, b.pattern, iso)) {
                        b.vertices.clear();
                        b.transforms.clear();
                        break;
                    }
                }
            }
            if (!detected.isogroups[s.index].transforms.empty()) kept.push_back(s.index);
        }
        for (SelectedIsogroup& s : selected) {
            if (std::find(todo.begin(), todo.end(), s.index) != todo.end() || detected.isogroups[s.index].frequency() == 0) {
                s = select_one(g, detected.isogroups[s.index], s.index, options.selection);
            }
        }
        std::erase_if(selected, [&](const SelectedIsogroup& s) {
            return !violated_constraint(s.shape, options.constraints).empty() && !(seeded && s.index == 0);
        });
        sort_by_gain(selected, detected.isogroups);
    }
    // Groups left without occurrences (recounted to nothing, or duplicates) are dropped.
    std::erase_if(selected, [&](const SelectedIsogroup& s) { return detected.isogroups[s.index].frequency() < options.detection.min_count && !(seeded && s.index == 0); });
    report(progress, 1.0, "counting the leading patterns exactly");
    if (seeded) {
        // The seed's group first, whatever the constraints say (and the ranking put it).
        auto it = std::find_if(selected.begin(), selected.end(), [](const SelectedIsogroup& s) { return s.index == 0; });
        if (it != selected.end()) {
            std::rotate(selected.begin(), it, it + 1);
        } else {
            SelectionConstraints none;
            std::vector<Isogroup> just_seed{detected.isogroups[0]};
            auto first = select_isogroups(g, just_seed, none, options.selection);
            selected.insert(selected.begin(), std::move(first.front()));
        }
    }

    Analysis result;
    result.orders = std::move(detected.orders);
    result.detected = detected.isogroups.size();
    result.stopped_by_budget = detected.stopped_by_budget;
    std::vector<long> position(detected.isogroups.size(), -1);
    for (std::size_t i = 0; i < selected.size(); ++i) position[selected[i].index] = static_cast<long>(i);
    result.isogroups.reserve(selected.size());
    for (SelectedIsogroup& s : selected) {
        AnalyzedIsogroup a;
        const std::size_t i = s.index;
        a.group = std::move(detected.isogroups[i]);
        const long p = detected.parents[i];
        a.parent = p >= 0 ? position[static_cast<std::size_t>(p)] : -1;
        a.score = detected.scores[i];
        a.recounted = recounted[i] != 0 && !(seeded && i == 0 && options.include_analysis_group);
        a.selection = std::move(s);
        result.isogroups.push_back(std::move(a));
    }
    return result;
}

Isogroup find_similar(const GeometricGraph& g, std::span<const VertexId> seed, const AnalyzeOptions& options,
                      const ProgressCallback& progress) {
    check_options(options);
    Isogroup found = find_occurrences(g, seed, search_options(options), stage(progress, 0.0, 0.3));
    const std::size_t k = found.order();
    if (!options.include_analysis_group || found.pattern.edges.empty() ||
        (options.detection.max_order > 0 && k > static_cast<std::size_t>(options.detection.max_order))) {
        return found;
    }

    // The group the analysis puts the seed in: detection up to the seed's order, the most
    // frequent group of that order with the seed's vertex set among its occurrences.
    DetectionOptions detection = options.detection;
    detection.max_order = static_cast<int>(k);
    const DetectionResult detected = detect_isogroups(g, detection, stage(progress, 0.3, 0.95));
    std::vector<VertexId> seed_set(seed.begin(), seed.end());
    std::sort(seed_set.begin(), seed_set.end());
    const Isogroup* group = nullptr;
    std::size_t seed_at = 0;
    for (const Isogroup& candidate : detected.isogroups) {
        if (candidate.order() != k || candidate.pattern.edges.size() != found.pattern.edges.size()) continue;
        if (group && candidate.frequency() <= group->frequency()) continue;
        for (std::size_t o = 0; o < candidate.frequency(); ++o) {
            const auto occ = candidate.occurrence(o);
            std::vector<VertexId> set(occ.begin(), occ.end());
            std::sort(set.begin(), set.end());
            if (set == seed_set) {
                group = &candidate;
                seed_at = o;
                break;
            }
        }
    }
    report(progress, 1.0, "finding similar pieces");
    if (!group) return found;

    // The group's occurrences are labelled alike; relabel them as the seed is labelled.
    const auto seed_occurrence = group->occurrence(seed_at);
    std::vector<std::size_t> from_group(k);
    for (std::size_t i = 0; i < k; ++i) {
        from_group[i] = static_cast<std::size_t>(std::find(seed_occurrence.begin(), seed_occurrence.end(), seed[i]) - seed_occurrence.begin());
    }
    std::set<std::vector<VertexId>> have;
    for (std::size_t o = 0; o < found.frequency(); ++o) {
        const auto occ = found.occurrence(o);
        std::vector<VertexId> set(occ.begin(), occ.end());
        std::sort(set.begin(), set.end());
        have.insert(std::move(set));
    }
    std::vector<Vec2> world(k);
    for (std::size_t o = 0; o < group->frequency(); ++o) {
        const auto occ = group->occurrence(o);
        std::vector<VertexId> labelled(k);
        for (std::size_t i = 0; i < k; ++i) labelled[i] = occ[from_group[i]];
        std::vector<VertexId> set = labelled;
        std::sort(set.begin(), set.end());
        if (!have.insert(std::move(set)).second) continue;
        for (std::size_t i = 0; i < k; ++i) world[i] = g.positions[static_cast<std::size_t>(labelled[i])];
        found.vertices.insert(found.vertices.end(), labelled.begin(), labelled.end());
        found.transforms.push_back(fit_similarity(found.pattern.positions, world).transform);
    }
    return found;
}

} // namespace ggg
