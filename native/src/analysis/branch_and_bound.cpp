// What proves a selection maximum: clique-cover upper bounds, and the exact branch and
// bound for the components small enough (independent_set.hpp).
#include "independent_set.hpp"

#include <algorithm>
#include <bit>

namespace ggg::non_overlapping_detail {

namespace {

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

} // namespace

std::uint32_t index_cover_bound(const LocalGraph& g) {
    std::vector<std::uint32_t> order(g.size());
    for (std::uint32_t v = 0; v < g.size(); ++v) order[v] = v;
    return clique_cover_bound(g, order);
}

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

BranchAndBound::BranchAndBound(const LocalGraph& g, std::uint64_t budget)
    : s_(g.size()), words_((g.size() + 63) / 64), budget_(budget), charge_(words_ * words_),
      adjacency_(static_cast<std::size_t>(g.size()) * words_, 0),
      pool_((static_cast<std::size_t>(g.size()) / 3 + 3) * words_, 0), scratch_(2 * words_, 0) {
    for (std::uint32_t v = 0; v < s_; ++v) {
        for (const std::uint32_t* p = g.begin(v); p != g.end(v); ++p) {
            adjacency_[v * words_ + *p / 64] |= std::uint64_t{1} << (*p % 64);
        }
    }
}

bool BranchAndBound::solve(std::vector<std::uint32_t>& best) {
    best_ = std::move(best);
    std::uint64_t* root = pool_.data();
    for (std::uint32_t v = 0; v < s_; ++v) root[v / 64] |= std::uint64_t{1} << (v % 64);
    search(root, 0);
    best = std::move(best_);
    return !aborted_;
}

std::uint32_t BranchAndBound::degree_in(std::uint32_t v, const std::uint64_t* set) const {
    const std::uint64_t* r = row(v);
    std::uint32_t d = 0;
    for (std::size_t w = 0; w < words_; ++w) d += static_cast<std::uint32_t>(std::popcount(r[w] & set[w]));
    return d;
}

std::size_t BranchAndBound::cover(const std::uint64_t* set, std::size_t enough) {
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

void BranchAndBound::search(std::uint64_t* set, std::size_t depth) {
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

} // namespace ggg::non_overlapping_detail
