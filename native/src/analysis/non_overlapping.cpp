#include "ggg/analysis/non_overlapping.hpp"

#include <algorithm>
#include <bit>
#include <limits>

#include "ggg/error.hpp"

namespace ggg {

namespace {

// The branch and bound keeps an s x s bit matrix of the component and one bit row per
// recursion level; beyond this size that is tens of megabytes and the search would not
// finish anyway (exact solvers stop being practical at a few thousand occurrences).
constexpr std::size_t kMaxExactComponent = 16384;
constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

const std::string kExactMethod = "exact branch and bound";
const std::string kHeuristicMethod = "greedy min-degree + local search";

// splitmix64: small, fast, and the same sequence on every platform (the standard
// distributions are not, which would break "same seed, same result").
struct Rng {
    std::uint64_t state;
    std::uint64_t next() {
        std::uint64_t z = (state += 0x9E3779B97F4A7C15ULL);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
        return z ^ (z >> 31);
    }
    // Uniform in [0, n) by multiply-shift (n < 2^32).
    std::uint32_t below(std::uint32_t n) {
        return static_cast<std::uint32_t>(((next() >> 32) * n) >> 32);
    }
};

// One connected component with local ids 0..s-1 (ascending in the global ids, so rows
// stay sorted and the input order, which often follows the geometry, is kept).
struct LocalGraph {
    std::vector<std::size_t> offsets{0};
    std::vector<std::uint32_t> nbrs;

    std::uint32_t size() const { return static_cast<std::uint32_t>(offsets.size() - 1); }
    const std::uint32_t* begin(std::uint32_t v) const { return nbrs.data() + offsets[v]; }
    const std::uint32_t* end(std::uint32_t v) const { return nbrs.data() + offsets[v + 1]; }
    std::uint32_t degree(std::uint32_t v) const { return static_cast<std::uint32_t>(offsets[v + 1] - offsets[v]); }
};

// Upper bound: a greedy clique cover. Vertices are taken in `order`; each joins the
// largest clique built so far whose every member it is adjacent to, or starts its own.
// An independent set holds at most one vertex per clique. O(m).
std::uint32_t clique_cover_bound(const LocalGraph& g, const std::vector<std::uint32_t>& order) {
    const std::uint32_t s = g.size();
    std::vector<std::uint32_t> clique_of(s, kNone);
    std::vector<std::uint32_t> clique_size;
    std::vector<std::uint32_t> seen_by;  // the vertex that last counted into this clique
    std::vector<std::uint32_t> adjacent; // how many of its members that vertex is adjacent to
    for (const std::uint32_t v : order) {
        for (const std::uint32_t* p = g.begin(v); p != g.end(v); ++p) {
            const std::uint32_t c = clique_of[*p];
            if (c == kNone) continue;
            if (seen_by[c] != v) {
                seen_by[c] = v;
                adjacent[c] = 0;
            }
            ++adjacent[c];
        }
        std::uint32_t join = kNone;
        for (const std::uint32_t* p = g.begin(v); p != g.end(v); ++p) {
            const std::uint32_t c = clique_of[*p];
            if (c != kNone && adjacent[c] == clique_size[c] && (join == kNone || clique_size[c] > clique_size[join])) {
                join = c;
            }
        }
        if (join == kNone) {
            join = static_cast<std::uint32_t>(clique_size.size());
            clique_size.push_back(0);
            seen_by.push_back(kNone);
            adjacent.push_back(0);
        }
        clique_of[v] = join;
        ++clique_size[join];
    }
    return static_cast<std::uint32_t>(clique_size.size());
}

// The cover in index order: on grid-like inputs listed row by row it finds the 2x2
// blocks, which is tight.
std::uint32_t index_cover_bound(const LocalGraph& g) {
    std::vector<std::uint32_t> order(g.size());
    for (std::uint32_t v = 0; v < g.size(); ++v) order[v] = v;
    return clique_cover_bound(g, order);
}

// The cover seeded by an independent set: its vertices first (one clique each), then the
// others by how many chosen neighbours they have, fewest first (they have the fewest
// cliques to choose from). Unlike the index cover it does not depend on the input
// order; neither is tight in general (on a shuffled grid of squares both are ~25 % high).
std::uint32_t guided_cover_bound(const LocalGraph& g, const std::vector<std::uint8_t>& chosen) {
    const std::uint32_t s = g.size();
    std::vector<std::uint32_t> tight(s, 0);
    std::uint32_t most = 0;
    for (std::uint32_t v = 0; v < s; ++v) {
        for (const std::uint32_t* p = g.begin(v); p != g.end(v); ++p) tight[v] += chosen[*p];
        most = std::max(most, tight[v]);
    }
    std::vector<std::uint32_t> order;
    order.reserve(s);
    for (std::uint32_t v = 0; v < s; ++v) {
        if (chosen[v]) order.push_back(v);
    }
    std::vector<std::size_t> first(most + 2, 0);
    for (std::uint32_t v = 0; v < s; ++v) {
        if (!chosen[v]) ++first[tight[v] + 1];
    }
    for (std::uint32_t t = 0; t <= most; ++t) first[t + 1] += first[t];
    const std::size_t base = order.size();
    order.resize(s);
    for (std::uint32_t v = 0; v < s; ++v) {
        if (!chosen[v]) order[base + first[tight[v]]++] = v;
    }
    return clique_cover_bound(g, order);
}

// Greedy minimum degree: repeatedly take a vertex of least degree in what is left, delete
// it and its neighbours. Degrees live in a bucket queue (doubly linked list per degree),
// so the pass is O(n + m). The result is maximal.
std::vector<std::uint8_t> greedy_min_degree(const LocalGraph& g) {
    const std::uint32_t s = g.size();
    std::vector<std::uint32_t> degree(s), next(s), prev(s);
    std::uint32_t max_degree = 0;
    for (std::uint32_t v = 0; v < s; ++v) {
        degree[v] = g.degree(v);
        max_degree = std::max(max_degree, degree[v]);
    }
    std::vector<std::uint32_t> head(max_degree + 1, kNone), tail(max_degree + 1, kNone);
    auto unlink = [&](std::uint32_t v) {
        if (prev[v] != kNone) next[prev[v]] = next[v];
        else head[degree[v]] = next[v];
        if (next[v] != kNone) prev[next[v]] = prev[v];
        else tail[degree[v]] = prev[v];
    };
    auto push = [&](std::uint32_t v) {
        next[v] = kNone;
        prev[v] = tail[degree[v]];
        if (prev[v] != kNone) next[prev[v]] = v;
        else head[degree[v]] = v;
        tail[degree[v]] = v;
    };
    // First in, first out within a degree: ties go to the lowest id, and a vertex whose
    // degree just dropped waits behind those already there.
    for (std::uint32_t v = 0; v < s; ++v) push(v);

    std::vector<std::uint8_t> alive(s, 1), chosen(s, 0);
    std::vector<std::uint32_t> removed;
    std::uint32_t left = s, low = 0;
    while (left > 0) {
        while (head[low] == kNone) ++low;
        const std::uint32_t v = head[low];
        unlink(v);
        alive[v] = 0;
        chosen[v] = 1;
        --left;
        removed.clear();
        for (const std::uint32_t* p = g.begin(v); p != g.end(v); ++p) {
            if (alive[*p]) {
                unlink(*p);
                alive[*p] = 0;
                --left;
                removed.push_back(*p);
            }
        }
        for (const std::uint32_t u : removed) {
            for (const std::uint32_t* p = g.begin(u); p != g.end(u); ++p) {
                const std::uint32_t w = *p;
                if (!alive[w]) continue;
                unlink(w);
                --degree[w];
                push(w);
                low = std::min(low, degree[w]);
            }
        }
    }
    return chosen;
}

// Local search on an independent set, after Andrade, Resende and Werneck (2012):
// (1,2)-swaps remove one chosen vertex x and insert two non-adjacent vertices whose only
// chosen neighbour is x; free vertices are inserted as they appear. Iterated: a
// perturbation forces a random unchosen vertex in, the swaps repair around it, and the
// step is undone when it made the set smaller (equal is kept, to walk plateaus).
class LocalSearch {
public:
    LocalSearch(const LocalGraph& g, const std::vector<std::uint8_t>& initial)
        : g_(g), in_(g.size(), 0), tight_(g.size(), 0), xor_(g.size(), 0), one_tight_(g.size(), 0), queued_(g.size(), 0) {
        for (std::uint32_t v = 0; v < g.size(); ++v) {
            if (initial[v]) insert(v);
        }
        for (std::uint32_t v = 0; v < g.size(); ++v) {
            if (!in_[v] && tight_[v] == 0) insert(v);
        }
        for (std::uint32_t v = 0; v < g.size(); ++v) {
            if (in_[v]) enqueue(v);
        }
        log_.clear();
    }

    std::uint32_t count() const { return count_; }
    const std::vector<std::uint8_t>& solution() const { return in_; }

    // (1,2)-swaps until none applies: each strictly grows the set, so this terminates.
    void descend() {
        while (!queue_.empty()) {
            const std::uint32_t x = queue_.back();
            queue_.pop_back();
            queued_[x] = 0;
            if (in_[x]) try_swap(x);
        }
    }

    // Perturb-and-repair steps until `steps` are done or the set reaches `bound`.
    void iterate(std::uint64_t steps, std::uint32_t bound, Rng& rng) {
        const std::uint32_t s = g_.size();
        for (std::uint64_t step = 0; step < steps && count_ < bound; ++step) {
            const std::uint32_t before = count_;
            log_.clear();
            std::uint32_t v = rng.below(s);
            for (int tries = 0; in_[v] && tries < 16; ++tries) v = rng.below(s);
            while (in_[v]) v = v + 1 == s ? 0 : v + 1; // a connected component of >= 2 has an unchosen vertex
            force(v);
            descend();
            if (count_ < before) {
                // Undo in reverse; every logged entry was one flip.
                logging_ = false;
                for (std::size_t i = log_.size(); i-- > 0;) {
                    const std::uint32_t u = log_[i];
                    if (in_[u]) remove(u);
                    else insert(u);
                }
                logging_ = true;
            }
        }
        log_.clear();
    }

private:
    void insert(std::uint32_t v) {
        in_[v] = 1;
        ++count_;
        for (const std::uint32_t* p = g_.begin(v); p != g_.end(v); ++p) {
            const std::uint32_t z = *p;
            if (tight_[z] == 0) ++one_tight_[v];
            else if (tight_[z] == 1) --one_tight_[xor_[z]];
            ++tight_[z];
            xor_[z] ^= v;
        }
        if (logging_) log_.push_back(v);
    }
    void remove(std::uint32_t v) {
        in_[v] = 0;
        --count_;
        for (const std::uint32_t* p = g_.begin(v); p != g_.end(v); ++p) {
            const std::uint32_t z = *p;
            --tight_[z];
            xor_[z] ^= v;
            if (tight_[z] == 0) --one_tight_[v];
            else if (tight_[z] == 1) ++one_tight_[xor_[z]];
        }
        if (logging_) log_.push_back(v);
    }
    void enqueue(std::uint32_t v) {
        if (!queued_[v]) {
            queued_[v] = 1;
            queue_.push_back(v);
        }
    }
    // After x left the set, its unchosen neighbours with one chosen neighbour y are new
    // swap candidates of y; free ones go straight in.
    void after_removal(std::uint32_t x) {
        for (const std::uint32_t* p = g_.begin(x); p != g_.end(x); ++p) {
            const std::uint32_t z = *p;
            if (in_[z]) continue;
            if (tight_[z] == 0) {
                insert(z);
                enqueue(z);
            } else if (tight_[z] == 1) {
                enqueue(xor_[z]);
            }
        }
    }
    void try_swap(std::uint32_t x) {
        if (one_tight_[x] < 2) return;
        candidates_.clear();
        for (const std::uint32_t* p = g_.begin(x); p != g_.end(x); ++p) {
            if (!in_[*p] && tight_[*p] == 1) candidates_.push_back(*p);
        }
        for (std::size_t a = 0; a + 1 < candidates_.size(); ++a) {
            const std::uint32_t u = candidates_[a];
            for (std::size_t b = a + 1; b < candidates_.size(); ++b) {
                const std::uint32_t w = candidates_[b];
                if (std::binary_search(g_.begin(u), g_.end(u), w)) continue; // rows are sorted
                remove(x);
                insert(u);
                insert(w);
                enqueue(u);
                enqueue(w);
                after_removal(x);
                return;
            }
        }
    }
    void force(std::uint32_t v) {
        removed_.clear();
        for (const std::uint32_t* p = g_.begin(v); p != g_.end(v); ++p) {
            if (in_[*p]) {
                remove(*p);
                removed_.push_back(*p);
            }
        }
        insert(v);
        enqueue(v);
        for (const std::uint32_t u : removed_) after_removal(u);
    }

    const LocalGraph& g_;
    std::vector<std::uint8_t> in_;
    std::vector<std::uint32_t> tight_; // chosen neighbours of each vertex
    // XOR of the ids of the chosen neighbours: when tight_ is 1 it is that neighbour.
    std::vector<std::uint32_t> xor_;
    // Of a chosen vertex: how many neighbours have it as their only chosen neighbour (a
    // swap needs two), so most queued vertices are dismissed in O(1).
    std::vector<std::uint32_t> one_tight_;
    std::vector<std::uint8_t> queued_;
    std::vector<std::uint32_t> queue_;
    std::vector<std::uint32_t> candidates_;
    std::vector<std::uint32_t> removed_;
    std::vector<std::uint32_t> log_;
    bool logging_ = true;
    std::uint32_t count_ = 0;
};

// Exact maximum independent set of one component by branch and bound on bit rows.
// A node takes every vertex of degree <= 1 (always safe), then bounds by a greedy clique
// cover of what is left, then branches on a vertex of maximum degree: take it (drop its
// neighbours) or drop it. Taking removes at least three vertices, so the depth is at
// most s/3 + 1.
class BranchAndBound {
public:
    // A node costs about s * s / 64 word operations, so a node of a component above 64
    // occurrences is charged (s / 64)^2 of the budget: the budget bounds time, not nodes.
    BranchAndBound(const LocalGraph& g, std::uint64_t budget)
        : s_(g.size()), words_((g.size() + 63) / 64), budget_(budget), charge_(words_ * words_),
          adjacency_(static_cast<std::size_t>(g.size()) * words_, 0),
          pool_((static_cast<std::size_t>(g.size()) / 3 + 3) * words_, 0), scratch_(2 * words_, 0) {
        for (std::uint32_t v = 0; v < s_; ++v) {
            for (const std::uint32_t* p = g.begin(v); p != g.end(v); ++p) {
                adjacency_[v * words_ + *p / 64] |= std::uint64_t{1} << (*p % 64);
            }
        }
    }

    // Returns false when the node budget ran out; `best` then holds the best set found
    // (never worse than the one passed in).
    bool solve(std::vector<std::uint32_t>& best) {
        best_ = std::move(best);
        std::uint64_t* root = pool_.data();
        for (std::uint32_t v = 0; v < s_; ++v) root[v / 64] |= std::uint64_t{1} << (v % 64);
        search(root, 0);
        best = std::move(best_);
        return !aborted_;
    }

private:
    const std::uint64_t* row(std::uint32_t v) const { return adjacency_.data() + static_cast<std::size_t>(v) * words_; }

    std::uint32_t degree_in(std::uint32_t v, const std::uint64_t* set) const {
        const std::uint64_t* r = row(v);
        std::uint32_t d = 0;
        for (std::size_t w = 0; w < words_; ++w) d += static_cast<std::uint32_t>(std::popcount(r[w] & set[w]));
        return d;
    }

    // Cliques in a greedy cover of `set`, counted only up to `enough` (past that the node
    // cannot be pruned, so the exact count does not matter).
    std::size_t cover(const std::uint64_t* set, std::size_t enough) {
        std::uint64_t* rest = scratch_.data();
        std::uint64_t* clique = scratch_.data() + words_;
        std::copy(set, set + words_, rest);
        std::size_t count = 0;
        for (std::size_t w = 0; w < words_ && count < enough;) {
            if (rest[w] == 0) {
                ++w;
                continue;
            }
            const auto v = static_cast<std::uint32_t>(w * 64 + static_cast<std::size_t>(std::countr_zero(rest[w])));
            rest[w] &= rest[w] - 1;
            ++count;
            const std::uint64_t* r = row(v);
            bool any = false;
            for (std::size_t i = w; i < words_; ++i) {
                clique[i] = rest[i] & r[i];
                any = any || clique[i] != 0;
            }
            for (std::size_t i = w; any && i < words_;) {
                if (clique[i] == 0) {
                    ++i;
                    continue;
                }
                const auto u = static_cast<std::uint32_t>(i * 64 + static_cast<std::size_t>(std::countr_zero(clique[i])));
                rest[u / 64] &= ~(std::uint64_t{1} << (u % 64));
                const std::uint64_t* ru = row(u);
                for (std::size_t j = i; j < words_; ++j) clique[j] &= ru[j];
            }
        }
        return count;
    }

    void search(std::uint64_t* set, std::size_t depth) {
        const std::size_t base = current_.size();
        while (true) {
            if (spent_ >= budget_) {
                aborted_ = true;
                break;
            }
            spent_ += charge_;
            // Reductions, and the vertex to branch on.
            bool empty = true, reduced = false;
            std::uint32_t branch = kNone, branch_degree = 0;
            for (std::size_t w = 0; w < words_; ++w) {
                for (std::uint64_t bits = set[w]; bits != 0; bits &= bits - 1) {
                    const auto v = static_cast<std::uint32_t>(w * 64 + static_cast<std::size_t>(std::countr_zero(bits)));
                    if (!(set[w] >> (v % 64) & 1)) continue; // dropped by a reduction above
                    empty = false;
                    const std::uint32_t d = degree_in(v, set);
                    if (d <= 1) {
                        current_.push_back(v);
                        const std::uint64_t* r = row(v);
                        for (std::size_t i = 0; i < words_; ++i) set[i] &= ~r[i];
                        set[w] &= ~(std::uint64_t{1} << (v % 64));
                        reduced = true;
                    } else if (d > branch_degree) {
                        branch = v;
                        branch_degree = d;
                    }
                }
            }
            if (empty) {
                if (current_.size() > best_.size()) best_ = current_;
                break;
            }
            if (reduced) continue; // degrees changed; look again
            if (current_.size() < best_.size() &&
                current_.size() + cover(set, best_.size() - current_.size() + 1) <= best_.size()) {
                break;
            }

            std::uint64_t* taken = set + words_;
            const std::uint64_t* r = row(branch);
            for (std::size_t i = 0; i < words_; ++i) taken[i] = set[i] & ~r[i];
            taken[branch / 64] &= ~(std::uint64_t{1} << (branch % 64));
            current_.push_back(branch);
            search(taken, depth + 1);
            current_.pop_back();
            if (aborted_) break;
            set[branch / 64] &= ~(std::uint64_t{1} << (branch % 64));
        }
        current_.resize(base);
    }

    std::uint32_t s_;
    std::size_t words_;
    std::uint64_t budget_;
    std::uint64_t charge_;
    std::uint64_t spent_ = 0;
    bool aborted_ = false;
    std::vector<std::uint64_t> adjacency_;
    std::vector<std::uint64_t> pool_; // one bit row per recursion level, consecutive
    std::vector<std::uint64_t> scratch_;
    std::vector<std::uint32_t> current_;
    std::vector<std::uint32_t> best_;
};

// Seeded per component (by its first occurrence), so that a component's result does not
// depend on the others.
Rng component_rng(std::uint64_t seed, std::uint32_t root) {
    return Rng{seed ^ (0x9E3779B97F4A7C15ULL * (static_cast<std::uint64_t>(root) + 1))};
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

void check_occurrences(std::span<const VertexId> vertices, std::size_t k) {
    if (k == 0) throw UsageError("non-overlapping selection: occurrence size k must be positive");
    if (vertices.size() % k != 0) {
        throw UsageError("non-overlapping selection: " + std::to_string(vertices.size()) +
                         " vertex ids are not a whole number of occurrences of " + std::to_string(k));
    }
    if (vertices.size() / k >= kNone) {
        throw UsageError("non-overlapping selection: at most 2^32 - 1 occurrences are supported");
    }
}

void check_graph(const OverlapGraph& graph) {
    if (graph.offsets.empty() || graph.offsets.front() != 0 ||
        graph.offsets.back() != static_cast<std::int64_t>(graph.neighbors.size())) {
        throw UsageError("overlap graph: offsets do not span the neighbour array");
    }
    const std::size_t n = graph.offsets.size() - 1;
    if (n >= kNone) throw UsageError("overlap graph: at most 2^32 - 1 occurrences are supported");
    for (std::size_t i = 0; i < n; ++i) {
        if (graph.offsets[i + 1] < graph.offsets[i]) throw UsageError("overlap graph: offsets decrease");
    }
    for (std::uint32_t i = 0; i < n; ++i) {
        const auto row = graph.neighbours_of(i);
        for (std::size_t p = 0; p < row.size(); ++p) {
            const std::uint32_t j = row[p];
            if (j >= n || j == i || (p > 0 && row[p - 1] >= j)) {
                throw UsageError("overlap graph: row " + std::to_string(i) +
                                 " is not sorted, repeats, or holds itself or an id out of range");
            }
            const auto back = graph.neighbours_of(j);
            if (!std::binary_search(back.begin(), back.end(), i)) {
                throw UsageError("overlap graph: not symmetric at " + std::to_string(i) + "-" + std::to_string(j));
            }
        }
    }
}

} // namespace

OverlapGraph build_overlap_graph(std::span<const VertexId> vertices, std::size_t k) {
    check_occurrences(vertices, k);
    OverlapGraph graph;
    const std::size_t n = vertices.size() / k;
    if (n == 0) return graph;

    VertexId max_id = 0;
    for (const VertexId v : vertices) {
        if (v < 0) throw UsageError("non-overlapping selection: negative vertex id " + std::to_string(v));
        max_id = std::max(max_id, v);
    }
    // Bucket index per vertex id: the id itself when ids are reasonably dense, else its
    // rank among the distinct ids (sparse ids would make a direct table huge).
    std::vector<std::uint32_t> key(vertices.size());
    std::size_t keys = 0;
    if (static_cast<std::size_t>(max_id) < 4 * vertices.size() + 256) {
        for (std::size_t i = 0; i < vertices.size(); ++i) key[i] = static_cast<std::uint32_t>(vertices[i]);
        keys = static_cast<std::size_t>(max_id) + 1;
    } else {
        std::vector<VertexId> distinct(vertices.begin(), vertices.end());
        std::sort(distinct.begin(), distinct.end());
        distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
        for (std::size_t i = 0; i < vertices.size(); ++i) {
            key[i] = static_cast<std::uint32_t>(std::lower_bound(distinct.begin(), distinct.end(), vertices[i]) -
                                                distinct.begin());
        }
        keys = distinct.size();
    }

    // Occurrences through each vertex (counting sort; ascending within a bucket).
    std::vector<std::size_t> start(keys + 1, 0);
    for (const std::uint32_t key_v : key) ++start[key_v + 1];
    for (std::size_t v = 0; v < keys; ++v) start[v + 1] += start[v];
    std::vector<std::uint32_t> through(vertices.size());
    {
        std::vector<std::size_t> fill(start.begin(), start.end() - 1);
        for (std::uint32_t i = 0; i < n; ++i) {
            for (std::size_t p = static_cast<std::size_t>(i) * k; p < static_cast<std::size_t>(i + 1) * k; ++p) {
                through[fill[key[p]]++] = i;
            }
        }
    }

    // Row i = union of the buckets of its vertices, deduplicated by a mark per
    // occurrence. Occurrences come in any order, so their buckets are scattered in
    // memory: ask for the bucket bounds a few occurrences ahead and for the buckets a
    // little nearer.
    constexpr std::size_t kAheadBounds = 8, kAheadBuckets = 4;
    std::vector<std::int64_t> offsets(n + 1, 0);
    std::vector<std::uint32_t> unsorted;
    {
        std::vector<std::uint32_t> mark(n, kNone);
        for (std::uint32_t i = 0; i < n; ++i) {
            if (i + kAheadBounds < n) {
                for (std::size_t p = (i + kAheadBounds) * k; p < (i + kAheadBounds + 1) * k; ++p) __builtin_prefetch(&start[key[p]]);
            }
            if (i + kAheadBuckets < n) {
                for (std::size_t p = (i + kAheadBuckets) * k; p < (i + kAheadBuckets + 1) * k; ++p) __builtin_prefetch(&through[start[key[p]]]);
            }
            for (std::size_t p = static_cast<std::size_t>(i) * k; p < static_cast<std::size_t>(i + 1) * k; ++p) {
                for (std::size_t q = start[key[p]]; q < start[key[p] + 1]; ++q) {
                    const std::uint32_t j = through[q];
                    if (j != i && mark[j] != i) {
                        mark[j] = i;
                        unsorted.push_back(j);
                    }
                }
            }
            offsets[i + 1] = static_cast<std::int64_t>(unsorted.size());
        }
    }
    // Sorted rows without sorting: the relation is symmetric, so its transpose is the
    // same graph, and filling the transpose row by row in order of i sorts every row.
    graph.neighbors.resize(unsorted.size());
    {
        std::vector<std::int64_t> fill(offsets.begin(), offsets.end() - 1);
        for (std::uint32_t i = 0; i < n; ++i) {
            for (std::int64_t p = offsets[i]; p < offsets[i + 1]; ++p) {
                graph.neighbors[static_cast<std::size_t>(fill[unsorted[static_cast<std::size_t>(p)]]++)] = i;
            }
        }
    }
    graph.offsets = std::move(offsets);
    return graph;
}

namespace {

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
            Rng rng = component_rng(options.seed, root);
            search.iterate(static_cast<std::uint64_t>(options.local_search_rounds) * s, bound, rng);
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
                Rng rng = component_rng(options.seed, root);
                polish.iterate(static_cast<std::uint64_t>(options.local_search_rounds) * s, bound, rng);
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
    check_graph(graph);
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
