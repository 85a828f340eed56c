// The search for the bijections of the geometric isomorphism test (isomorphism_matcher.hpp).
#include "isomorphism_matcher.hpp"

#include <algorithm>
#include <limits>
#include <numeric>
#include <tuple>

namespace ggg::isomorphism_detail {

Matcher::Matcher(const Prepared& a, const Prepared& b, double sigma, double tau, bool with_symbols)
    : a_(a), b_(b), sigma_(sigma), tau_(tau), with_symbols_(with_symbols), k_(static_cast<int>(a.size())),
      begin_(a.size() + 1), order_(a.size()), f_(a.size(), -1), inv_(a.size(), -1), next_(a.size(), 0),
      twin_before_(a.size(), -1), twin_after_(a.size(), -1) {
    find_twins();
}

void Matcher::search(Complex r0, int p, int q, double reach_p, Best& best) {
    if (!collect_candidates(r0, p, q, reach_p)) return;
    const bool first_only = p < 0;
    for (int i = 0; i < k_; ++i) order_[static_cast<std::size_t>(i)] = i;
    // Most constrained first: the forced and unambiguous vertices fix the rest early.
    std::stable_sort(order_.begin(), order_.end(), [&](int x, int y) { return count(x) < count(y); });
    std::fill(f_.begin(), f_.end(), -1);
    std::fill(inv_.begin(), inv_.end(), -1);
    std::fill(next_.begin(), next_.end(), 0);

    int depth = 0;
    while (depth >= 0) {
        if (depth == k_) {
            if (evaluate(r0, best) && first_only) return;
            --depth;
            unassign(order_[static_cast<std::size_t>(depth)]);
            continue;
        }
        const int i = order_[static_cast<std::size_t>(depth)];
        const std::size_t d = static_cast<std::size_t>(depth);
        bool placed = false;
        while (next_[d] < count(i)) {
            const int j = candidates_[static_cast<std::size_t>(begin_[static_cast<std::size_t>(i)] + next_[d]++)].vertex;
            if (inv_[static_cast<std::size_t>(j)] >= 0) continue;
            if (++steps_ > search_budget) return;
            if (!consistent(i, j)) continue;
            f_[static_cast<std::size_t>(i)] = j;
            inv_[static_cast<std::size_t>(j)] = i;
            placed = true;
            break;
        }
        if (placed) {
            ++depth;
            if (depth < k_) next_[static_cast<std::size_t>(depth)] = 0;
        } else {
            next_[d] = 0;
            --depth;
            if (depth >= 0) unassign(order_[static_cast<std::size_t>(depth)]);
        }
    }
}

bool Matcher::collect_candidates(Complex r0, int p, int q, double reach_p) {
    candidates_.clear();
    const double zp = p >= 0 ? a_.radius[static_cast<std::size_t>(p)] : 0.0;
    for (int i = 0; i < k_; ++i) {
        begin_[static_cast<std::size_t>(i)] = static_cast<int>(candidates_.size());
        if (i == p) {
            candidates_.push_back({0.0, q});
            continue;
        }
        const std::size_t first = candidates_.size();
        const Complex predicted = sigma_ * r0 * a_.z[static_cast<std::size_t>(i)];
        const double reach = p >= 0 ? tau_ + reach_p * a_.radius[static_cast<std::size_t>(i)] / zp
                                    : std::numeric_limits<double>::infinity();
        const double reach2 = reach * reach;
        for (int j = 0; j < k_; ++j) {
            if (!compatible(i, j)) continue;
            const double distance2 = std::norm(predicted - b_.z[static_cast<std::size_t>(j)]);
            if (distance2 <= reach2) candidates_.push_back({distance2, j});
        }
        if (candidates_.size() == first) return false; // vertex i has nowhere to go
        std::sort(candidates_.begin() + static_cast<std::ptrdiff_t>(first), candidates_.end(),
                  [](const Candidate& x, const Candidate& y) {
                      return x.distance2 < y.distance2 || (x.distance2 == y.distance2 && x.vertex < y.vertex);
                  });
    }
    begin_[static_cast<std::size_t>(k_)] = static_cast<int>(candidates_.size());
    return true;
}

void Matcher::find_twins() {
    std::vector<int> byplace(static_cast<std::size_t>(k_));
    std::iota(byplace.begin(), byplace.end(), 0);
    auto key = [&](int v) {
        const Complex z = a_.z[static_cast<std::size_t>(v)];
        return std::make_tuple(z.real(), z.imag(), v);
    };
    std::sort(byplace.begin(), byplace.end(), [&](int x, int y) { return key(x) < key(y); });
    for (std::size_t n = 1; n < byplace.size(); ++n) {
        const int v = byplace[n];
        // Walk back over the vertices at the same place (lower ids) for the nearest twin.
        for (std::size_t m = n; m-- > 0;) {
            const int u = byplace[m];
            if (a_.z[static_cast<std::size_t>(u)] != a_.z[static_cast<std::size_t>(v)]) break;
            if (a_.symbol(u) == a_.symbol(v) && same_neighbours(u, v)) {
                twin_before_[static_cast<std::size_t>(v)] = u;
                twin_after_[static_cast<std::size_t>(u)] = v;
                break;
            }
        }
    }
}

bool Matcher::same_neighbours(int u, int v) const {
    const auto nu = a_.adjacent(u);
    const auto nv = a_.adjacent(v);
    auto x = nu.begin();
    auto y = nv.begin();
    while (true) {
        while (x != nu.end() && *x == v) ++x;
        while (y != nv.end() && *y == u) ++y;
        if (x == nu.end() || y == nv.end()) return x == nu.end() && y == nv.end();
        if (*x++ != *y++) return false;
    }
}

bool Matcher::consistent(int i, int j) const {
    const int before = twin_before_[static_cast<std::size_t>(i)];
    if (before >= 0 && f_[static_cast<std::size_t>(before)] >= 0 && !(f_[static_cast<std::size_t>(before)] < j)) return false;
    const int after = twin_after_[static_cast<std::size_t>(i)];
    if (after >= 0 && f_[static_cast<std::size_t>(after)] >= 0 && !(j < f_[static_cast<std::size_t>(after)])) return false;
    const auto bj = b_.adjacent(j);
    int placed_a = 0;
    for (int n : a_.adjacent(i)) {
        const int image = f_[static_cast<std::size_t>(n)];
        if (image < 0) continue;
        ++placed_a;
        if (!std::binary_search(bj.begin(), bj.end(), image)) return false;
    }
    int placed_b = 0;
    for (int m : bj) placed_b += inv_[static_cast<std::size_t>(m)] >= 0 ? 1 : 0;
    return placed_a == placed_b;
}

bool Matcher::evaluate(Complex r0, Best& best) const {
    Complex w = 0.0;
    for (int i = 0; i < k_; ++i) {
        w += std::conj(a_.z[static_cast<std::size_t>(i)]) * b_.z[static_cast<std::size_t>(f_[static_cast<std::size_t>(i)])];
    }
    const double norm = std::sqrt(std::norm(w));
    const Complex r = norm > 0.0 ? w * (1.0 / norm) : r0;
    double squares = 0.0;
    double worst2 = 0.0;
    for (int i = 0; i < k_; ++i) {
        const double e2 = std::norm(sigma_ * r * a_.z[static_cast<std::size_t>(i)] -
                                    b_.z[static_cast<std::size_t>(f_[static_cast<std::size_t>(i)])]);
        worst2 = std::max(worst2, e2);
        squares += e2;
    }
    const double worst = std::sqrt(worst2);
    if (!(worst <= tau_)) return false;
    if (best.all) best.all->emplace_back(f_, r);
    const double rms = std::sqrt(squares / k_);
    if (best.found && !(rms < best.rms)) return true;
    best.found = true;
    best.mapping = f_;
    best.rotation = r;
    best.rms = rms;
    best.max = worst;
    return true;
}

void search_rotations(Matcher& matcher, const Prepared& pa, const Prepared& pb, double sigma, double tau, Matcher::Best& best) {
    int p = 0;
    for (int i = 1; i < static_cast<int>(pa.size()); ++i) {
        if (pa.radius[static_cast<std::size_t>(i)] > pa.radius[static_cast<std::size_t>(p)]) p = i;
    }
    const Complex zp = pa.z[static_cast<std::size_t>(p)];
    const double rp = pa.radius[static_cast<std::size_t>(p)];
    for (int q = 0; q < static_cast<int>(pb.size()) && !matcher.exhausted(); ++q) {
        const Complex zq = pb.z[static_cast<std::size_t>(q)];
        const double rq = pb.radius[static_cast<std::size_t>(q)];
        if (!matcher.compatible(p, q) || std::abs(rq - sigma * rp) > tau) continue;
        const Complex r0 = rq > 0.0 ? zq * std::conj(zp) * (1.0 / (rq * rp)) : Complex(1.0);
        // |r0 - R| * sigma * |z_p| <= 2 tau for a passing rotation R (see collect_candidates).
        matcher.search(r0, p, q, 2.0 * tau, best);
    }
}

} // namespace ggg::isomorphism_detail
