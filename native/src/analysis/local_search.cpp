// The heuristic of the non-overlapping selection: a greedy start, then local search
// (independent_set.hpp).
#include "independent_set.hpp"

#include <algorithm>

namespace ggg::non_overlapping_detail {

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

LocalSearch::LocalSearch(const LocalGraph& g, const std::vector<std::uint8_t>& initial)
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

void LocalSearch::descend() {
    while (!queue_.empty()) {
        const std::uint32_t x = queue_.back();
        queue_.pop_back();
        queued_[x] = 0;
        if (in_[x]) try_swap(x);
    }
}

void LocalSearch::iterate(std::uint64_t steps, std::uint32_t bound, Random& random) {
    const std::uint32_t s = g_.size();
    for (std::uint64_t step = 0; step < steps && count_ < bound; ++step) {
        const std::uint32_t before = count_;
        log_.clear();
        std::uint32_t v = random.below(s);
        for (int tries = 0; in_[v] && tries < 16; ++tries) v = random.below(s);
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

void LocalSearch::insert(std::uint32_t v) {
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

void LocalSearch::remove(std::uint32_t v) {
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

void LocalSearch::enqueue(std::uint32_t v) {
    if (!queued_[v]) {
        queued_[v] = 1;
        queue_.push_back(v);
    }
}

void LocalSearch::after_removal(std::uint32_t x) {
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

void LocalSearch::try_swap(std::uint32_t x) {
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

void LocalSearch::force(std::uint32_t v) {
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

} // namespace ggg::non_overlapping_detail
