// The subgraphs that could be copies of a seed or pattern (see seed_candidates.hpp): a plan
// of the pattern, walked out depth-first from every edge of the graph.
#include "seed_candidates.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>

#include <tbb/parallel_for.h>

#include "ggg/error.hpp"

namespace ggg::seeded_search_detail {

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
            if (depth >= 2 && !fit_possible(c, w, depth, eps)) continue;
            mapping_[static_cast<std::size_t>(c)] = w;
            used_.push_back(w);
            place(depth + 1, found);
            used_.pop_back();
            mapping_[static_cast<std::size_t>(c)] = -1;
        }
    }

    // Whether the placed vertices and w at c can still be a copy: under the copy's final
    // transform every vertex is within eps of its partner, so the least-squares similarity
    // of any subset fits it with an RMS error of at most eps. Checking that as vertices are
    // placed stops a wrong start long before the window above would.
    bool fit_possible(int c, VertexId w, std::size_t depth, double eps) const {
        const Pattern& p = plan_.pattern;
        const std::size_t n = depth + 1;
        Vec2 pc = p.positions[static_cast<std::size_t>(c)];
        Vec2 gc = g_.positions[static_cast<std::size_t>(w)];
        for (std::size_t i = 0; i < depth; ++i) {
            pc += p.positions[static_cast<std::size_t>(plan_.order[i])];
            gc += g_.positions[static_cast<std::size_t>(mapping_[static_cast<std::size_t>(plan_.order[i])])];
        }
        pc /= static_cast<double>(n);
        gc /= static_cast<double>(n);
        double re = 0.0, im = 0.0, pp = 0.0, gg = 0.0;
        auto add = [&](const Vec2& pv, const Vec2& gv) {
            const Vec2 dp = pv - pc;
            const Vec2 dg = gv - gc;
            re += dp.x() * dg.x() + dp.y() * dg.y();
            im += dp.x() * dg.y() - dp.y() * dg.x();
            pp += dp.squaredNorm();
            gg += dg.squaredNorm();
        };
        add(p.positions[static_cast<std::size_t>(c)], g_.positions[static_cast<std::size_t>(w)]);
        for (std::size_t i = 0; i < depth; ++i) {
            const int x = plan_.order[i];
            add(p.positions[static_cast<std::size_t>(x)], g_.positions[static_cast<std::size_t>(mapping_[static_cast<std::size_t>(x)])]);
        }
        if (!(pp > 0.0)) return true;
        const double residual2 = gg - (re * re + im * im) / pp; // least-squares similarity, closed form
        return residual2 <= static_cast<double>(n) * eps * eps * 1.0001 + 1e-12;
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

} // namespace

std::vector<std::vector<VertexId>> candidates_for(const GeometricGraph& g, const Adjacency& adj, const Pattern& pattern,
                                                  const SeedSearchOptions& o) {
    const Plan plan = plan_for(pattern);
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
    std::vector<std::vector<VertexId>> candidates;
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
    return candidates;
}

} // namespace ggg::seeded_search_detail
