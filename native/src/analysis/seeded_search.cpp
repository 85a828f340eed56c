// User-seeded search: every copy of a seed subgraph (see the header for the method).
#include "ggg/analysis/seeded_search.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <unordered_map>
#include <vector>

#include <tbb/parallel_for.h>

#include "ggg/error.hpp"

namespace ggg {

namespace {

struct Plan {
    Pattern pattern;
    int a = 0, b = 0;      // the start edge
    double length = 0.0;   // its length, canonical units
    Vec2 middle;
    std::vector<int> order;  // pattern vertices in placement order (a, b first)
    std::vector<int> anchor; // per order position >= 2: a placed neighbour to search from
    std::vector<std::vector<int>> neighbours;
};

Plan plan_for(const Pattern& p) {
    Plan plan;
    plan.pattern = p;
    const int k = static_cast<int>(p.size());
    plan.neighbours.resize(static_cast<std::size_t>(k));
    for (const auto& [u, v] : p.edges) {
        plan.neighbours[static_cast<std::size_t>(u)].push_back(v);
        plan.neighbours[static_cast<std::size_t>(v)].push_back(u);
    }
    if (p.edges.empty()) throw UsageError("the seed is not connected: select vertices joined by streets");
    // The longest edge pins the frame best.
    for (const auto& [u, v] : p.edges) {
        const double l = (p.positions[static_cast<std::size_t>(u)] - p.positions[static_cast<std::size_t>(v)]).norm();
        if (l > plan.length) {
            plan.length = l;
            plan.a = u;
            plan.b = v;
        }
    }
    plan.middle = (p.positions[static_cast<std::size_t>(plan.a)] + p.positions[static_cast<std::size_t>(plan.b)]) / 2.0;
    std::vector<int> position(static_cast<std::size_t>(k), -1);
    plan.order = {plan.a, plan.b};
    plan.anchor = {-1, -1};
    position[static_cast<std::size_t>(plan.a)] = 0;
    position[static_cast<std::size_t>(plan.b)] = 1;
    while (static_cast<int>(plan.order.size()) < k) {
        // Next: the vertex with most placed neighbours (tighter adjacency test), then nearest
        // to the start edge (tighter window).
        int best = -1;
        int best_links = 0;
        double best_distance = 0.0;
        for (int c = 0; c < k; ++c) {
            if (position[static_cast<std::size_t>(c)] >= 0) continue;
            int links = 0;
            for (int n : plan.neighbours[static_cast<std::size_t>(c)]) links += position[static_cast<std::size_t>(n)] >= 0;
            if (links == 0) continue;
            const double d = (p.positions[static_cast<std::size_t>(c)] - plan.middle).norm();
            if (best < 0 || links > best_links || (links == best_links && d < best_distance)) {
                best = c;
                best_links = links;
                best_distance = d;
            }
        }
        if (best < 0) throw UsageError("the seed is not connected: select vertices joined by streets");
        int anchor = -1;
        for (int n : plan.neighbours[static_cast<std::size_t>(best)]) {
            if (position[static_cast<std::size_t>(n)] >= 0 &&
                (anchor < 0 || position[static_cast<std::size_t>(n)] < position[static_cast<std::size_t>(anchor)])) {
                anchor = n;
            }
        }
        position[static_cast<std::size_t>(best)] = static_cast<int>(plan.order.size());
        plan.order.push_back(best);
        plan.anchor.push_back(anchor);
    }
    return plan;
}

Symbol symbol_of(const GeometricGraph& g, VertexId v) {
    return g.symbols.empty() ? 0 : g.symbols[static_cast<std::size_t>(v)];
}

bool adjacent(const Adjacency& adj, VertexId u, VertexId v) {
    const auto su = static_cast<std::size_t>(u);
    const auto first = adj.neighbors.begin() + adj.offsets[su];
    const auto last = adj.neighbors.begin() + adj.offsets[su + 1];
    return std::find(first, last, v) != last;
}

// Depth-first placement of the plan's vertices from one oriented start edge; complete
// mappings (graph vertex per pattern vertex) are appended to `found`.
class Walker {
public:
    Walker(const GeometricGraph& g, const Adjacency& adj, const Plan& plan, const SeedSearchOptions& o, double seed_size)
        : g_(g), adj_(adj), plan_(plan), o_(o), seed_size_(seed_size), k_(plan.order.size()), mapping_(k_, -1) {}

    void from(VertexId u, VertexId v, std::vector<std::vector<VertexId>>& found) {
        const int a = plan_.a;
        const int b = plan_.b;
        if (!fits(a, u) || !fits(b, v)) return;
        if (o_.mode == IsomorphismOptions::Scale::rigid) {
            // The start edge's length bounds the copy's size: skip edges far off the seed's.
            const double ratio = (g_.positions[static_cast<std::size_t>(v)] - g_.positions[static_cast<std::size_t>(u)]).norm() /
                                 (plan_.length * seed_size_);
            if (ratio > 1.0 + 4.0 * o_.tolerance + 0.5 || ratio < 0.5 - 4.0 * o_.tolerance) return;
        }
        mapping_[static_cast<std::size_t>(a)] = u;
        mapping_[static_cast<std::size_t>(b)] = v;
        used_.clear();
        used_.push_back(u);
        used_.push_back(v);
        place(2, found);
    }

private:
    bool fits(int c, VertexId w) const {
        if (o_.respect_symbols && plan_.pattern.symbols[static_cast<std::size_t>(c)] != symbol_of(g_, w)) return false;
        return adj_.degree(w) >= plan_.neighbours[static_cast<std::size_t>(c)].size();
    }

    void place(std::size_t depth, std::vector<std::vector<VertexId>>& found) {
        if (depth == k_) {
            found.push_back(mapping_);
            return;
        }
        const int c = plan_.order[depth];
        const VertexId from = mapping_[static_cast<std::size_t>(plan_.anchor[depth])];
        // Least-squares similarity of the vertices placed so far (the set S). If a copy
        // passes with transform T* and error eps = tau * scale(T*) per vertex, then the
        // difference D = T_S - T* has RMS at most 2 eps over S, so at a point p at distance
        // d from S's centroid |D(p)| <= 2 eps sqrt(1 + d^2 / r_S^2), r_S being S's RMS
        // radius; and scale(T*) <= scale(T_S) / (1 - 2 tau / r_S). Hence the window below,
        // which tightens as S grows and never cuts a true copy off.
        const Pattern& p = plan_.pattern;
        Vec2 pc = Vec2::Zero();
        Vec2 gc = Vec2::Zero();
        for (std::size_t i = 0; i < depth; ++i) {
            const int x = plan_.order[i];
            pc += p.positions[static_cast<std::size_t>(x)];
            gc += g_.positions[static_cast<std::size_t>(mapping_[static_cast<std::size_t>(x)])];
        }
        pc /= static_cast<double>(depth);
        gc /= static_cast<double>(depth);
        double re = 0.0;
        double im = 0.0;
        double r2 = 0.0;
        for (std::size_t i = 0; i < depth; ++i) {
            const int x = plan_.order[i];
            const Vec2 dp = p.positions[static_cast<std::size_t>(x)] - pc;
            const Vec2 dg = g_.positions[static_cast<std::size_t>(mapping_[static_cast<std::size_t>(x)])] - gc;
            re += dp.x() * dg.x() + dp.y() * dg.y();
            im += dp.x() * dg.y() - dp.y() * dg.x();
            r2 += dp.squaredNorm();
        }
        if (!(r2 > 0.0)) return;
        const double rs = std::sqrt(r2 / static_cast<double>(depth));
        const double fa = re / r2;
        const double fb = im / r2;
        const double tau = o_.tolerance;
        double size = std::hypot(fa, fb) * (rs > 2.0 * tau ? 1.0 / (1.0 - 2.0 * tau / rs) : 1e9);
        if (o_.mode == IsomorphismOptions::Scale::rigid) size = std::max(size, seed_size_ * (1.0 + tau));
        const double eps = tau * size * 1.02 + 1e-9;
        const Vec2 q = p.positions[static_cast<std::size_t>(c)] - pc;
        const Vec2 want = gc + Vec2(fa * q.x() - fb * q.y(), fb * q.x() + fa * q.y());
        const double d = q.norm();
        const double reach = eps + 2.0 * eps * std::sqrt(1.0 + d * d / (rs * rs));
        const auto f = static_cast<std::size_t>(from);
        for (auto e = adj_.offsets[f]; e < adj_.offsets[f + 1]; ++e) {
            const VertexId w = adj_.neighbors[static_cast<std::size_t>(e)];
            if (std::find(used_.begin(), used_.end(), w) != used_.end()) continue;
            if (!fits(c, w)) continue;
            if ((g_.positions[static_cast<std::size_t>(w)] - want).norm() > reach) continue;
            if (!induced_consistent(c, w, depth)) continue;
            mapping_[static_cast<std::size_t>(c)] = w;
            used_.push_back(w);
            place(depth + 1, found);
            used_.pop_back();
            mapping_[static_cast<std::size_t>(c)] = -1;
        }
    }

    // Adjacent in the pattern to exactly the placed vertices whose images w is adjacent to.
    bool induced_consistent(int c, VertexId w, std::size_t depth) const {
        for (std::size_t i = 0; i < depth; ++i) {
            const int x = plan_.order[i];
            const auto& nc = plan_.neighbours[static_cast<std::size_t>(c)];
            const bool in_pattern = std::find(nc.begin(), nc.end(), x) != nc.end();
            if (in_pattern != adjacent(adj_, w, mapping_[static_cast<std::size_t>(x)])) return false;
        }
        return true;
    }

    const GeometricGraph& g_;
    const Adjacency& adj_;
    const Plan& plan_;
    const SeedSearchOptions& o_;
    double seed_size_;
    std::size_t k_;
    std::vector<VertexId> mapping_;
    std::vector<VertexId> used_;
};


// Every induced copy of `pattern` in g (see the header), in the order of g's edges: vertex
// lists in pattern order and their transforms.
struct Copies {
    std::vector<std::vector<VertexId>> vertices;
    std::vector<Similarity2> transforms;
};

Copies search(const GeometricGraph& g, const Adjacency& adj, const Pattern& pattern, const SeedSearchOptions& o,
              const ProgressCallback& progress) {
    const Plan plan = plan_for(pattern);
    IsomorphismOptions iso;
    iso.tolerance = o.tolerance;
    iso.mode = o.mode;
    iso.min_scale = o.min_scale;
    iso.max_scale = o.max_scale;
    iso.respect_symbols = o.respect_symbols;
    report(progress, 0.0, "searching for the seed");

    // Every edge, both ways round, as the image of the start edge. Chunks keep the order.
    constexpr std::size_t chunk = 4096;
    const std::size_t chunks = (g.edge_count() + chunk - 1) / chunk;
    std::vector<std::vector<std::vector<VertexId>>> per_chunk(chunks);
    tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t c) {
        Walker walker(g, adj, plan, o, pattern.metres_per_unit);
        for (std::size_t e = c * chunk; e < std::min(g.edge_count(), (c + 1) * chunk); ++e) {
            const auto [u, v] = g.edges[e];
            walker.from(u, v, per_chunk[c]);
            walker.from(v, u, per_chunk[c]);
        }
    });
    report(progress, 0.6, "searching for the seed");

    // One candidate per vertex set, in edge order.
    std::vector<std::vector<VertexId>> candidates;
    {
        std::vector<std::vector<VertexId>> seen_sets;
        std::unordered_multimap<std::uint64_t, std::size_t> by_hash;
        for (auto& list : per_chunk) {
            for (auto& mapping : list) {
                std::vector<VertexId> key(mapping);
                std::sort(key.begin(), key.end());
                std::uint64_t h = 1469598103934665603ULL;
                for (VertexId v : key) h = (h ^ static_cast<std::uint32_t>(v)) * 1099511628211ULL;
                bool duplicate = false;
                const auto range = by_hash.equal_range(h);
                for (auto it = range.first; it != range.second && !duplicate; ++it) duplicate = seen_sets[it->second] == key;
                if (duplicate) continue;
                by_hash.emplace(h, seen_sets.size());
                seen_sets.push_back(std::move(key));
                candidates.push_back(std::move(mapping));
            }
        }
    }

    // The isomorphism test decides; it also gives the vertex order and the transform.
    std::vector<char> accepted(candidates.size(), 0);
    std::vector<Similarity2> transforms(candidates.size());
    std::vector<std::vector<VertexId>> ordered(candidates.size());
    tbb::parallel_for(std::size_t{0}, candidates.size(), [&](std::size_t i) {
        Similarity2 frame;
        const Pattern copy = induced_pattern(g, adj, candidates[i], &frame);
        const auto match = geometrically_isomorphic(pattern, copy, iso);
        if (!match) return;
        accepted[i] = 1;
        transforms[i] = frame * match->transform;
        ordered[i].resize(pattern.size());
        for (std::size_t j = 0; j < pattern.size(); ++j) {
            ordered[i][j] = candidates[i][static_cast<std::size_t>(match->mapping[j])];
        }
    });

    Copies copies;
    for (std::size_t i = 0; i < candidates.size(); ++i) {
        if (!accepted[i]) continue;
        copies.vertices.push_back(std::move(ordered[i]));
        copies.transforms.push_back(transforms[i]);
    }
    return copies;
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

} // namespace ggg
