// Geometric isomorphism of patterns (paper 3.1).
//
// The search: with the centroids matched and the scale fixed by the mode, only
// the rotation and the bijection are unknown. One vertex p of a farthest from its centroid
// and each plausible partner q in b give a rotation hypothesis; every other vertex then has
// few partners near its predicted place, and a depth-first search over those (nearest first,
// pruned by degree, symbol and adjacency with the vertices already placed) finds the
// bijections whose least-squares rotation passes the tolerance. The candidate radius is
// wide enough that no passing bijection is missed (see reach below).
#include "ggg/analysis/geometric_isomorphism.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <memory>
#include <numeric>
#include <string>
#include <tuple>
#include <utility>

#include "ggg/error.hpp"

namespace ggg {

namespace {

using Complex = std::complex<double>;

Complex to_complex(const Vec2& v) { return {v.x(), v.y()}; }

void require_valid(const Pattern& p, const char* name) {
    const std::string problem = check_pattern(p);
    if (!problem.empty()) throw UsageError(std::string("pattern ") + name + ": " + problem);
}

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

// The invariants compared before any geometry: sorted (degree, symbol) per vertex and
// sorted (degree, degree) per edge.
struct Signature {
    std::vector<std::uint64_t> vertices;
    std::vector<std::uint64_t> edges;
    bool operator==(const Signature&) const = default;
};

Signature signature_of(const Prepared& p, const Pattern& pattern, bool with_symbols) {
    Signature s;
    s.vertices.reserve(p.size());
    for (std::size_t v = 0; v < p.size(); ++v) {
        const auto d = static_cast<std::uint64_t>(p.degree(static_cast<int>(v)));
        s.vertices.push_back(d << 32 | (with_symbols ? p.symbol(static_cast<int>(v)) : 0u));
    }
    s.edges.reserve(pattern.edges.size());
    for (const auto& [u, v] : pattern.edges) {
        const auto du = static_cast<std::uint64_t>(p.degree(u));
        const auto dv = static_cast<std::uint64_t>(p.degree(v));
        s.edges.push_back(std::min(du, dv) << 32 | std::max(du, dv));
    }
    std::sort(s.vertices.begin(), s.vertices.end());
    std::sort(s.edges.begin(), s.edges.end());
    return s;
}

std::uint64_t mix(std::uint64_t x) { // splitmix64 finaliser
    x += 0x9e3779b97f4a7c15ULL;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
    return x ^ (x >> 31);
}

std::uint64_t combine(std::uint64_t h, std::uint64_t x) { return mix(h ^ mix(x)); }

// Far more consistency checks than any street pattern needs (a few hundred at most). Only a
// crowd of nearly coincident vertices of equal degree, where geometry no longer narrows the
// search, comes near it; a handful of exactly coincident twins does not (see find_twins).
constexpr std::size_t search_budget = 1'000'000;

struct Candidate {
    double distance2; // squared distance from the predicted place
    int vertex;
};

class Matcher {
public:
    Matcher(const Prepared& a, const Prepared& b, double sigma, double tau, bool with_symbols)
        : a_(a), b_(b), sigma_(sigma), tau_(tau), with_symbols_(with_symbols), k_(static_cast<int>(a.size())),
          begin_(a.size() + 1), order_(a.size()), f_(a.size(), -1), inv_(a.size(), -1), next_(a.size(), 0),
          twin_before_(a.size(), -1), twin_after_(a.size(), -1) {
        find_twins();
    }

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
    void search(Complex r0, int p, int q, double reach_p, Best& best) {
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
    bool collect_candidates(Complex r0, int p, int q, double reach_p) {
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

    // Twins of a: vertices at exactly the same place with the same symbol and the same
    // neighbours apart from each other. Swapping their partners changes neither adjacency nor
    // any residual, so only bijections that keep twins in increasing order are searched;
    // without this a pile of k twins would be searched k! times over.
    void find_twins() {
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

    bool same_neighbours(int u, int v) const {
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

    // i -> j keeps adjacency with every vertex placed so far: each placed neighbour of i maps
    // to a neighbour of j, and j has no more placed neighbours than that.
    bool consistent(int i, int j) const {
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

    // Least-squares rotation of the complete bijection; keeps it when every residual passes
    // and it beats the best so far (ties keep the earlier one: deterministic).
    bool evaluate(Complex r0, Best& best) const {
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

void check_options(const IsomorphismOptions& o) {
    if (!std::isfinite(o.tolerance) || o.tolerance < 0.0) {
        throw UsageError("isomorphism tolerance must be a finite number >= 0, got " + std::to_string(o.tolerance));
    }
    switch (o.mode) {
    case IsomorphismOptions::Scale::similarity:
    case IsomorphismOptions::Scale::rigid:
        return;
    case IsomorphismOptions::Scale::range:
        if (!(std::isfinite(o.min_scale) && std::isfinite(o.max_scale) && o.min_scale > 0.0 &&
              o.min_scale <= o.max_scale)) {
            throw UsageError("isomorphism scale range must satisfy 0 < min_scale <= max_scale, got [" +
                             std::to_string(o.min_scale) + ", " + std::to_string(o.max_scale) + "]");
        }
        return;
    }
    throw UsageError("unknown isomorphism scale mode");
}

} // namespace

IsomorphismOptions::Scale scale_mode_from_name(std::string_view name) {
    if (name == "similarity") return IsomorphismOptions::Scale::similarity;
    if (name == "rigid") return IsomorphismOptions::Scale::rigid;
    if (name == "range") return IsomorphismOptions::Scale::range;
    throw UsageError("scale mode must be similarity, rigid or range, got '" + std::string(name) + "'");
}

namespace {

// The test on prepared patterns whose signatures (with or without symbols, as the options
// say) are equal, once the cheap checks have passed.
std::optional<IsomorphismMatch> match_prepared(const Prepared& pa, const Pattern& a, const Prepared& pb, const Pattern& b,
                                               const IsomorphismOptions& options) {
    using Scale = IsomorphismOptions::Scale;

    // sigma: size of a over size of b in the frame where residuals are measured (b's
    // normalised coordinates); tau: the tolerance in that frame; to_reported: from that
    // frame to the unit the caller's tolerance is in.
    const bool degenerate = pa.spread.degenerate;
    const double size_a = pa.spread.rms * a.metres_per_unit;
    const double size_b = pb.spread.rms * b.metres_per_unit;
    double sigma = 1.0;
    double to_reported = 1.0;
    if (!degenerate && options.mode == Scale::range) {
        const double ratio = size_b / size_a;
        const double slack = 1e-12;
        if (!(ratio >= options.min_scale * (1.0 - slack) && ratio <= options.max_scale * (1.0 + slack))) {
            return std::nullopt;
        }
    }
    if (!degenerate && options.mode == Scale::rigid) {
        sigma = size_a / size_b;
        to_reported = size_b / (0.5 * (size_a + size_b));
    }
    // A hair of slack so that exact copies pass at tolerance 0 despite rounding.
    const double tau = options.tolerance / to_reported * (1.0 + 1e-9) + 1e-12;
    // Whatever the rotation and bijection, RMS(sigma R a - b) >= |sigma - 1| (both have RMS 1).
    if (std::abs(sigma - 1.0) > tau) return std::nullopt;

    Matcher matcher(pa, pb, sigma, tau, options.respect_symbols);
    Matcher::Best best;
    if (degenerate) {
        matcher.search(1.0, -1, -1, 0.0, best);
    } else {
        search_rotations(matcher, pa, pb, sigma, tau, best);
    }
    if (!best.found) return std::nullopt;

    // Back from normalised frames to the patterns' coordinates.
    IsomorphismMatch match;
    match.mapping = std::move(best.mapping);
    match.rms_residual = best.rms * to_reported;
    match.max_residual = best.max * to_reported;
    Complex linear = 1.0;
    if (!degenerate) {
        linear = pb.spread.rms / pa.spread.rms * sigma * best.rotation;
    } else if (options.mode == Scale::rigid) {
        linear = a.metres_per_unit / b.metres_per_unit;
    } else if (options.mode == Scale::range) {
        linear = std::clamp(1.0, options.min_scale, options.max_scale) * a.metres_per_unit / b.metres_per_unit;
    }
    match.transform.a = linear.real();
    match.transform.b = linear.imag();
    match.transform.t = pb.spread.centroid - match.transform.apply_linear(pa.spread.centroid);
    return match;
}

} // namespace

std::optional<IsomorphismMatch> geometrically_isomorphic(const Pattern& a, const Pattern& b,
                                                         const IsomorphismOptions& options) {
    check_options(options);
    require_valid(a, "a");
    require_valid(b, "b");
    if (a.size() != b.size() || a.edges.size() != b.edges.size()) return std::nullopt;
    const Prepared pa(a);
    const Prepared pb(b);
    if (pa.spread.degenerate != pb.spread.degenerate) return std::nullopt;
    if (signature_of(pa, a, options.respect_symbols) != signature_of(pb, b, options.respect_symbols)) {
        return std::nullopt;
    }
    return match_prepared(pa, a, pb, b, options);
}

struct PreparedPattern::Impl {
    Pattern pattern;
    Prepared prepared;
    Signature with_symbols;
    Signature without_symbols;
    explicit Impl(Pattern p)
        : pattern(std::move(p)), prepared(pattern), with_symbols(signature_of(prepared, pattern, true)),
          without_symbols(signature_of(prepared, pattern, false)) {}
};

PreparedPattern::PreparedPattern(Pattern p) {
    require_valid(p, "to prepare");
    impl_ = std::make_shared<const Impl>(std::move(p));
}

const Pattern& PreparedPattern::pattern() const { return impl_->pattern; }

std::optional<IsomorphismMatch> geometrically_isomorphic(const PreparedPattern& a, const PreparedPattern& b,
                                                         const IsomorphismOptions& options) {
    check_options(options);
    const PreparedPattern::Impl& x = *a.impl_;
    const PreparedPattern::Impl& y = *b.impl_;
    if (x.pattern.size() != y.pattern.size() || x.pattern.edges.size() != y.pattern.edges.size()) return std::nullopt;
    if (x.prepared.spread.degenerate != y.prepared.spread.degenerate) return std::nullopt;
    if (options.respect_symbols ? x.with_symbols != y.with_symbols : x.without_symbols != y.without_symbols) return std::nullopt;
    return match_prepared(x.prepared, x.pattern, y.prepared, y.pattern, options);
}

std::vector<IsomorphismMatch> geometric_automorphisms(const Pattern& p, const IsomorphismOptions& options,
                                                     std::size_t limit) {
    check_options(options);
    require_valid(p, "p");
    const Prepared prepared(p);
    std::vector<IsomorphismMatch> result;
    IsomorphismMatch identity;
    identity.mapping.resize(p.size());
    std::iota(identity.mapping.begin(), identity.mapping.end(), 0);
    result.push_back(identity);
    if (prepared.spread.degenerate || limit <= 1) return result;

    const double tau = options.tolerance * (1.0 + 1e-9) + 1e-12;
    Matcher matcher(prepared, prepared, 1.0, tau, options.respect_symbols);
    std::vector<std::pair<std::vector<int>, Complex>> all;
    Matcher::Best best;
    best.all = &all;
    search_rotations(matcher, prepared, prepared, 1.0, tau, best);
    // Each bijection can pass under several hypotheses; keep it once, in a stable order.
    std::sort(all.begin(), all.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
    all.erase(std::unique(all.begin(), all.end(), [](const auto& x, const auto& y) { return x.first == y.first; }),
              all.end());
    for (auto& [mapping, rotation] : all) {
        if (mapping == identity.mapping) continue;
        if (result.size() >= limit) break;
        IsomorphismMatch m;
        m.mapping = std::move(mapping);
        m.transform.a = rotation.real();
        m.transform.b = rotation.imag();
        m.transform.t = prepared.spread.centroid - m.transform.apply_linear(prepared.spread.centroid);
        double squares = 0.0;
        double worst = 0.0;
        for (std::size_t i = 0; i < p.size(); ++i) {
            const double e = std::abs(rotation * prepared.z[i] - prepared.z[static_cast<std::size_t>(m.mapping[i])]);
            squares += e * e;
            worst = std::max(worst, e);
        }
        m.rms_residual = std::sqrt(squares / static_cast<double>(p.size()));
        m.max_residual = worst;
        result.push_back(std::move(m));
    }
    return result;
}

std::uint64_t invariant_hash(const Pattern& p, bool with_symbols) {
    require_valid(p, "to hash");
    const Prepared prepared(p);
    const Signature s = signature_of(prepared, p, with_symbols);
    std::uint64_t h = combine(0x6767675f70617474ULL, p.size());
    h = combine(h, p.edges.size());
    for (std::uint64_t x : s.vertices) h = combine(h, x);
    for (std::uint64_t x : s.edges) h = combine(h, x);
    return h;
}

} // namespace ggg
