#pragma once
// The search of the geometric isomorphism test (analysis/geometric_isomorphism.hpp), private
// to it: patterns prepared for matching, and the depth-first search for the bijections
// under each rotation hypothesis (isomorphism_matcher.cpp; the method is described at the
// top of geometric_isomorphism.cpp).
#include <cmath>
#include <complex>
#include <cstddef>
#include <span>
#include <utility>
#include <vector>

#include "ggg/analysis/geometric_isomorphism.hpp"
#include "ggg/analysis/pattern.hpp"

namespace ggg::isomorphism_detail {

using Complex = std::complex<double>;

inline Complex to_complex(const Vec2& v) { return {v.x(), v.y()}; }

// A pattern ready for matching: normalised coordinates and its adjacency as sorted lists.
struct Prepared {
    Spread spread;
    std::vector<Complex> z; // (position - centroid) / rms; all 0 when degenerate
    std::vector<double> radius; // |z|
    std::vector<int> offsets;
    std::vector<int> neighbors;
    const std::vector<Symbol>* symbols = nullptr;

    explicit Prepared(const Pattern& p) : spread(spread_of(p.positions)), symbols(&p.symbols) {
        const std::size_t k = p.size();
        z.resize(k);
        radius.resize(k);
        if (!spread.degenerate) {
            for (std::size_t i = 0; i < k; ++i) {
                z[i] = to_complex((p.positions[i] - spread.centroid) / spread.rms);
                radius[i] = std::sqrt(std::norm(z[i]));
            }
        }
        offsets.assign(k + 1, 0);
        for (const auto& [u, v] : p.edges) {
            ++offsets[static_cast<std::size_t>(u) + 1];
            ++offsets[static_cast<std::size_t>(v) + 1];
        }
        for (std::size_t i = 0; i < k; ++i) offsets[i + 1] += offsets[i];
        neighbors.resize(static_cast<std::size_t>(offsets[k]));
        std::vector<int> fill(offsets.begin(), offsets.end() - 1);
        // Edges are sorted by (a, b), so each list comes out ascending: the lower
        // neighbours (edges (u, v), u < v) arrive before the higher ones (edges (v, w)).
        for (const auto& [u, v] : p.edges) {
            neighbors[static_cast<std::size_t>(fill[static_cast<std::size_t>(u)]++)] = v;
            neighbors[static_cast<std::size_t>(fill[static_cast<std::size_t>(v)]++)] = u;
        }
    }

    std::size_t size() const { return z.size(); }
    int degree(int v) const { return offsets[static_cast<std::size_t>(v) + 1] - offsets[static_cast<std::size_t>(v)]; }
    std::span<const int> adjacent(int v) const {
        return {neighbors.data() + offsets[static_cast<std::size_t>(v)], static_cast<std::size_t>(degree(v))};
    }
    Symbol symbol(int v) const { return (*symbols)[static_cast<std::size_t>(v)]; }
};

// Far more consistency checks than any street pattern needs (a few hundred at most). Only a
// crowd of nearly coincident vertices of equal degree, where geometry no longer narrows the
// search, comes near it; a handful of exactly coincident twins does not (see find_twins).
inline constexpr std::size_t search_budget = 1'000'000;

struct Candidate {
    double distance2; // squared distance from the predicted place
    int vertex;
};

class Matcher {
public:
    Matcher(const Prepared& a, const Prepared& b, double sigma, double tau, bool with_symbols);

    bool compatible(int i, int j) const {
        return a_.degree(i) == b_.degree(j) && (!with_symbols_ || a_.symbol(i) == b_.symbol(j));
    }

    bool exhausted() const { return steps_ > search_budget; }

    // The best bijection found so far over all hypotheses (residuals in normalised units of b).
    struct Best {
        bool found = false;
        std::vector<int> mapping;
        Complex rotation = 1.0;
        double rms = 0.0;
        double max = 0.0;
        // When set, every passing bijection is also appended here (automorphism listing).
        std::vector<std::pair<std::vector<int>, Complex>>* all = nullptr;
    };

    // Every passing bijection under the rotation hypothesis `r0` (unit complex) with p -> q
    // forced; p < 0: no forced pair, every compatible vertex is a candidate (the degenerate
    // case, where any passing bijection is as good as another and the first one ends it).
    void search(Complex r0, int p, int q, double reach_p, Best& best);

private:
    int count(int i) const {
        return begin_[static_cast<std::size_t>(i) + 1] - begin_[static_cast<std::size_t>(i)];
    }

    void unassign(int i) {
        inv_[static_cast<std::size_t>(f_[static_cast<std::size_t>(i)])] = -1;
        f_[static_cast<std::size_t>(i)] = -1;
    }

    // Partners of every vertex of a near its predicted place, nearest first. The radius:
    // if a bijection passes with rotation R, the hypothesis rotation r0 (which puts p on
    // the ray of q) places p within 2 tau of where R places it; a vertex at radius |z_i|
    // moves |z_i| / |z_p| as much, then its own residual tau adds.
    bool collect_candidates(Complex r0, int p, int q, double reach_p);

    // Twins of a: vertices at exactly the same place with the same symbol and the same
    // neighbours apart from each other. Swapping their partners changes neither adjacency nor
    // any residual, so only bijections that keep twins in increasing order are searched;
    // without this a pile of k twins would be searched k! times over.
    void find_twins();

    bool same_neighbours(int u, int v) const;

    // i -> j keeps adjacency with every vertex placed so far: each placed neighbour of i maps
    // to a neighbour of j, and j has no more placed neighbours than that.
    bool consistent(int i, int j) const;

    // Least-squares rotation of the complete bijection; keeps it when every residual passes
    // and it beats the best so far (ties keep the earlier one: deterministic).
    bool evaluate(Complex r0, Best& best) const;

    const Prepared& a_;
    const Prepared& b_;
    double sigma_;
    double tau_;
    bool with_symbols_;
    int k_;
    std::size_t steps_ = 0;
    std::vector<Candidate> candidates_;
    std::vector<int> begin_;
    std::vector<int> order_;
    std::vector<int> f_;
    std::vector<int> inv_;
    std::vector<int> next_;
    std::vector<int> twin_before_; // the previous twin of a vertex of a (lower id), or -1
    std::vector<int> twin_after_;  // the next twin, or -1
};

// Every rotation hypothesis of a non-degenerate pair: the vertex p of a farthest from its
// centroid pins the rotation best (|z_p| >= 1); each compatible q of b at the right radius
// gives one, the unit complex turning the direction of z_p into that of z_q.
void search_rotations(Matcher& matcher, const Prepared& pa, const Prepared& pb, double sigma, double tau, Matcher::Best& best);

} // namespace ggg::isomorphism_detail
