// Detection, then selection; see analyzer.hpp.
#include "ggg/analyzer.hpp"

#include <algorithm>
#include <string>

namespace ggg {

namespace {

// Maps a stage's progress 0..1 onto [lo, hi] of the caller's.
ProgressCallback stage(const ProgressCallback& progress, double lo, double hi) {
    if (!progress) return {};
    return [=](double f, std::string_view message) { return progress(lo + (hi - lo) * f, message); };
}

} // namespace

Analysis analyze(const GeometricGraph& g, const AnalyzeOptions& options, const ProgressCallback& progress) {
    check_options(options.detection);
    DetectionResult detected;
    const bool seeded = !options.seed.empty();
    if (seeded) {
        SeedSearchOptions s;
        s.tolerance = options.seed_tolerance;
        s.mode = options.detection.scale_mode;
        s.min_scale = options.detection.min_scale;
        s.max_scale = options.detection.max_scale;
        s.respect_symbols = options.detection.respect_symbols;
        Isogroup seed = find_occurrences(g, options.seed, s, stage(progress, 0.0, 0.1));
        detected = detect_isogroups_from(g, std::move(seed), options.detection, stage(progress, 0.1, 0.85));
    } else {
        detected = detect_isogroups(g, options.detection, stage(progress, 0.0, 0.85));
    }

    std::vector<SelectedIsogroup> selected =
        select_isogroups(detected.isogroups, options.constraints, options.selection, stage(progress, 0.85, 1.0));
    if (seeded) {
        // The seed's group first, whatever the constraints say.
        auto it = std::find_if(selected.begin(), selected.end(), [](const SelectedIsogroup& s) { return s.index == 0; });
        if (it != selected.end()) {
            std::rotate(selected.begin(), it, it + 1);
        } else {
            SelectionConstraints none;
            std::vector<Isogroup> just_seed{detected.isogroups[0]};
            auto first = select_isogroups(just_seed, none, options.selection);
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
        a.selection = std::move(s);
        result.isogroups.push_back(std::move(a));
    }
    return result;
}

} // namespace ggg
