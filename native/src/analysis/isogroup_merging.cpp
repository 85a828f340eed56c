// Groups of the isogroup detection merged: isomorphic ones from different parents, and the
// fragments that noise splits off a pattern (detection_stages.hpp).
#include "detection_stages.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>

#include <tbb/parallel_for.h>

#include "ggg/graph/spatial_index.hpp"

namespace ggg::detection_detail {

namespace {

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

} // namespace

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
        using Point = spatial::PointIn<6>;
        using Box = spatial::BoxIn<6>;
        std::vector<std::size_t> representatives;
        spatial::IncrementalRTree<std::pair<Point, std::size_t>> filed;
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
            filed.query(spatial::bgi::intersects(Box(lo, hi)), std::back_inserter(hits));
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

} // namespace ggg::detection_detail
