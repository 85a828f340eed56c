// The isogroup detection's expansion: the candidates of a parent's occurrences, binned in
// the polar grid, become its children (detection_stages.hpp).
#include "detection_stages.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <unordered_map>

#include <tbb/parallel_for.h>

namespace ggg::detection_detail {

namespace {

std::uint64_t permute_mask(std::uint64_t mask, const std::vector<int>& perm) {
    std::uint64_t out = 0;
    while (mask) {
        const int j = std::countr_zero(mask);
        mask &= mask - 1;
        out |= std::uint64_t{1} << perm[static_cast<std::size_t>(j)];
    }
    return out;
}

Symbol symbol_of(const GeometricGraph& g, VertexId v) {
    return g.symbols.empty() ? 0 : g.symbols[static_cast<std::size_t>(v)];
}

// Splits a group whose occurrences have different sizes into groups of one size (rigid)
// or of sizes within a factor (range), by clustering log(scale) like the polar grid.
std::vector<Isogroup> split_by_scale(Isogroup group, const DetectionOptions& o) {
    std::vector<Isogroup> out;
    if (o.scale_mode == IsomorphismOptions::Scale::similarity || group.frequency() == 0) {
        out.push_back(std::move(group));
        return out;
    }
    const double width = o.scale_mode == IsomorphismOptions::Scale::rigid ? std::log1p(o.scale_tolerance)
                                                                            : std::log(o.max_scale / o.min_scale) / 3.0;
    const std::size_t n = group.frequency();
    std::vector<long> bin(n);
    long lo = std::numeric_limits<long>::max();
    long hi = std::numeric_limits<long>::min();
    for (std::size_t i = 0; i < n; ++i) {
        bin[i] = static_cast<long>(std::floor(std::log(group.transforms[i].scale()) / width));
        lo = std::min(lo, bin[i]);
        hi = std::max(hi, bin[i]);
    }
    if (lo == hi) {
        out.push_back(std::move(group));
        return out;
    }
    std::vector<std::uint32_t> counts(static_cast<std::size_t>(hi - lo + 1), 0);
    for (long b : bin) ++counts[static_cast<std::size_t>(b - lo)];
    std::vector<int> cluster;
    const int size = static_cast<int>(counts.size());
    const int clusters = cluster_histogram(counts, cluster, [&](int c, auto&& f) {
        if (c > 0) f(c - 1);
        if (c + 1 < size) f(c + 1);
    });
    const std::size_t k = group.order();
    out.resize(static_cast<std::size_t>(clusters));
    for (auto& part : out) part.pattern = group.pattern;
    for (std::size_t i = 0; i < n; ++i) {
        Isogroup& part = out[static_cast<std::size_t>(cluster[static_cast<std::size_t>(bin[i] - lo)])];
        part.vertices.insert(part.vertices.end(), group.vertices.begin() + static_cast<std::ptrdiff_t>(i * k),
                             group.vertices.begin() + static_cast<std::ptrdiff_t>((i + 1) * k));
        part.transforms.push_back(group.transforms[i]);
    }
    return out;
}

} // namespace

void collect_candidates(const GeometricGraph& g, const Adjacency& adjacency, const Parent& parent,
                        const PolarGrid& grid, bool with_symbols, std::size_t begin, std::size_t end,
                        std::vector<Candidate>& out) {
    const Isogroup& group = *parent.group;
    const std::size_t k = group.order();
    const auto& pattern = group.pattern.positions;
    for (std::size_t i = begin; i < end; ++i) {
        const VertexId* occurrence = group.vertices.data() + i * k;
        const Similarity2 inverse = group.transforms[i].inverse();
        auto index_in = [&](VertexId x) -> int {
            for (std::size_t j = 0; j < k; ++j) {
                if (occurrence[j] == x) return static_cast<int>(j);
            }
            return -1;
        };
        for (std::size_t v = 0; v < k; ++v) {
            const auto u = static_cast<std::size_t>(occurrence[v]);
            for (auto a = adjacency.offsets[u]; a < adjacency.offsets[u + 1]; ++a) {
                const VertexId w = adjacency.neighbors[static_cast<std::size_t>(a)];
                if (index_in(w) >= 0) continue;
                std::uint64_t mask = 0;
                const auto wi = static_cast<std::size_t>(w);
                for (auto b = adjacency.offsets[wi]; b < adjacency.offsets[wi + 1]; ++b) {
                    const int j = index_in(adjacency.neighbors[static_cast<std::size_t>(b)]);
                    if (j >= 0) mask |= std::uint64_t{1} << j;
                }
                // Counted once, from the lowest pattern vertex it touches.
                if (std::countr_zero(mask) != static_cast<int>(v)) continue;
                const Vec2 x = inverse.apply(g.positions[wi]);
                // The smallest key over the symmetries of the pattern: masks first (cheap),
                // the polar cell (atan2, log) only for the symmetries that tie on the mask.
                std::uint64_t least = ~std::uint64_t{0};
                for (std::size_t s = 0; s < parent.symmetries.size(); ++s) {
                    least = std::min(least, s == 0 ? mask : permute_mask(mask, parent.symmetries[s].perm));
                }
                bool found = false;
                Candidate best{};
                // Least mask first; only when no symmetry with it has a cell (the new vertex
                // is outside the grid as seen from there) are the larger masks tried.
                for (int pass = 0; pass < 2 && !found; ++pass) {
                    for (std::size_t s = 0; s < parent.symmetries.size(); ++s) {
                        const Symmetry& sym = parent.symmetries[s];
                        const std::uint64_t m = s == 0 ? mask : permute_mask(mask, sym.perm);
                        if (pass == 0 && m != least) continue;
                        const Vec2 xs = s == 0 ? x : sym.map.apply(x);
                        const int anchor = std::countr_zero(m);
                        const int cell = grid.cell(xs - pattern[static_cast<std::size_t>(anchor)]);
                        if (cell < 0) continue;
                        if (!found || m < best.mask || (m == best.mask && cell < best.cell)) {
                            found = true;
                            best.mask = m;
                            best.cell = static_cast<std::uint16_t>(cell);
                            best.symmetry = static_cast<std::uint8_t>(s);
                            best.x = static_cast<float>(xs.x());
                            best.y = static_cast<float>(xs.y());
                        }
                    }
                }
                if (!found) continue;
                best.symbol = with_symbols ? symbol_of(g, w) : 0;
                best.occurrence = static_cast<std::uint32_t>(i);
                best.vertex = w;
                out.push_back(best);
            }
        }
    }
}

std::vector<Found> children_of(const GeometricGraph& g, const Parent& parent, std::vector<Candidate>& candidates,
                               const PolarGrid& grid, const DetectionOptions& o) {
    const Isogroup& pg = *parent.group;
    const std::size_t k = pg.order();
    // One (mask, symbol) topology per segment; segments are independent, so a parent with
    // many occurrences (the edges, at order 3) is split over the threads too.
    std::vector<std::pair<std::size_t, std::size_t>> segments;
    for (std::size_t a = 0; a < candidates.size();) {
        std::size_t b = a + 1;
        while (b < candidates.size() && candidates[b].mask == candidates[a].mask &&
               candidates[b].symbol == candidates[a].symbol) {
            ++b;
        }
        if (b - a >= o.min_count) segments.emplace_back(a, b);
        a = b;
    }
    std::vector<std::vector<Found>> per_segment(segments.size());
    tbb::parallel_for(std::size_t{0}, segments.size(), [&](std::size_t si) {
        const auto [a, b] = segments[si];
        std::vector<Found>& result = per_segment[si];
        std::vector<std::uint32_t> counts(static_cast<std::size_t>(grid.size()), 0);
        std::vector<int> cluster;
        for (std::size_t c = a; c < b; ++c) ++counts[candidates[c].cell];
        const int clusters = cluster_histogram(counts, cluster, [&](int cell, auto&& f) { grid.for_each_neighbour(cell, f); });
        std::vector<std::vector<std::uint32_t>> members(static_cast<std::size_t>(clusters));
        for (std::size_t c = a; c < b; ++c) {
            members[static_cast<std::size_t>(cluster[candidates[c].cell])].push_back(static_cast<std::uint32_t>(c));
        }
        for (auto& list : members) {
            if (list.size() < o.min_count) continue;
            // Candidates are sorted by cell first; occurrence order makes the child deterministic
            // and independent of how cells were grouped.
            std::sort(list.begin(), list.end(), [&](std::uint32_t x, std::uint32_t y) {
                const Candidate& cx = candidates[x];
                const Candidate& cy = candidates[y];
                return cx.occurrence < cy.occurrence || (cx.occurrence == cy.occurrence && cx.vertex < cy.vertex);
            });
            Found f;
            f.parent = parent.index;
            Isogroup& child = f.group;
            child.pattern.symbols = pg.pattern.symbols;
            child.pattern.symbols.push_back(candidates[list.front()].symbol);
            child.pattern.edges = pg.pattern.edges;
            const std::uint64_t mask = candidates[list.front()].mask;
            for (std::size_t j = 0; j < k; ++j) {
                if (mask >> j & 1) child.pattern.edges.push_back({static_cast<int>(j), static_cast<int>(k)});
            }
            std::sort(child.pattern.edges.begin(), child.pattern.edges.end());
            child.vertices.resize(list.size() * (k + 1));
            child.transforms.resize(list.size());
            Vec2 mean = Vec2::Zero();
            for (std::size_t i = 0; i < list.size(); ++i) {
                const Candidate& c = candidates[list[i]];
                const Symmetry& sym = parent.symmetries[c.symmetry];
                const VertexId* occurrence = pg.vertices.data() + static_cast<std::size_t>(c.occurrence) * k;
                VertexId* out = child.vertices.data() + i * (k + 1);
                for (std::size_t j = 0; j < k; ++j) out[sym.perm[j]] = occurrence[j];
                out[k] = c.vertex;
                child.transforms[i] = pg.transforms[c.occurrence] * sym.map.inverse();
                mean += Vec2(c.x, c.y);
            }
            child.pattern.positions = pg.pattern.positions;
            child.pattern.positions.push_back(mean / static_cast<double>(list.size()));
            deduplicate(child);
            if (child.frequency() < o.min_count) continue;
            for (Isogroup& part : split_by_scale(std::move(child), o)) {
                if (part.frequency() < o.min_count) continue;
                refine(part, g);
                Found piece;
                piece.parent = parent.index;
                piece.group = std::move(part);
                result.push_back(std::move(piece));
            }
        }
    });
    std::vector<Found> result;
    for (auto& list : per_segment) {
        for (Found& f : list) result.push_back(std::move(f));
    }
    return result;
}

std::vector<Symmetry> symmetries_of(const Pattern& p, const DetectionOptions& o) {
    IsomorphismOptions iso;
    iso.tolerance = o.merge_tolerance;
    iso.respect_symbols = o.respect_symbols;
    std::vector<Symmetry> result;
    for (auto& m : geometric_automorphisms(p, iso, 255)) result.push_back({std::move(m.mapping), m.transform});
    return result;
}

std::vector<Found> edge_groups(const GeometricGraph& g, const DetectionOptions& o) {
    std::unordered_map<std::uint64_t, std::size_t> index;
    std::vector<Found> groups;
    for (const auto& [a, b] : g.edges) {
        VertexId u = a;
        VertexId v = b;
        Symbol su = o.respect_symbols ? symbol_of(g, u) : 0;
        Symbol sv = o.respect_symbols ? symbol_of(g, v) : 0;
        if (su > sv || (su == sv && u > v)) {
            std::swap(u, v);
            std::swap(su, sv);
        }
        const Vec2 pu = g.positions[static_cast<std::size_t>(u)];
        const Vec2 pv = g.positions[static_cast<std::size_t>(v)];
        const Vec2 half = (pv - pu) / 2.0;
        if (!(half.norm() > 0.0)) continue; // coincident ends: no frame
        const std::uint64_t key = static_cast<std::uint64_t>(su) << 32 | sv;
        auto [it, inserted] = index.try_emplace(key, groups.size());
        if (inserted) {
            Found f;
            f.group.pattern.positions = {Vec2(-1.0, 0.0), Vec2(1.0, 0.0)};
            f.group.pattern.symbols = {su, sv};
            f.group.pattern.edges = {{0, 1}};
            groups.push_back(std::move(f));
        }
        Isogroup& group = groups[it->second].group;
        group.vertices.push_back(u);
        group.vertices.push_back(v);
        group.transforms.push_back({half.x(), half.y(), (pu + pv) / 2.0});
    }
    std::vector<Found> result;
    for (Found& f : groups) {
        for (Isogroup& part : split_by_scale(std::move(f.group), o)) {
            if (part.frequency() < o.min_count) continue;
            refine(part, g);
            Found piece;
            piece.group = std::move(part);
            result.push_back(std::move(piece));
        }
    }
    return result;
}

} // namespace ggg::detection_detail
