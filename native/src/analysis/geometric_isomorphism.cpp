// Geometric isomorphism of patterns (paper 3.1).
//
// The search: with the centroids matched and the scale fixed by the mode, only
// the rotation and the bijection are unknown. One vertex p of a farthest from its centroid
// and each plausible partner q in b give a rotation hypothesis; every other vertex then has
// few partners near its predicted place, and a depth-first search over those (nearest first,
// pruned by degree, symbol and adjacency with the vertices already placed) finds the
// bijections whose least-squares rotation passes the tolerance. The candidate radius is
// wide enough that no passing bijection is missed (see Matcher::collect_candidates).
#include "ggg/analysis/geometric_isomorphism.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <memory>
#include <numeric>
#include <string>
#include <utility>

#include "ggg/error.hpp"
#include "isomorphism_matcher.hpp"

namespace ggg {

namespace {

using namespace isomorphism_detail; // Complex, Prepared, Matcher, search_rotations

void require_valid(const Pattern& p, const char* name) {
    const std::string problem = check_pattern(p);
    if (!problem.empty()) throw UsageError(std::string("pattern ") + name + ": " + problem);
}

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
