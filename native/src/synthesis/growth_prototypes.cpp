// The first stage of growth: each rule derived all the way to streets, once, at unit size:
// what one placement of it adds, how much it weighs in the random choice of a rule, and how
// square it is (growth_stages.hpp). Placement copies these shapes onto the frontier.
#include "growth_stages.hpp"

#include <algorithm>
#include <complex>
#include <tuple>

#include "ggg/grammar/rewriting.hpp"

namespace ggg::growth_detail {

std::pair<double, double> four_fold(const std::vector<std::pair<Vec2, Vec2>>& segments) {
    std::complex<double> z = 0.0;
    double total = 0.0;
    for (const auto& [a, b] : segments) {
        const Vec2 d = b - a;
        const double l = d.norm();
        if (l <= 0) continue;
        z += l * std::polar(1.0, 4.0 * std::atan2(d.y(), d.x()));
        total += l;
    }
    if (total <= 0) return {0.0, 0.0};
    return {std::abs(z) / total, std::arg(z) / 4.0};
}

Prototype prototype_of(const Grammar& grammar, const Rule& rule, int depth, const GrowOptions& o) {
    Prototype p;
    p.symbol = rule.symbol;
    p.size_m = rule.size_m > 0 ? rule.size_m : o.default_size_m;
    p.weight = rule.uses > 0 ? static_cast<double>(rule.uses) : 1.0; // times its edges, below
    GeometricGraph g;
    place_nonterminal(g, rule.symbol, Vec2::Zero(), Frame{});
    DeriveOptions d;
    d.max_steps = depth + 1;
    d.max_vertices = 20'000;
    d.grammar_validated = true; // by grow_region
    derive(g, grammar, d);
    std::vector<int> index(g.vertex_count(), -1);
    for (std::size_t v = 0; v < g.vertex_count(); ++v) {
        if (g.symbols[v] != 0) continue; // a nonterminal without a rule stays out
        index[v] = static_cast<int>(p.positions.size());
        p.positions.push_back(g.positions[v]);
    }
    std::vector<int> degree(p.positions.size(), 0);
    std::vector<double> lengths;
    for (const auto& [a, b] : g.edges) {
        const int x = index[static_cast<std::size_t>(a)], y = index[static_cast<std::size_t>(b)];
        if (x < 0 || y < 0) continue;
        p.edges.push_back({x, y});
        ++degree[static_cast<std::size_t>(x)];
        ++degree[static_cast<std::size_t>(y)];
        lengths.push_back((p.positions[static_cast<std::size_t>(x)] - p.positions[static_cast<std::size_t>(y)]).norm());
    }
    if (p.positions.empty() || p.edges.empty()) return p;
    for (const Vec2& v : p.positions) p.centroid += v;
    p.centroid /= static_cast<double>(p.positions.size());
    for (const Vec2& v : p.positions) p.radius = std::max(p.radius, (v - p.centroid).norm());
    std::nth_element(lengths.begin(), lengths.begin() + static_cast<long>(lengths.size() / 2), lengths.end());
    p.edge_length = lengths[lengths.size() / 2];
    std::vector<std::pair<Vec2, Vec2>> segments;
    for (const auto& [a, b] : p.edges) segments.emplace_back(p.positions[static_cast<std::size_t>(a)], p.positions[static_cast<std::size_t>(b)]);
    std::tie(p.squareness, p.square_angle) = four_fold(segments);
    // A rule is chosen as often as its streets occur in the city it was learned from: a
    // block of eight streets used 10 times weighs as much as a street used 80 times.
    p.weight *= static_cast<double>(p.edges.size());
    // Blocks make a street network; a rule with c independent cycles (E - V + 1, for a
    // connected rule) counts 1 + c times, so that tree-shaped pieces do not crowd blocks out.
    const double cycles = std::max(0.0, static_cast<double>(p.edges.size()) - static_cast<double>(p.positions.size()) + 1.0);
    p.weight *= 1.0 + o.block_preference * cycles;
    for (std::size_t v = 0; v < p.positions.size(); ++v) {
        if (degree[v] < 3) p.attach.push_back(static_cast<int>(v));
    }
    if (p.attach.empty()) {
        for (std::size_t v = 0; v < p.positions.size(); ++v) p.attach.push_back(static_cast<int>(v));
    }
    return p;
}

} // namespace ggg::growth_detail
