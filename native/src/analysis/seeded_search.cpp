// User-seeded search: every copy of a seed subgraph (see the header for the method).
#include "ggg/analysis/seeded_search.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include <tbb/parallel_for.h>

#include "ggg/error.hpp"
#include "seed_candidates.hpp"

namespace ggg {

namespace {

using seeded_search_detail::candidates_for;

// Every induced copy of `pattern` in g (see the header), in the order of g's edges: vertex
// lists in pattern order and their transforms.
struct Copies {
    std::vector<std::vector<VertexId>> vertices;
    std::vector<Similarity2> transforms;
};

IsomorphismOptions isomorphism_options(const SeedSearchOptions& o) {
    IsomorphismOptions iso;
    iso.tolerance = o.tolerance;
    iso.mode = o.mode;
    iso.min_scale = o.min_scale;
    iso.max_scale = o.max_scale;
    iso.respect_symbols = o.respect_symbols;
    return iso;
}

// Candidates cut out of the graph once, to be decided against several patterns.
struct CutCandidates {
    std::vector<std::vector<VertexId>> vertices;
    std::vector<std::optional<PreparedPattern>> patterns;
    std::vector<Similarity2> frames; // canonical -> graph
};

CutCandidates cut(const GeometricGraph& g, const Adjacency& adj, std::vector<std::vector<VertexId>> candidates) {
    CutCandidates out;
    out.patterns.resize(candidates.size());
    out.frames.resize(candidates.size());
    tbb::parallel_for(std::size_t{0}, candidates.size(), [&](std::size_t i) {
        out.patterns[i].emplace(induced_pattern(g, adj, candidates[i], &out.frames[i]));
    });
    out.vertices = std::move(candidates);
    return out;
}

// The candidates that the isomorphism test accepts as copies of `pattern`, in their order,
// with their vertices in pattern order and their transforms.
Copies accept(const CutCandidates& c, const Pattern& pattern, const IsomorphismOptions& iso) {
    const std::size_t n = c.vertices.size();
    const PreparedPattern prepared(pattern);
    std::vector<char> accepted(n, 0);
    std::vector<Similarity2> transforms(n);
    std::vector<std::vector<VertexId>> ordered(n);
    tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
        const auto match = geometrically_isomorphic(prepared, *c.patterns[i], iso);
        if (!match) return;
        accepted[i] = 1;
        transforms[i] = c.frames[i] * match->transform;
        ordered[i].resize(pattern.size());
        for (std::size_t j = 0; j < pattern.size(); ++j) {
            ordered[i][j] = c.vertices[i][static_cast<std::size_t>(match->mapping[j])];
        }
    });
    Copies copies;
    for (std::size_t i = 0; i < n; ++i) {
        if (!accepted[i]) continue;
        copies.vertices.push_back(std::move(ordered[i]));
        copies.transforms.push_back(transforms[i]);
    }
    return copies;
}

Copies search(const GeometricGraph& g, const Adjacency& adj, const Pattern& pattern, const SeedSearchOptions& o,
              const ProgressCallback& progress) {
    report(progress, 0.0, "searching for the seed");
    std::vector<std::vector<VertexId>> candidates = candidates_for(g, adj, pattern, o);
    report(progress, 0.6, "searching for the seed");
    // The isomorphism test decides; it also gives the vertex order and the transform.
    return accept(cut(g, adj, std::move(candidates)), pattern, isomorphism_options(o));
}

void check_tolerance(const SeedSearchOptions& o) {
    if (!std::isfinite(o.tolerance) || o.tolerance < 0.0 || o.tolerance >= 1.0) {
        throw UsageError("seed search tolerance must be in [0, 1), got " + std::to_string(o.tolerance));
    }
}

} // namespace

Isogroup find_occurrences(const GeometricGraph& g, std::span<const VertexId> seed, const SeedSearchOptions& o,
                          const ProgressCallback& progress) {
    check_tolerance(o);
    if (seed.size() < 2) throw UsageError("a seed needs at least two vertices joined by a street");
    const Adjacency adj(g);
    Similarity2 seed_frame;
    const Pattern pattern = induced_pattern(g, adj, seed, &seed_frame); // validates ids
    if (spread_of(pattern.positions).degenerate) throw UsageError("the seed's vertices all lie at one point");
    Copies copies = search(g, adj, pattern, o, progress);

    Isogroup group;
    group.pattern = pattern;
    std::vector<VertexId> seed_sorted(seed.begin(), seed.end());
    std::sort(seed_sorted.begin(), seed_sorted.end());
    // The seed itself first, in the seed's own vertex order.
    group.vertices.assign(seed.begin(), seed.end());
    group.transforms.push_back(seed_frame);
    for (std::size_t i = 0; i < copies.vertices.size(); ++i) {
        std::vector<VertexId> key(copies.vertices[i]);
        std::sort(key.begin(), key.end());
        if (key == seed_sorted) continue;
        group.vertices.insert(group.vertices.end(), copies.vertices[i].begin(), copies.vertices[i].end());
        group.transforms.push_back(copies.transforms[i]);
    }
    report(progress, 1.0, "searching for the seed");
    return group;
}

Isogroup find_pattern(const GeometricGraph& g, const Pattern& pattern, const SeedSearchOptions& o,
                      const ProgressCallback& progress) {
    check_tolerance(o);
    if (const std::string problem = check_pattern(pattern); !problem.empty()) throw UsageError("pattern: " + problem);
    if (pattern.size() < 2 || pattern.edges.empty()) throw UsageError("pattern: a pattern to search needs an edge");
    if (spread_of(pattern.positions).degenerate) throw UsageError("pattern: its vertices all lie at one point");
    const Adjacency adj(g);
    // The plan starts from an edge and walks the pattern's edges: it must be connected.
    Copies copies = search(g, adj, pattern, o, progress);
    Isogroup group;
    group.pattern = pattern;
    for (std::size_t i = 0; i < copies.vertices.size(); ++i) {
        group.vertices.insert(group.vertices.end(), copies.vertices[i].begin(), copies.vertices[i].end());
        group.transforms.push_back(copies.transforms[i]);
    }
    report(progress, 1.0, "searching for the pattern");
    return group;
}

Pattern mean_pattern(const GeometricGraph& g, const Isogroup& group) {
    const std::size_t k = group.order();
    const std::size_t n = group.frequency();
    Pattern mean = group.pattern;
    if (n == 0 || k == 0) return mean;
    std::vector<Vec2> sum(k, Vec2::Zero());
    double scale_sum = 0.0;
    std::size_t used = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const Similarity2& t = group.transforms[i];
        const double s = std::hypot(t.a, t.b);
        if (!(s > 0.0)) continue;
        const Similarity2 inverse = t.inverse();
        const std::span<const VertexId> occ = group.occurrence(i);
        for (std::size_t j = 0; j < k; ++j) sum[j] += inverse.apply(g.positions[static_cast<std::size_t>(occ[j])]);
        scale_sum += s;
        ++used;
    }
    if (used == 0) return mean;
    for (Vec2& p : sum) p /= static_cast<double>(used);
    const Spread spread = spread_of(sum);
    if (spread.degenerate) return mean;
    for (Vec2& p : sum) p = (p - spread.centroid) / spread.rms;
    mean.positions = std::move(sum);
    // The transforms give metres per unit of the old pattern; the mean's unit is
    // spread.rms of those.
    mean.metres_per_unit = scale_sum / static_cast<double>(used) * spread.rms;
    return mean;
}

namespace {

// A pattern made exactly as symmetric as it nearly is: each vertex becomes the mean of its
// images under the pattern's symmetries. Copies of a nearly symmetric pattern (a square
// block) can be labelled in several ways, and each copy takes the labelling that fits the
// current estimate best; a skewed estimate would then pick the copies' skews in its own
// direction and keep its skew for ever.
Pattern symmetrised(Pattern p, double tolerance) {
    IsomorphismOptions iso;
    iso.tolerance = tolerance;
    const std::vector<IsomorphismMatch> symmetries = geometric_automorphisms(p, iso);
    if (symmetries.size() < 2) return p;
    std::vector<Vec2> sum(p.size(), Vec2::Zero());
    for (const IsomorphismMatch& m : symmetries) {
        // m.transform takes vertex i near vertex m.mapping[i]; its inverse brings the
        // partner back onto i.
        const Similarity2 back = m.transform.inverse();
        for (std::size_t i = 0; i < p.size(); ++i) {
            sum[i] += back.apply(p.positions[static_cast<std::size_t>(m.mapping[i])]);
        }
    }
    for (Vec2& q : sum) q /= static_cast<double>(symmetries.size());
    const Spread spread = spread_of(sum);
    if (spread.degenerate) return p;
    for (Vec2& q : sum) q = (q - spread.centroid) / spread.rms;
    p.positions = std::move(sum);
    p.metres_per_unit *= spread.rms;
    return p;
}

} // namespace

Isogroup find_settled_pattern(const GeometricGraph& g, const Pattern& pattern, const SeedSearchOptions& o,
                              int max_rounds) {
    check_tolerance(o);
    if (const std::string problem = check_pattern(pattern); !problem.empty()) throw UsageError("pattern: " + problem);
    if (pattern.size() < 2 || pattern.edges.empty()) throw UsageError("pattern: a pattern to search needs an edge");
    if (spread_of(pattern.positions).degenerate) throw UsageError("pattern: its vertices all lie at one point");
    const Adjacency adj(g);
    auto vertex_sets = [](const Copies& copies) {
        std::vector<std::vector<VertexId>> sets = copies.vertices;
        for (auto& set : sets) std::sort(set.begin(), set.end());
        std::sort(sets.begin(), sets.end());
        return sets;
    };
    auto as_group = [](const Pattern& p, const Copies& copies) {
        Isogroup group;
        group.pattern = p;
        for (const auto& v : copies.vertices) group.vertices.insert(group.vertices.end(), v.begin(), v.end());
        group.transforms = copies.transforms;
        return group;
    };
    const IsomorphismOptions count = isomorphism_options(o);
    // Every round decides the same candidates, found once in a window a tenth wider than the
    // tolerance; when the estimate has moved by more than that tenth, they are found again.
    SeedSearchOptions pool_options = o;
    pool_options.tolerance = std::min(0.95, 1.1 * o.tolerance);
    IsomorphismOptions drift = count;
    drift.mode = IsomorphismOptions::Scale::similarity;
    drift.tolerance = pool_options.tolerance - o.tolerance;

    Pattern estimate = pattern;
    Pattern pool_origin = pattern;
    CutCandidates pool = cut(g, adj, candidates_for(g, adj, estimate, pool_options));
    Copies copies = accept(pool, estimate, count);
    std::vector<std::vector<VertexId>> sets = vertex_sets(copies);
    for (int round = 1; round < max_rounds && !copies.vertices.empty(); ++round) {
        estimate = symmetrised(mean_pattern(g, as_group(estimate, copies)), o.tolerance);
        if (!geometrically_isomorphic(pool_origin, estimate, drift)) {
            pool_origin = estimate;
            pool = cut(g, adj, candidates_for(g, adj, estimate, pool_options));
        }
        Copies next = accept(pool, estimate, count);
        std::vector<std::vector<VertexId>> next_sets = vertex_sets(next);
        const bool settled = next_sets == sets;
        copies = std::move(next);
        sets = std::move(next_sets);
        if (settled) break;
    }
    return as_group(estimate, copies);
}

} // namespace ggg
