// Isogroup detection by vertex expansion (paper 5.1). See the header for the method; the
// notes here are about how it is made fast and deterministic:
//  - occurrences live in flat arrays (Isogroup), candidates in one flat vector per batch;
//  - parallel loops (oneTBB) write only into slots indexed by their input, and every
//    sequential merge walks those slots in index order, so the thread count never changes
//    a result;
//  - parents are processed in batches so that the candidate arrays stay bounded.
#include "ggg/analysis/isogroup_detection.hpp"

#include <algorithm>
#include <chrono>
#include <array>
#include <bit>
#include <cmath>
#include <complex>
#include <cstdint>
#include <limits>
#include <numbers>
#include <string>
#include <unordered_map>
#include <utility>

#include <boost/geometry.hpp>
#include <boost/geometry/geometries/point_xy.hpp>
#include <boost/geometry/geometries/polygon.hpp>
#include <boost/geometry/geometries/multi_point.hpp>
#include <boost/geometry/index/rtree.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include "ggg/error.hpp"

namespace ggg {

namespace {

using Complex = std::complex<double>;
constexpr int max_pattern_order = 64; // vertex masks are 64-bit

// ---------------------------------------------------------------------------------------
// Geometry helpers

double hull_area(std::span<const Vec2> points) {
    namespace bg = boost::geometry;
    using Point = bg::model::d2::point_xy<double>;
    if (points.size() < 3) return 0.0;
    bg::model::multi_point<Point> cloud;
    cloud.reserve(points.size());
    for (const Vec2& p : points) cloud.emplace_back(p.x(), p.y());
    bg::model::polygon<Point> hull;
    bg::convex_hull(cloud, hull);
    return std::abs(bg::area(hull));
}

// The similarity mapping the canonical pattern `p` (centroid 0, sum of squares k) onto the
// graph points `y`: closed-form least squares, no allocation (the analyzer's hot path).
Similarity2 fit_canonical(const std::vector<Vec2>& p, const Vec2* y, std::size_t k) {
    Vec2 centroid = Vec2::Zero();
    for (std::size_t j = 0; j < k; ++j) centroid += y[j];
    centroid /= static_cast<double>(k);
    double re = 0.0;
    double im = 0.0;
    double norm = 0.0;
    for (std::size_t j = 0; j < k; ++j) {
        const Vec2 d = y[j] - centroid;
        re += p[j].x() * d.x() + p[j].y() * d.y();
        im += p[j].x() * d.y() - p[j].y() * d.x();
        norm += p[j].squaredNorm();
    }
    Similarity2 t;
    if (norm > 0.0) {
        t.a = re / norm;
        t.b = im / norm;
    }
    t.t = centroid;
    return t;
}

// Brings `positions` to the canonical frame (centroid 0, RMS radius 1); false when they
// all coincide.
bool canonicalise(std::vector<Vec2>& positions) {
    const Spread s = spread_of(positions);
    if (s.degenerate) return false;
    for (Vec2& p : positions) p = (p - s.centroid) / s.rms;
    return true;
}

// Generalised Procrustes: fit every occurrence to the pattern, replace the pattern by the
// mean of the occurrences seen through their fits, fit again. One round settles it: the
// first pattern is already close (it is the parent's mean plus the new vertex's mean).
void refine(Isogroup& group, const GeometricGraph& g, int rounds = 1) {
    const std::size_t k = group.order();
    const std::size_t n = group.frequency();
    if (!canonicalise(group.pattern.positions)) return;
    // The occurrences' positions, gathered once: the rounds then read them in order.
    std::vector<Vec2> ys(n * k);
    for (std::size_t i = 0; i < n * k; ++i) ys[i] = g.positions[static_cast<std::size_t>(group.vertices[i])];
    for (int round = 0; round <= rounds; ++round) {
        std::vector<Vec2> mean(k, Vec2::Zero());
        double scale_sum = 0.0;
        for (std::size_t i = 0; i < n; ++i) {
            const Vec2* y = ys.data() + i * k;
            Similarity2& t = group.transforms[i];
            t = fit_canonical(group.pattern.positions, y, k);
            const double s = std::sqrt(t.a * t.a + t.b * t.b);
            scale_sum += s;
            if (round == rounds || !(s > 0.0)) continue;
            const Similarity2 inverse = t.inverse();
            for (std::size_t j = 0; j < k; ++j) mean[j] += inverse.apply(y[j]);
        }
        group.pattern.metres_per_unit = n > 0 && scale_sum > 0.0 ? scale_sum / static_cast<double>(n) : 1.0;
        if (round == rounds) break;
        for (Vec2& m : mean) m /= static_cast<double>(n);
        if (!canonicalise(mean)) break;
        group.pattern.positions = std::move(mean);
    }
}

// ---------------------------------------------------------------------------------------
// The polar grid

class PolarGrid {
public:
    PolarGrid(int angles, int distances) : angles_(angles), distances_(distances) {
        log_lo_ = std::log(1.0 / 8.0);
        const double log_hi = std::log(8.0);
        lo2_ = std::exp(2.0 * log_lo_);
        hi2_ = std::exp(2.0 * log_hi);
        per_log_ = distances / (log_hi - log_lo_);
        per_radian_ = angles / (2.0 * std::numbers::pi);
    }
    int size() const { return angles_ * distances_; }
    int angles() const { return angles_; }
    int distances() const { return distances_; }

    // Cell of offset d, or -1 outside the ring.
    int cell(const Vec2& d) const {
        const double r2 = d.squaredNorm();
        if (!(r2 >= lo2_ && r2 < hi2_)) return -1;
        int ring = static_cast<int>((0.5 * std::log(r2) - log_lo_) * per_log_);
        ring = std::clamp(ring, 0, distances_ - 1);
        int sector = static_cast<int>((std::atan2(d.y(), d.x()) + std::numbers::pi) * per_radian_);
        if (sector >= angles_) sector = 0;
        if (sector < 0) sector = 0;
        return ring * angles_ + sector;
    }

    // Chebyshev neighbours (angle wraps around, distance does not) of `cell`, itself excluded.
    template <class F>
    void for_each_neighbour(int cell, F&& f) const {
        const int ring = cell / angles_;
        const int sector = cell % angles_;
        for (int dr = -1; dr <= 1; ++dr) {
            const int r = ring + dr;
            if (r < 0 || r >= distances_) continue;
            for (int ds = -1; ds <= 1; ++ds) {
                if (dr == 0 && ds == 0) continue;
                if (angles_ <= 2 && ds != 0) continue;
                const int s = (sector + ds + angles_) % angles_;
                f(r * angles_ + s);
            }
        }
    }

private:
    int angles_;
    int distances_;
    double log_lo_;
    double lo2_;
    double hi2_;
    double per_log_;
    double per_radian_;
};

// Greedy peak clustering of a histogram: cells in decreasing count (ties: lower index) each
// become a peak unless already claimed, and claim their unclaimed non-empty neighbours.
// Returns the cluster of every cell (-1 for empty cells) and the number of clusters.
template <class Neighbours>
int cluster_histogram(const std::vector<std::uint32_t>& counts, std::vector<int>& cluster, Neighbours&& neighbours) {
    const int size = static_cast<int>(counts.size());
    cluster.assign(counts.size(), -1);
    std::vector<int> order;
    for (int c = 0; c < size; ++c) {
        if (counts[static_cast<std::size_t>(c)] > 0) order.push_back(c);
    }
    std::sort(order.begin(), order.end(), [&](int a, int b) {
        const auto ca = counts[static_cast<std::size_t>(a)];
        const auto cb = counts[static_cast<std::size_t>(b)];
        return ca > cb || (ca == cb && a < b);
    });
    int clusters = 0;
    for (int c : order) {
        if (cluster[static_cast<std::size_t>(c)] >= 0) continue;
        const int id = clusters++;
        cluster[static_cast<std::size_t>(c)] = id;
        neighbours(c, [&](int n) {
            if (counts[static_cast<std::size_t>(n)] > 0 && cluster[static_cast<std::size_t>(n)] < 0) {
                cluster[static_cast<std::size_t>(n)] = id;
            }
        });
    }
    return clusters;
}

// ---------------------------------------------------------------------------------------
// Expansion

struct Symmetry {
    std::vector<int> perm; // pattern vertex j corresponds to perm[j]
    Similarity2 map;       // pattern coordinates: x -> rotation about the centroid
};

// A parent group ready for expansion.
struct Parent {
    const Isogroup* group = nullptr;
    long index = -1; // in the result
    std::vector<Symmetry> symmetries; // identity first
};

struct Candidate {
    std::uint64_t mask;      // pattern vertices the new vertex touches, after the symmetry
    std::uint32_t symbol;    // of the new vertex
    std::uint32_t occurrence;
    VertexId vertex;
    std::uint16_t cell;
    std::uint8_t symmetry;
    float x, y;              // new vertex in the parent's canonical frame, after the symmetry
};

bool candidate_less(const Candidate& a, const Candidate& b) {
    if (a.mask != b.mask) return a.mask < b.mask;
    if (a.symbol != b.symbol) return a.symbol < b.symbol;
    if (a.cell != b.cell) return a.cell < b.cell;
    if (a.occurrence != b.occurrence) return a.occurrence < b.occurrence;
    return a.vertex < b.vertex;
}

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

// Candidates of occurrences [begin, end) of `parent`, appended to `out` in occurrence order.
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

// Sorted vertex set of an occurrence, for de-duplication.
struct VertexSetKey {
    std::uint64_t hash;
    std::uint32_t index;
};

std::uint64_t mix(std::uint64_t x) {
    x += 0x9e3779b97f4a7c15ULL;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
    return x ^ (x >> 31);
}

// Removes occurrences whose vertex set repeats an earlier one (the first one stays).
void deduplicate(Isogroup& group) {
    const std::size_t k = group.order();
    const std::size_t n = group.frequency();
    std::vector<VertexId> sorted(group.vertices);
    std::vector<VertexSetKey> keys(n);
    for (std::size_t i = 0; i < n; ++i) {
        auto first = sorted.begin() + static_cast<std::ptrdiff_t>(i * k);
        std::sort(first, first + static_cast<std::ptrdiff_t>(k));
        std::uint64_t h = 0x5eed;
        for (std::size_t j = 0; j < k; ++j) h = mix(h ^ static_cast<std::uint64_t>(static_cast<std::uint32_t>(sorted[i * k + j])));
        keys[i] = {h, static_cast<std::uint32_t>(i)};
    }
    std::sort(keys.begin(), keys.end(), [](const VertexSetKey& a, const VertexSetKey& b) {
        return a.hash < b.hash || (a.hash == b.hash && a.index < b.index);
    });
    std::vector<char> drop(n, 0);
    bool any = false;
    for (std::size_t a = 0; a < n;) {
        std::size_t b = a + 1;
        while (b < n && keys[b].hash == keys[a].hash) ++b;
        for (std::size_t x = a; x < b; ++x) {
            if (drop[keys[x].index]) continue;
            for (std::size_t y = x + 1; y < b; ++y) {
                if (drop[keys[y].index]) continue;
                if (std::equal(sorted.begin() + static_cast<std::ptrdiff_t>(keys[x].index * k),
                               sorted.begin() + static_cast<std::ptrdiff_t>((keys[x].index + 1) * k),
                               sorted.begin() + static_cast<std::ptrdiff_t>(keys[y].index * k))) {
                    drop[keys[y].index] = 1;
                    any = true;
                }
            }
        }
        a = b;
    }
    if (!any) return;
    std::size_t out = 0;
    for (std::size_t i = 0; i < n; ++i) {
        if (drop[i]) continue;
        if (out != i) {
            std::copy_n(group.vertices.begin() + static_cast<std::ptrdiff_t>(i * k), k,
                        group.vertices.begin() + static_cast<std::ptrdiff_t>(out * k));
            group.transforms[out] = group.transforms[i];
        }
        ++out;
    }
    group.vertices.resize(out * k);
    group.transforms.resize(out);
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

// Runs body(i) for i in [0, n) in parallel, `batch` at a time, calling between(done) on the
// calling thread after each batch: where progress is reported and a cancel can stop it, so
// a long stage never holds a cancel for more than one batch.
template <class Body, class Between>
// False when `between` asked to stop (a budget ran out) before every batch was done.
bool in_batches(std::size_t n, std::size_t batch, Body&& body, Between&& between) {
    for (std::size_t start = 0; start < n; start += batch) {
        const std::size_t end = std::min(n, start + batch);
        tbb::parallel_for(start, end, body);
        if (!between(end)) return false;
    }
    return true;
}

// A group found at the current order, with what ranking and merging need.
struct Found {
    Isogroup group;
    long parent = -1;
    double added_area = 0.0; // hull area the last vertex added, canonical units
    std::uint64_t hash = 0;
    std::vector<double> radii; // sorted distances from the centroid, canonical
    // What isomorphism keeps up to the tolerance, per class that it keeps exactly:
    // distances from the centroid sorted by (degree, symbol, distance) and edge lengths
    // sorted by (end degrees, length). Equal hashes make the classes line up.
    std::vector<std::pair<std::uint64_t, double>> vertex_profile;
    std::vector<std::pair<std::uint64_t, double>> edge_profile;
    // The 99th percentile over the occurrences of their largest vertex residual from the
    // pattern (canonical units): how far this group's own copies stray (see absorb_fragments).
    double spread = -1.0; // not computed yet
    bool merged_away = false;
};

// Largest residual of each occurrence of `group` from `pattern` (vertex j of the pattern
// is vertex mapping[j] of the group's occurrences), after a least-squares fit, in units of
// the fitted scale.
std::vector<double> residuals_against(const Isogroup& group, const std::vector<Vec2>& pattern, const std::vector<int>& mapping,
                                      const GeometricGraph& g) {
    const std::size_t k = group.order();
    std::vector<double> out(group.frequency());
    std::vector<Vec2> y(k);
    for (std::size_t i = 0; i < group.frequency(); ++i) {
        for (std::size_t j = 0; j < k; ++j) {
            y[j] = g.positions[static_cast<std::size_t>(group.vertices[i * k + static_cast<std::size_t>(mapping[j])])];
        }
        const Similarity2 t = fit_canonical(pattern, y.data(), k);
        const double s = std::sqrt(t.a * t.a + t.b * t.b);
        double worst = 0.0;
        for (std::size_t j = 0; j < k; ++j) worst = std::max(worst, (t.apply(pattern[j]) - y[j]).norm());
        out[i] = s > 0.0 ? worst / s : std::numeric_limits<double>::infinity();
    }
    return out;
}

double spread_of_group(const Isogroup& group, const GeometricGraph& g) {
    if (group.frequency() == 0) return 0.0;
    std::vector<int> identity(group.order());
    for (std::size_t j = 0; j < identity.size(); ++j) identity[j] = static_cast<int>(j);
    std::vector<double> r = residuals_against(group, group.pattern.positions, identity, g);
    const auto q = r.begin() + static_cast<std::ptrdiff_t>(0.99 * static_cast<double>(r.size() - 1));
    std::nth_element(r.begin(), q, r.end());
    return *q;
}

void describe(Found& f, bool with_symbols) {
    const auto& p = f.group.pattern.positions;
    f.hash = invariant_hash(f.group.pattern, with_symbols);
    f.radii.resize(p.size());
    for (std::size_t i = 0; i < p.size(); ++i) f.radii[i] = p[i].norm();
    std::sort(f.radii.begin(), f.radii.end());
    std::vector<std::uint64_t> degree(p.size(), 0);
    for (const auto& [u, v] : f.group.pattern.edges) {
        ++degree[static_cast<std::size_t>(u)];
        ++degree[static_cast<std::size_t>(v)];
    }
    f.vertex_profile.resize(p.size());
    for (std::size_t i = 0; i < p.size(); ++i) {
        f.vertex_profile[i] = {degree[i] << 32 | (with_symbols ? f.group.pattern.symbols[i] : 0u), p[i].norm()};
    }
    std::sort(f.vertex_profile.begin(), f.vertex_profile.end());
    f.edge_profile.clear();
    for (const auto& [u, v] : f.group.pattern.edges) {
        const auto du = degree[static_cast<std::size_t>(u)];
        const auto dv = degree[static_cast<std::size_t>(v)];
        f.edge_profile.emplace_back(std::min(du, dv) << 32 | std::max(du, dv),
                                    (p[static_cast<std::size_t>(u)] - p[static_cast<std::size_t>(v)]).norm());
    }
    std::sort(f.edge_profile.begin(), f.edge_profile.end());
    const double whole = hull_area(p);
    const double without_last = hull_area(std::span<const Vec2>(p.data(), p.size() - 1));
    f.added_area = std::max(0.0, whole - without_last);
}

double score_of(const Found& f) { return static_cast<double>(f.group.frequency()) * f.added_area; }

// Builds the children of one parent from its sorted candidates.
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

// Groups in buckets of equal invariant hash (only these can be isomorphic); inside a
// bucket, most frequent first, then in input order. buckets are ranges of `order`.
struct HashBuckets {
    std::vector<std::size_t> order;
    std::vector<std::pair<std::size_t, std::size_t>> buckets;
};

HashBuckets hash_buckets(const std::vector<Found>& found) {
    HashBuckets hb;
    hb.order.resize(found.size());
    for (std::size_t i = 0; i < found.size(); ++i) hb.order[i] = i;
    std::sort(hb.order.begin(), hb.order.end(), [&](std::size_t a, std::size_t b) {
        if (found[a].hash != found[b].hash) return found[a].hash < found[b].hash;
        if (found[a].group.frequency() != found[b].group.frequency()) {
            return found[a].group.frequency() > found[b].group.frequency();
        }
        return a < b;
    });
    for (std::size_t a = 0; a < hb.order.size();) {
        std::size_t b = a + 1;
        while (b < hb.order.size() && found[hb.order[b]].hash == found[hb.order[a]].hash) ++b;
        hb.buckets.emplace_back(a, b);
        a = b;
    }
    return hb;
}

// Moves f's occurrences into rep (f's vertex j is rep's vertex match.mapping[j]; the
// transforms are composed through the match) and marks f merged away.
void fold_into(Found& rep, Found& f, const IsomorphismMatch& match) {
    const std::size_t k = f.group.order();
    const Similarity2 back = match.transform.inverse();
    std::vector<VertexId> remapped(k);
    for (std::size_t i = 0; i < f.group.frequency(); ++i) {
        for (std::size_t j = 0; j < k; ++j) remapped[static_cast<std::size_t>(match.mapping[j])] = f.group.vertices[i * k + j];
        rep.group.vertices.insert(rep.group.vertices.end(), remapped.begin(), remapped.end());
        rep.group.transforms.push_back(f.group.transforms[i] * back);
    }
    f.merged_away = true;
    f.group.vertices = {};
    f.group.transforms = {};
}

// Folds groups that are geometrically isomorphic into the most frequent of them.
void merge_isomorphic(std::vector<Found>& found, const GeometricGraph& g, const DetectionOptions& o) {
    IsomorphismOptions iso;
    iso.tolerance = o.merge_tolerance;
    iso.mode = o.scale_mode;
    iso.respect_symbols = o.respect_symbols;
    if (o.scale_mode == IsomorphismOptions::Scale::rigid) {
        iso.mode = IsomorphismOptions::Scale::range;
        iso.min_scale = 1.0 / (1.0 + o.scale_tolerance);
        iso.max_scale = 1.0 + o.scale_tolerance;
    } else if (o.scale_mode == IsomorphismOptions::Scale::range) {
        iso.min_scale = o.min_scale / o.max_scale;
        iso.max_scale = o.max_scale / o.min_scale;
    }

    const HashBuckets hb = hash_buckets(found);
    const std::vector<std::size_t>& order = hb.order;
    const auto& buckets = hb.buckets;
    const double radius_slack = 1.5 * o.merge_tolerance + 1e-9;
    tbb::parallel_for(std::size_t{0}, buckets.size(), [&](std::size_t bi) {
        const auto [a, b] = buckets[bi];
        if (b - a < 2) return;
        // Representatives are filed in an R-tree over six of the profile values (three
        // vertex distances, three edge lengths), so a group is compared only with those
        // whose values could all be within the tolerance.
        namespace bg = boost::geometry;
        namespace bgi = boost::geometry::index;
        using Point = bg::model::point<double, 6, bg::cs::cartesian>;
        using Box = bg::model::box<Point>;
        std::vector<std::size_t> representatives;
        bgi::rtree<std::pair<Point, std::size_t>, bgi::quadratic<16>> filed;
        std::vector<std::size_t> touched;
        auto key_of = [](const Found& f) {
            const auto& vp = f.vertex_profile;
            const auto& ep = f.edge_profile;
            const std::size_t k = vp.size();
            const std::size_t e = ep.size();
            Point pt;
            pt.set<0>(vp[0].second);
            pt.set<1>(vp[k / 2].second);
            pt.set<2>(vp[k - 1].second);
            pt.set<3>(e ? ep[0].second : 0.0);
            pt.set<4>(e ? ep[e / 2].second : 0.0);
            pt.set<5>(e ? ep[e - 1].second : 0.0);
            return pt;
        };
        std::vector<std::pair<Point, std::size_t>> hits;
        std::vector<std::size_t> nearby;
        for (std::size_t x = a; x < b; ++x) {
            Found& f = found[order[x]];
            const Point key = key_of(f);
            const double v = radius_slack;
            const double w = 2.0 * radius_slack;
            Point lo;
            Point hi;
            auto span = [&](auto index, double slack) {
                constexpr std::size_t i = decltype(index)::value;
                lo.set<i>(key.get<i>() - slack);
                hi.set<i>(key.get<i>() + slack);
            };
            span(std::integral_constant<std::size_t, 0>{}, v);
            span(std::integral_constant<std::size_t, 1>{}, v);
            span(std::integral_constant<std::size_t, 2>{}, v);
            span(std::integral_constant<std::size_t, 3>{}, w);
            span(std::integral_constant<std::size_t, 4>{}, w);
            span(std::integral_constant<std::size_t, 5>{}, w);
            hits.clear();
            filed.query(bgi::intersects(Box(lo, hi)), std::back_inserter(hits));
            nearby.clear();
            for (const auto& h : hits) nearby.push_back(h.second);
            // In the order the representatives were made: the most frequent match wins.
            std::sort(nearby.begin(), nearby.end());
            nearby.erase(std::unique(nearby.begin(), nearby.end()), nearby.end());
            bool merged = false;
            for (std::size_t position : nearby) {
                const std::size_t r = representatives[position];
                Found& rep = found[r];
                bool close = true;
                for (std::size_t i = 0; i < f.radii.size() && close; ++i) {
                    close = std::abs(f.radii[i] - rep.radii[i]) <= radius_slack;
                }
                for (std::size_t i = 0; i < f.vertex_profile.size() && close; ++i) {
                    close = f.vertex_profile[i].first == rep.vertex_profile[i].first &&
                            std::abs(f.vertex_profile[i].second - rep.vertex_profile[i].second) <= radius_slack;
                }
                for (std::size_t i = 0; i < f.edge_profile.size() && close; ++i) {
                    close = f.edge_profile[i].first == rep.edge_profile[i].first &&
                            std::abs(f.edge_profile[i].second - rep.edge_profile[i].second) <= 2.0 * radius_slack;
                }
                if (!close) continue;
                const auto match = geometrically_isomorphic(f.group.pattern, rep.group.pattern, iso);
                if (!match) continue;
                fold_into(rep, f, *match);
                if (std::find(touched.begin(), touched.end(), r) == touched.end()) touched.push_back(r);
                merged = true;
                break;
            }
            if (!merged) {
                filed.insert({key, representatives.size()});
                representatives.push_back(order[x]);
            }
        }
        for (std::size_t r : touched) {
            deduplicate(found[r].group);
            refine(found[r].group, g);
        }
    });
    std::erase_if(found, [](const Found& f) { return f.merged_away; });
}

// Noise splits a pattern's copies: most land in one group, a few take other paths through
// the polar grids and form small groups whose mean patterns are pulled off by the noise, too
// far for merge_isomorphic. A small group is folded into one of the dominant groups of its
// topology when its copies look like that group's own: the median of their residuals from
// the dominant pattern is within the dominant group's 99th-percentile residual plus the
// merge tolerance. Only groups at most a quarter as frequent are folded,
// and only into the four most frequent groups of the topology, so distinct patterns that
// are both common stay apart. Folding changes only the groups reported: the groups that
// are grown keep their own copies (so a folded group never widens the next order, where it
// would fold more), and groups marked in keep_apart are neither folded nor removed.
// Folded groups are marked merged_away.
void absorb_fragments(std::vector<Found>& found, const GeometricGraph& g, const DetectionOptions& o,
                      const std::vector<char>& keep_apart) {
    constexpr std::size_t dominant = 4;
    constexpr double ratio = 4.0;
    const HashBuckets hb = hash_buckets(found);
    const std::vector<std::size_t>& order = hb.order;
    const auto& buckets = hb.buckets;
    tbb::parallel_for(std::size_t{0}, buckets.size(), [&](std::size_t bi) {
        const auto [a, b] = buckets[bi];
        if (b - a < 2) return;
        const std::size_t heads = std::min(dominant, b - a);
        std::vector<char> touched(heads, 0);
        for (std::size_t x = a + 1; x < b; ++x) {
            if (keep_apart[order[x]]) continue;
            Found& f = found[order[x]];
            for (std::size_t h = 0; h < heads && a + h < x; ++h) {
                Found& rep = found[order[a + h]];
                if (static_cast<double>(f.group.frequency()) * ratio > static_cast<double>(rep.group.frequency())) continue;
                if (rep.spread < 0.0) rep.spread = spread_of_group(rep.group, g);
                const double reach = rep.spread + o.merge_tolerance;
                const double slack = 1.5 * reach;
                bool close = true;
                for (std::size_t i = 0; i < f.vertex_profile.size() && close; ++i) {
                    close = f.vertex_profile[i].first == rep.vertex_profile[i].first &&
                            std::abs(f.vertex_profile[i].second - rep.vertex_profile[i].second) <= slack;
                }
                if (!close) continue;
                IsomorphismOptions iso;
                iso.tolerance = std::min(reach, 0.9);
                iso.respect_symbols = o.respect_symbols;
                const auto match = geometrically_isomorphic(f.group.pattern, rep.group.pattern, iso);
                if (!match) continue;
                // rep's vertex j is f's vertex inverse[j].
                std::vector<int> inverse(match->mapping.size());
                for (std::size_t j = 0; j < inverse.size(); ++j) inverse[static_cast<std::size_t>(match->mapping[j])] = static_cast<int>(j);
                std::vector<double> r = residuals_against(f.group, rep.group.pattern.positions, inverse, g);
                const auto median = r.begin() + static_cast<std::ptrdiff_t>(r.size() / 2);
                std::nth_element(r.begin(), median, r.end());
                if (!(*median <= reach)) continue;
                fold_into(rep, f, *match);
                touched[h] = 1;
                break;
            }
        }
        for (std::size_t h = 0; h < heads; ++h) {
            if (!touched[h]) continue;
            Found& rep = found[order[a + h]];
            deduplicate(rep.group);
            refine(rep.group, g);
        }
    });
}

// One subgraph, one isogroup: a vertex set found in several groups (groups whose patterns
// are alike but not within the merge tolerance, e.g. at a cell border) stays only in the
// most frequent of them. Without this, near-duplicate groups would multiply with every
// order instead of competing for the same occurrences.
void assign_to_one_group(std::vector<Found>& found, const GeometricGraph& g) {
    struct Entry {
        std::uint64_t hash;
        std::uint32_t rank; // of the group, most frequent first
        std::uint32_t occurrence;
    };
    std::vector<std::size_t> by_frequency(found.size());
    for (std::size_t i = 0; i < found.size(); ++i) by_frequency[i] = i;
    std::stable_sort(by_frequency.begin(), by_frequency.end(), [&](std::size_t a, std::size_t b) {
        return found[a].group.frequency() > found[b].group.frequency();
    });
    std::vector<std::size_t> offset(found.size() + 1, 0);
    for (std::size_t r = 0; r < found.size(); ++r) offset[r + 1] = offset[r] + found[by_frequency[r]].group.frequency();
    std::vector<Entry> entries(offset.back());
    std::vector<std::vector<VertexId>> sorted_sets(found.size());
    tbb::parallel_for(std::size_t{0}, found.size(), [&](std::size_t r) {
        const Isogroup& group = found[by_frequency[r]].group;
        const std::size_t k = group.order();
        std::vector<VertexId>& sorted = sorted_sets[r];
        sorted = group.vertices;
        for (std::size_t i = 0; i < group.frequency(); ++i) {
            auto first = sorted.begin() + static_cast<std::ptrdiff_t>(i * k);
            std::sort(first, first + static_cast<std::ptrdiff_t>(k));
            std::uint64_t h = 0x5eed;
            for (std::size_t j = 0; j < k; ++j) h = mix(h ^ static_cast<std::uint32_t>(sorted[i * k + j]));
            entries[offset[r] + i] = {h, static_cast<std::uint32_t>(r), static_cast<std::uint32_t>(i)};
        }
    });
    tbb::parallel_sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) {
        if (a.hash != b.hash) return a.hash < b.hash;
        if (a.rank != b.rank) return a.rank < b.rank;
        return a.occurrence < b.occurrence;
    });
    std::vector<std::vector<char>> drop(found.size());
    for (std::size_t r = 0; r < found.size(); ++r) drop[r].assign(found[by_frequency[r]].group.frequency(), 0);
    std::vector<char> touched(found.size(), 0);
    auto set_of = [&](const Entry& e) {
        const std::size_t k = found[by_frequency[e.rank]].group.order();
        return sorted_sets[e.rank].data() + static_cast<std::size_t>(e.occurrence) * k;
    };
    for (std::size_t a = 0; a < entries.size();) {
        std::size_t b = a + 1;
        while (b < entries.size() && entries[b].hash == entries[a].hash) ++b;
        for (std::size_t x = a; x < b; ++x) {
            if (drop[entries[x].rank][entries[x].occurrence]) continue;
            const std::size_t k = found[by_frequency[entries[x].rank]].group.order();
            for (std::size_t y = x + 1; y < b; ++y) {
                if (drop[entries[y].rank][entries[y].occurrence]) continue;
                if (found[by_frequency[entries[y].rank]].group.order() != k) continue;
                if (std::equal(set_of(entries[x]), set_of(entries[x]) + k, set_of(entries[y]))) {
                    drop[entries[y].rank][entries[y].occurrence] = 1;
                    touched[entries[y].rank] = 1;
                }
            }
        }
        a = b;
    }
    tbb::parallel_for(std::size_t{0}, found.size(), [&](std::size_t r) {
        if (!touched[r]) return;
        Isogroup& group = found[by_frequency[r]].group;
        const std::size_t k = group.order();
        std::size_t out = 0;
        for (std::size_t i = 0; i < group.frequency(); ++i) {
            if (drop[r][i]) continue;
            if (out != i) {
                std::copy_n(group.vertices.begin() + static_cast<std::ptrdiff_t>(i * k), k,
                            group.vertices.begin() + static_cast<std::ptrdiff_t>(out * k));
                group.transforms[out] = group.transforms[i];
            }
            ++out;
        }
        group.vertices.resize(out * k);
        group.transforms.resize(out);
        if (out > 0) refine(group, g);
    });
}

std::vector<Symmetry> symmetries_of(const Pattern& p, const DetectionOptions& o) {
    IsomorphismOptions iso;
    iso.tolerance = o.merge_tolerance;
    iso.respect_symbols = o.respect_symbols;
    std::vector<Symmetry> result;
    for (auto& m : geometric_automorphisms(p, iso, 255)) result.push_back({std::move(m.mapping), m.transform});
    return result;
}

// The order-2 groups: every edge, one group per (sorted) symbol pair, oriented from the
// smaller symbol (equal symbols: from the smaller vertex id).
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

void sort_by_frequency(std::vector<Found>& found) {
    std::stable_sort(found.begin(), found.end(), [](const Found& a, const Found& b) {
        if (a.group.frequency() != b.group.frequency()) return a.group.frequency() > b.group.frequency();
        return score_of(a) > score_of(b);
    });
}

// The time and memory budgets of DetectionOptions. Memory is what the detection holds: the
// groups found, the groups being grown and the candidates of the order at hand.
class Budget {
public:
    explicit Budget(const DetectionOptions& o) : o_(o), start_(std::chrono::steady_clock::now()) {}

    bool out_of_time() const {
        const std::chrono::duration<double> elapsed = std::chrono::steady_clock::now() - start_;
        const double budget = time_budget_seconds(o_);
        return budget > 0 && elapsed.count() > budget;
    }

    bool spent(const DetectionResult& result, const std::vector<Isogroup>& growing, std::size_t extra_bytes) const {
        if (out_of_time()) return true;
        if (o_.max_memory_mb > 0) {
            double bytes = static_cast<double>(extra_bytes);
            for (const auto* list : {&result.isogroups, &growing}) {
                for (const Isogroup& group : *list) bytes += held_bytes(group);
            }
            if (bytes > o_.max_memory_mb * 1024.0 * 1024.0) return true;
        }
        return false;
    }

private:
    static double held_bytes(const Isogroup& group) {
        return static_cast<double>(group.vertices.capacity() * sizeof(VertexId) + group.transforms.capacity() * sizeof(Similarity2) +
                                   group.pattern.size() * (sizeof(Vec2) + sizeof(Symbol)) + group.pattern.edges.size() * 8 + sizeof(Isogroup));
    }

    const DetectionOptions& o_;
    std::chrono::steady_clock::time_point start_;
};

DetectionResult run(const GeometricGraph& g, std::vector<Found> level, const DetectionOptions& o,
                    const ProgressCallback& progress) {
    DetectionResult result;
    const Budget limits(o);
    const Adjacency adjacency(g);
    const PolarGrid grid(o.angle_cells, o.distance_cells);
    const int last_order = o.max_order == 0 ? max_pattern_order : std::min(o.max_order, max_pattern_order);
    const std::string_view message = "finding repeated patterns";

    int order = level.empty() ? 2 : static_cast<int>(level.front().group.order());
    {
        OrderReport r;
        r.order = order;
        r.groups = level.size();
        for (const Found& f : level) r.occurrences += f.group.frequency();
        r.expanded_next = level.size();
        result.orders.push_back(r);
    }
    // Groups of the current order that are expanded: their indices in result.isogroups.
    std::vector<long> expand;
    std::vector<Isogroup> growing; // the groups of `expand`, as they are grown
    for (Found& f : level) {
        growing.push_back(f.group);
        expand.push_back(static_cast<long>(result.isogroups.size()));
        result.isogroups.push_back(std::move(f.group));
        result.parents.push_back(f.parent);
        result.scores.push_back(0.0);
    }

    while (order < last_order && !expand.empty()) {
        report(progress, static_cast<double>(order - 1) / static_cast<double>(last_order - 1), message);
        OrderReport r;
        r.order = order + 1;
        r.parents = expand.size();

        // Bound the work: would the children possibly overflow the budget?
        std::size_t parent_vertices = 0;
        for (const Isogroup& p : growing) parent_vertices += p.vertices.size();
        if (parent_vertices > o.max_occurrence_vertices || limits.spent(result, growing, 0)) {
            result.stopped_by_budget = true;
            break;
        }

        std::vector<Parent> parents(expand.size());
        tbb::parallel_for(std::size_t{0}, expand.size(), [&](std::size_t i) {
            parents[i].group = &growing[i];
            parents[i].index = expand[i];
            parents[i].symmetries = symmetries_of(parents[i].group->pattern, o);
        });

        // Work units: (parent, range of occurrences) of bounded size.
        constexpr std::size_t chunk = 2048;
        struct Unit {
            std::size_t parent, begin, end;
        };
        std::vector<Unit> units;
        for (std::size_t p = 0; p < parents.size(); ++p) {
            const std::size_t n = parents[p].group->frequency();
            for (std::size_t s = 0; s < n; s += chunk) units.push_back({p, s, std::min(n, s + chunk)});
        }
        std::vector<std::vector<Candidate>> unit_candidates(units.size());
        const double step_begin = static_cast<double>(order - 1) / static_cast<double>(last_order - 1);
        const double step_size = 1.0 / static_cast<double>(last_order - 1);
        const bool collected = in_batches(units.size(), 64, [&](std::size_t u) {
            collect_candidates(g, adjacency, parents[units[u].parent], grid, o.respect_symbols, units[u].begin,
                               units[u].end, unit_candidates[u]);
        }, [&](std::size_t done) {
            report(progress, step_begin + step_size * 0.3 * static_cast<double>(done) / static_cast<double>(units.size()), message);
            return !limits.out_of_time();
        });
        if (!collected) {
            result.stopped_by_budget = true;
            break;
        }

        // Gather per parent (units of a parent are consecutive and in occurrence order).
        std::vector<std::vector<Candidate>> per_parent(parents.size());
        for (std::size_t u = 0; u < units.size(); ++u) {
            auto& target = per_parent[units[u].parent];
            r.candidates += unit_candidates[u].size();
            if (target.empty()) {
                target = std::move(unit_candidates[u]);
            } else {
                target.insert(target.end(), unit_candidates[u].begin(), unit_candidates[u].end());
            }
            unit_candidates[u] = {};
        }
        if (limits.spent(result, growing, r.candidates * sizeof(Candidate))) {
            result.stopped_by_budget = true;
            break;
        }
        std::vector<std::vector<Found>> per_parent_children(parents.size());
        const bool grouped = in_batches(parents.size(), 16, [&](std::size_t p) {
            auto& c = per_parent[p];
            if (c.size() > 100'000) {
                tbb::parallel_sort(c.begin(), c.end(), candidate_less);
            } else {
                std::sort(c.begin(), c.end(), candidate_less);
            }
            per_parent_children[p] = children_of(g, parents[p], c, grid, o);
            c = {};
        }, [&](std::size_t done) {
            report(progress, step_begin + step_size * (0.3 + 0.4 * static_cast<double>(done) / static_cast<double>(parents.size())),
                   message);
            return !limits.out_of_time();
        });
        if (!grouped) {
            result.stopped_by_budget = true;
            break;
        }
        std::vector<Found> children;
        for (auto& list : per_parent_children) {
            for (Found& f : list) children.push_back(std::move(f));
        }
        per_parent_children = {};
        r.children = children.size();
        report(progress, step_begin + step_size * 0.7, message);

        tbb::parallel_for(std::size_t{0}, children.size(), [&](std::size_t i) { describe(children[i], o.respect_symbols); });
        report(progress, step_begin + step_size * 0.75, message);
        merge_isomorphic(children, g, o);
        report(progress, step_begin + step_size * 0.85, message);
        if (order == 2) {
            // Groups of two edges: here noise is largest relative to the pattern, and the
            // fragments it makes would cut whole lineages of larger patterns short.
            absorb_fragments(children, g, o, std::vector<char>(children.size(), 0));
            std::erase_if(children, [](const Found& f) { return f.merged_away; });
        }
        assign_to_one_group(children, g);
        report(progress, step_begin + step_size * 0.9, message);
        std::erase_if(children, [&](const Found& f) { return f.group.frequency() < o.min_count; });
        tbb::parallel_for(std::size_t{0}, children.size(), [&](std::size_t i) {
            if (children[i].radii.size() != children[i].group.order()) describe(children[i], o.respect_symbols);
            const auto& p = children[i].group.pattern.positions;
            children[i].added_area = std::max(0.0, hull_area(p) - hull_area(std::span<const Vec2>(p.data(), p.size() - 1)));
        });

        // Frequency cut: rank by frequency x added area (the paper's cell score), so that
        // frequent bifurcations are grown before frequent straight continuations.
        sort_by_frequency(children);
        std::vector<std::size_t> rank(children.size());
        for (std::size_t i = 0; i < rank.size(); ++i) rank[i] = i;
        std::stable_sort(rank.begin(), rank.end(), [&](std::size_t a, std::size_t b) {
            const double sa = score_of(children[a]);
            const double sb = score_of(children[b]);
            if (sa != sb) return sa > sb;
            return a < b; // children are sorted by frequency

        });
        // Of those, grow the best ones until they hold the share (1 - cut) of this order's
        // occurrences (and at most that share of its groups). Counting occurrences, not only
        // groups, is what keeps the work per order bounded on grid cities, where thousands of
        // patches of the same grid all repeat and the few most frequent hold most copies.
        std::size_t keep = children.size();
        std::vector<char> expanded(children.size(), 0);
        if (order + 1 >= last_order) {
            keep = 0; // the last order: nothing is grown
        } else if (o.full) {
            std::fill(expanded.begin(), expanded.end(), 1);
        } else {
            const int step = order - 1; // 1 for the expansion to order 3
            const double share = 1.0 - o.cut * (1.0 - std::pow(0.5, step));
            const auto max_groups = static_cast<std::size_t>(std::ceil(share * static_cast<double>(children.size())));
            std::size_t total = 0;
            for (const Found& f : children) total += f.group.frequency();
            const double budget = share * static_cast<double>(total);
            std::size_t taken = 0;
            keep = 0;
            for (std::size_t i = 0; i < rank.size() && keep < max_groups && static_cast<double>(taken) < budget; ++i) {
                expanded[rank[i]] = 1;
                taken += children[rank[i]].group.frequency();
                ++keep;
            }
        }

        // The groups to grow, as they are before fragments are folded into the reported ones.
        std::vector<Isogroup> next_growing;
        std::vector<long> next_index;
        for (std::size_t i = 0; i < children.size(); ++i) {
            if (expanded[i]) next_growing.push_back(children[i].group);
        }
        report(progress, step_begin + step_size * 0.95, message);
        absorb_fragments(children, g, o, expanded);
        ++order;
        r.expanded_next = std::min(keep, children.size());
        r.groups = 0;
        for (std::size_t i = 0; i < children.size(); ++i) {
            if (children[i].merged_away) continue;
            ++r.groups;
            r.occurrences += children[i].group.frequency();
            if (expanded[i]) next_index.push_back(static_cast<long>(result.isogroups.size()));
            result.scores.push_back(score_of(children[i]));
            result.isogroups.push_back(std::move(children[i].group));
            result.parents.push_back(children[i].parent);
        }
        growing = std::move(next_growing);
        expand = std::move(next_index);
        result.orders.push_back(r);
    }
    report(progress, 1.0, message);
    return result;
}

} // namespace

void check_options(const DetectionOptions& o) {
    // Each message starts with the option's name as the Python module spells it.
    auto fail = [](const std::string& what) { throw UsageError(what); };
    if (o.angle_cells < 1 || o.angle_cells > 360) fail("grid: needs 1 to 360 angle cells, got " + std::to_string(o.angle_cells));
    if (o.distance_cells < 1 || o.distance_cells > 100) fail("grid: needs 1 to 100 distance cells, got " + std::to_string(o.distance_cells));
    if (!(o.cut >= 0.0 && o.cut < 1.0)) fail("cut: the frequency cut must be in [0, 1), got " + std::to_string(o.cut));
    if (o.max_order < 0 || o.max_order == 1) fail("max_order: must be 0 (until nothing repeats) or at least 2, got " + std::to_string(o.max_order));
    if (o.max_order > max_pattern_order) fail("max_order: at most " + std::to_string(max_pattern_order) + ", got " + std::to_string(o.max_order));
    if (o.min_count < 1) fail("min_count: must be at least 1");
    if (!std::isfinite(o.max_seconds)) fail("max_seconds: the time budget must be a number of seconds (0 = none, < 0 = automatic)");
    if (!(std::isfinite(o.max_memory_mb) && o.max_memory_mb >= 0.0)) fail("max_memory_mb: the memory budget must be a number of megabytes >= 0 (0 = none)");
    if (!(o.merge_tolerance >= 0.0 && o.merge_tolerance < 1.0)) fail("merge_tolerance: must be in [0, 1), got " + std::to_string(o.merge_tolerance));
    if (!(o.scale_tolerance > 0.0 && o.scale_tolerance < 1.0)) fail("scale_tolerance: must be in (0, 1), got " + std::to_string(o.scale_tolerance));
    if (o.scale_mode == IsomorphismOptions::Scale::range &&
        !(std::isfinite(o.min_scale) && std::isfinite(o.max_scale) && o.min_scale > 0.0 && o.min_scale < o.max_scale)) {
        fail("scale_range: must satisfy 0 < min < max");
    }
}

DetectionResult detect_isogroups(const GeometricGraph& g, const DetectionOptions& options,
                                 const ProgressCallback& progress) {
    check_options(options);
    return run(g, edge_groups(g, options), options, progress);
}

DetectionResult detect_isogroups_from(const GeometricGraph& g, Isogroup seed, const DetectionOptions& options,
                                      const ProgressCallback& progress) {
    check_options(options);
    if (const std::string problem = check_pattern(seed.pattern); !problem.empty()) {
        throw UsageError("analysis seed: " + problem);
    }
    if (seed.order() > static_cast<std::size_t>(max_pattern_order)) {
        throw UsageError("analysis seed: at most " + std::to_string(max_pattern_order) + " vertices");
    }
    if (seed.vertices.size() != seed.order() * seed.frequency()) throw UsageError("analysis seed: malformed occurrences");
    std::vector<Found> level(1);
    level[0].group = std::move(seed);
    refine(level[0].group, g);
    return run(g, std::move(level), options, progress);
}

} // namespace ggg
