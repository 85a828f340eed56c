// A rule made of one isogroup's copies, and its instances (encoder.hpp).
#include "encoder.hpp"

#include <algorithm>
#include <array>
#include <limits>

#include "ggg/analysis/isogroup_selection.hpp"
#include "ggg/analysis/non_overlapping.hpp"

namespace ggg::encoding_detail {

namespace {

// How much the outside streets of each vertex of an occurrence matter: 1 / rank summed over
// the streets that leave the occurrence there.
std::vector<double> outside_importance(const GeometricGraph& g, const Adjacency& adj, const std::vector<VertexId>& occ) {
    std::vector<double> importance(occ.size(), 0.0);
    for (std::size_t j = 0; j < occ.size(); ++j) {
        const VertexId v = occ[j];
        for (auto i = adj.offsets[static_cast<std::size_t>(v)]; i < adj.offsets[static_cast<std::size_t>(v) + 1]; ++i) {
            const VertexId w = adj.neighbors[static_cast<std::size_t>(i)];
            if (std::find(occ.begin(), occ.end(), w) != occ.end()) continue;
            importance[j] += 1.0 / highway_rank(g.edge_highway[static_cast<std::size_t>(adj.edge_ids[static_cast<std::size_t>(i)])]);
        }
    }
    return importance;
}

// The rule's origin: the vertex that meets the most important outside streets over all
// occurrences (then the first).
int representative_vertex(const GeometricGraph& g, const Adjacency& adj, const std::vector<std::vector<VertexId>>& occurrences) {
    std::vector<double> total(occurrences.front().size(), 0.0);
    for (const auto& occ : occurrences) {
        const std::vector<double> importance = outside_importance(g, adj, occ);
        for (std::size_t j = 0; j < total.size(); ++j) total[j] += importance[j];
    }
    return static_cast<int>(std::max_element(total.begin(), total.end()) - total.begin());
}

// Where an occurrence's nonterminal goes (Fig. 10c): on its vertex that meets the most
// important outside streets, so that the encoded graph keeps its arterials straight; among
// equals the south-westernmost, a choice that does not depend on how the occurrence's
// vertices are labelled, so that the nonterminals of a regular district form a regular
// pattern themselves, which the next level can encode.
std::size_t nonterminal_vertex(const GeometricGraph& g, const Adjacency& adj, const std::vector<VertexId>& occ) {
    const std::vector<double> importance = outside_importance(g, adj, occ);
    const double most = *std::max_element(importance.begin(), importance.end());
    std::size_t best = occ.size();
    for (std::size_t j = 0; j < occ.size(); ++j) {
        if (importance[j] < most - 1e-9) continue;
        const Vec2& p = g.positions[static_cast<std::size_t>(occ[j])];
        if (best == occ.size() || p.x() + p.y() < g.positions[static_cast<std::size_t>(occ[best])].x() + g.positions[static_cast<std::size_t>(occ[best])].y()) {
            best = j;
        }
    }
    return best;
}

EdgeId edge_between(const GeometricGraph&, const Adjacency& adj, VertexId u, VertexId v) {
    for (auto i = adj.offsets[static_cast<std::size_t>(u)]; i < adj.offsets[static_cast<std::size_t>(u) + 1]; ++i) {
        if (adj.neighbors[static_cast<std::size_t>(i)] == v) return adj.edge_ids[static_cast<std::size_t>(i)];
    }
    return -1;
}

} // namespace

std::optional<Encoder::GroupGains> Encoder::encode_group(const Isogroup& group, Take take, int level, const Adjacency& adj, std::vector<char>& used,
                                                        std::vector<std::int32_t>& level_instances, LevelReport& lr, bool price_only) {
    const std::size_t k = group.order();
    const std::size_t min_count = take == Take::once ? 1 : options_.analysis.detection.min_count;
    std::vector<std::vector<VertexId>> occs;
    for (std::size_t o = 0; o < group.frequency(); ++o) {
        const auto occ = group.occurrence(o);
        if (std::none_of(occ.begin(), occ.end(), [&](VertexId v) { return used[static_cast<std::size_t>(v)]; })) {
            occs.emplace_back(occ.begin(), occ.end());
        }
    }
    if (occs.size() < min_count) return std::nullopt;

    // Each occurrence's frame, fitted to its vertices (among the pattern's symmetries,
    // the labelling whose frame turns least from the map's axes, so that the
    // instances of a symmetric pattern agree on where their vertices are); occurrences
    // too far from the pattern's shape are left for a later level (or the axiom).
    // (A rule used once has one labelling: its own; and the search for the symmetries of a
    // whole district would be long.)
    std::vector<IsomorphismMatch> symmetries;
    if (take == Take::once) {
        IsomorphismMatch identity;
        for (std::size_t j = 0; j < k; ++j) identity.mapping.push_back(static_cast<int>(j));
        symmetries.push_back(std::move(identity));
    } else {
        symmetries = geometric_automorphisms(group.pattern, symmetry_options_);
    }
    std::vector<Similarity2> fits;
    std::vector<Vec2> world(k);
    std::size_t kept = 0;
    const std::size_t error_rejected_before = lr.error_rejected;
    for (auto& occ : occs) {
        SimilarityFit best;
        std::vector<VertexId> labelled = occ, trial(k);
        double best_turn = std::numeric_limits<double>::infinity();
        for (const IsomorphismMatch& s : symmetries) {
            for (std::size_t j = 0; j < k; ++j) trial[j] = occ[static_cast<std::size_t>(s.mapping[j])];
            for (std::size_t j = 0; j < k; ++j) world[j] = graph_.positions[static_cast<std::size_t>(trial[j])];
            const SimilarityFit fit = fit_similarity(group.pattern.positions, world);
            const double turn = std::abs(fit.transform.angle());
            if (turn < best_turn - 1e-9) {
                best_turn = turn;
                best = fit;
                labelled = trial;
            }
        }
        if (options_.max_shape_error > 0 && best.rms_residual > options_.max_shape_error * best.transform.scale()) continue;
        // A margin for the rounding of the stored frames and shapes (a few centimetres).
        if (options_.max_vertex_error_m > 0 && worst_street_misfit(group.pattern, best.transform, labelled) > options_.max_vertex_error_m - 0.05) {
            ++lr.error_rejected;
            continue;
        }
        fits.push_back(best.transform);
        occs[kept++] = std::move(labelled); // `labelled` is a copy, never occs[kept] itself
    }
    lr.shape_rejected += occs.size() - kept - (lr.error_rejected - error_rejected_before);
    occs.resize(kept);
    fits.resize(kept);
    choose_aligned(occs, fits, static_cast<int>(std::max<std::size_t>(1, symmetries.size())));
    if (occs.size() < min_count) return std::nullopt;
    std::vector<Frame> transforms(k);
    const std::size_t before = occs.size();
    consistent_frames(group, occs, fits, transforms);
    lr.frame_rejected += before - occs.size();
    if (occs.size() < min_count) return std::nullopt;
    if (price_only) return GroupGains{packed_gain(group, occs, fits, transforms, adj, false), packed_gain(group, occs, fits, transforms, adj, true)};
    const double gain = packed_gain(group, occs, fits, transforms, adj, strict_gain_);
    if (take == Take::paying && gain <= 0) return std::nullopt;

    const int rep = representative_vertex(graph_, adj, occs);
    RuleDraft draft;
    draft.level = level;
    Rule& rule = draft.rule;
    rule.symbol = static_cast<Symbol>(rules_.size() + 1);
    rule.uses = occs.size();
    const Vec2 origin = group.pattern.positions[static_cast<std::size_t>(rep)];
    std::vector<Vec2> shape(k);
    for (std::size_t j = 0; j < k; ++j) {
        RuleVertex rv;
        rv.position = round_to(group.pattern.positions[j] - origin, 1e4);
        rv.symbol = group.pattern.symbols[j];
        rv.transform = rv.symbol ? transforms[j] : Frame{};
        shape[j] = rv.position;
        rule.vertices.push_back(rv);
    }
    // Road class of each rule edge: the most common among the occurrences.
    std::vector<std::vector<HighwayClass>> classes(group.pattern.edges.size());
    for (const auto& occ : occs) {
        for (std::size_t e = 0; e < group.pattern.edges.size(); ++e) {
            const auto [a, b] = group.pattern.edges[e];
            const EdgeId id = edge_between(graph_, adj, occ[static_cast<std::size_t>(a)], occ[static_cast<std::size_t>(b)]);
            classes[e].push_back(id >= 0 ? graph_.edge_highway[static_cast<std::size_t>(id)] : HighwayClass::other);
        }
    }
    for (std::size_t e = 0; e < group.pattern.edges.size(); ++e) {
        std::array<std::size_t, highway_class_count> count{};
        for (HighwayClass c : classes[e]) ++count[static_cast<std::size_t>(c)];
        const auto best = static_cast<HighwayClass>(std::max_element(count.begin(), count.end()) - count.begin());
        rule.edges.push_back({group.pattern.edges[e][0], group.pattern.edges[e][1], best});
    }
    for (std::size_t c = 0; c < occs.size(); ++c) {
        const auto& occ = occs[c];
        for (std::size_t j = 0; j < k; ++j) world[j] = graph_.positions[static_cast<std::size_t>(occ[j])];
        InstanceDraft inst;
        inst.symbol = rule.symbol;
        inst.fit = fit_similarity(shape, world).transform;
        inst.frame = inst.fit;
        inst.frame.t = world[nonterminal_vertex(graph_, adj, occ)];
        for (std::size_t j = 0; j < k; ++j) {
            const Node n = nodes_[static_cast<std::size_t>(occ[j])];
            inst.members.push_back(n);
            if (n.nonterminal) instances_[static_cast<std::size_t>(n.id)].parent = static_cast<std::int32_t>(instances_.size());
            used[static_cast<std::size_t>(occ[j])] = 1;
        }
        RuleInstance ri;
        ri.symbol = rule.symbol;
        for (std::size_t e = 0; e < rule.edges.size(); ++e) {
            const auto [a, b] = group.pattern.edges[e];
            if (rule.vertices[static_cast<std::size_t>(a)].symbol || rule.vertices[static_cast<std::size_t>(b)].symbol) continue;
            if (classes[e][c] != rule.edges[e].highway) ri.edge_classes.emplace_back(static_cast<std::int32_t>(e), classes[e][c]);
        }
        level_instances.push_back(static_cast<std::int32_t>(instances_.size()));
        instances_.push_back(std::move(inst));
        encoded_.push_back(std::move(ri));
        occurrence_of_.push_back(occ);
    }
    std::vector<double> sizes;
    for (std::size_t c = instances_.size() - occs.size(); c < instances_.size(); ++c) sizes.push_back(instances_[c].fit.scale());
    std::nth_element(sizes.begin(), sizes.begin() + static_cast<long>(sizes.size() / 2), sizes.end());
    draft.rule.size_m = round_to(sizes[sizes.size() / 2], 100);
    lr.instances += occs.size();
    lr.bytes_saved += gain;
    ++lr.rules;
    rules_.push_back(std::move(draft));
    rotations_.push_back(static_cast<int>(std::max<std::size_t>(1, symmetries.size())));
    return std::nullopt;
}

double Encoder::packed_gain(const Isogroup& group, const std::vector<std::vector<VertexId>>& occs, const std::vector<Similarity2>& fits,
                            const std::vector<Frame>& transforms, const Adjacency& adj, bool strict) const {
    const Pattern& pattern = group.pattern;
    const std::size_t k = pattern.positions.size();
    // An instance at the top: its nonterminal's position and symbol, its frame (scale and
    // rotation), correction, shift and its count of links (rule points, class changes,
    // offsets and tolerances of its own are stored only where an instance has them). The
    // axiom's nonterminals are stored in runs, without an index each; pricing them a byte
    // less measured no smaller on the corpus (docs/learning.md#size), so the byte stays as slack.
    const double instance_bytes = vertex_bytes_ + 14.0;
    // A link (rule vertex and class in one number, the partner's rank) where the graph has an edge.
    const double link_bytes = 2.0;
    const double inverse = inverse_of(options_.quantum_m);
    std::size_t street_edges = 0;
    for (const auto& [a, b] : pattern.edges) street_edges += !pattern.symbols[static_cast<std::size_t>(a)] && !pattern.symbols[static_cast<std::size_t>(b)];
    double gain = 0.0;
    for (std::size_t c = 0; c < occs.size(); ++c) {
        const auto& occ = occs[c];
        double saved = static_cast<double>(street_edges) * edge_bytes_ - instance_bytes;
        std::size_t degrees = 0;
        for (std::size_t j = 0; j < k; ++j) {
            const auto v = static_cast<std::size_t>(occ[j]);
            degrees += adj.degree(occ[j]);
            saved += vertex_bytes_;
            if (pattern.symbols[j]) {
                // Its frame and symbol in the graph of this pass become the correction and the
                // shift of its instance, from the frame the rule's T_j gives it: a row of equal
                // blocks needs next to none, an irregular district as many bytes as it saves.
                const Similarity2& frame = graph_.frames[v];
                saved += cbor_bytes(std::llround(frame.scale() * axiom_scale_inverse_step)) + cbor_bytes(std::llround(frame.angle() * 180.0 / M_PI * 100.0)) + 1.0;
                const Complex correction = linear(frame) / (linear(fits[c]) * std::polar(transforms[j].scale, transforms[j].rotation_deg * M_PI / 180.0));
                saved -= cbor_bytes(std::llround((std::abs(correction) - 1.0) * 1e6)) + cbor_bytes(std::llround(std::arg(correction) * 180.0 / M_PI * 1e4));
                const Vec2 placed = options_.lossless ? graph_.positions[v] : fits[c].apply(pattern.positions[j]);
                const Vec2 shift = (frame.t - placed) * inverse;
                saved -= cbor_bytes(std::llround(shift.x())) + cbor_bytes(std::llround(shift.y()));
            }
            if (options_.lossless && strict) {
                const Vec2 r = (graph_.positions[v] - fits[c].apply(pattern.positions[j])) * inverse;
                saved -= cbor_bytes(std::llround(r.x())) + cbor_bytes(std::llround(r.y()));
            }
        }
        const double outside = static_cast<double>(degrees - 2 * pattern.edges.size());
        saved -= 0.5 * outside * (link_bytes - edge_bytes_); // each outside edge is stored by one of its two ends
        gain += saved;
    }
    // The rule: per vertex its position, symbol, count of points and the points of its
    // best-joined instance (13 bytes in all, measured on Columbus), per nonterminal vertex its
    // T_j; per edge its ends and class; its counts, size, uses and name.
    std::size_t nonterminals = 0;
    for (const Symbol s : pattern.symbols) nonterminals += s != 0;
    const double rule_bytes = 13.0 * static_cast<double>(k) + 6.0 * static_cast<double>(nonterminals) +
                              3.0 * static_cast<double>(pattern.edges.size()) + 20.0;
    return gain - (strict ? rule_bytes : 0.0);
}

double Encoder::worst_street_misfit(const Pattern& pattern, const Similarity2& fit, const std::vector<VertexId>& occ) const {
    double worst = 0.0;
    for (std::size_t j = 0; j < occ.size(); ++j) {
        if (pattern.symbols[j] != 0) continue;
        worst = std::max(worst, (fit.apply(pattern.positions[j]) - graph_.positions[static_cast<std::size_t>(occ[j])]).norm());
    }
    return worst;
}

void Encoder::choose_aligned(std::vector<std::vector<VertexId>>& occs, std::vector<Similarity2>& fits, int n) const {
    if (occs.empty()) return;
    const std::size_t k = occs.front().size();
    auto folded = [n](const Similarity2& f) { return std::pow(Complex(f.a, f.b) / f.scale(), n); };
    std::array<std::size_t, 12> sectors{};
    auto sector = [&](Complex z) { return std::min<std::size_t>(11, static_cast<std::size_t>((std::arg(z) + M_PI) / (M_PI / 6))); };
    for (const Similarity2& f : fits) ++sectors[sector(folded(f))];
    const std::size_t mode = static_cast<std::size_t>(std::max_element(sectors.begin(), sectors.end()) - sectors.begin());
    Complex direction = 0.0;
    for (const Similarity2& f : fits) {
        const std::size_t s = sector(folded(f));
        if (s == mode || s == (mode + 1) % 12 || s == (mode + 11) % 12) direction += folded(f);
    }
    std::vector<std::size_t> aligned, others;
    for (std::size_t c = 0; c < occs.size(); ++c) {
        const double turn = std::abs(std::arg(folded(fits[c]) / direction)); // in the n-fold cover
        (turn <= M_PI / 6 ? aligned : others).push_back(c);
    }
    std::vector<std::size_t> chosen;
    std::vector<char> taken(graph_.vertex_count(), 0);
    SelectionOptions quick;
    quick.prove = false;
    for (const std::vector<std::size_t>* part : {&aligned, &others}) {
        std::vector<std::size_t> free;
        for (std::size_t c : *part) {
            if (std::none_of(occs[c].begin(), occs[c].end(), [&](VertexId v) { return taken[static_cast<std::size_t>(v)]; })) free.push_back(c);
        }
        if (free.empty()) continue;
        std::vector<VertexId> flat;
        flat.reserve(free.size() * k);
        for (std::size_t c : free) flat.insert(flat.end(), occs[c].begin(), occs[c].end());
        for (std::uint32_t i : select_non_overlapping(flat, k, quick).chosen) {
            chosen.push_back(free[i]);
            for (VertexId v : occs[free[i]]) taken[static_cast<std::size_t>(v)] = 1;
        }
    }
    std::sort(chosen.begin(), chosen.end());
    std::vector<std::vector<VertexId>> kept_occs;
    std::vector<Similarity2> kept_fits;
    for (std::size_t c : chosen) {
        kept_occs.push_back(std::move(occs[c]));
        kept_fits.push_back(fits[c]);
    }
    occs = std::move(kept_occs);
    fits = std::move(kept_fits);
}

void Encoder::consistent_frames(const Isogroup& group, std::vector<std::vector<VertexId>>& chosen, std::vector<Similarity2>& fits,
                       std::vector<Frame>& transforms) const {
    const std::size_t k = group.order();
    if (chosen.empty()) return;
    std::vector<char> keep(chosen.size(), 1);
    for (std::size_t j = 0; j < k; ++j) {
        const Symbol symbol = group.pattern.symbols[j];
        if (symbol == 0) continue;
        // A nonterminal whose rule has n-fold symmetry looks the same turned by 360/n
        // degrees: frames are compared in the n-fold cover (angles times n).
        const int n = rotations_[symbol - 1];
        std::vector<Complex> relative(chosen.size());
        std::array<std::size_t, 12> sectors{};
        auto folded = [n](Complex z) { return std::pow(z / std::abs(z), n); };
        auto sector = [&](Complex z) {
            const double deg = std::arg(folded(z)) * 180.0 / M_PI + 180.0;
            return std::min<std::size_t>(11, static_cast<std::size_t>(deg / 30.0));
        };
        for (std::size_t c = 0; c < chosen.size(); ++c) {
            const VertexId v = chosen[c][j];
            relative[c] = linear(graph_.frames[static_cast<std::size_t>(v)]) / linear(fits[c]);
            ++sectors[sector(relative[c])];
        }
        const std::size_t mode = static_cast<std::size_t>(std::max_element(sectors.begin(), sectors.end()) - sectors.begin());
        Complex direction = 0.0;
        std::vector<double> scales;
        for (std::size_t c = 0; c < chosen.size(); ++c) {
            if (sector(relative[c]) != mode) continue;
            direction += folded(relative[c]);
            scales.push_back(std::abs(relative[c]));
        }
        std::nth_element(scales.begin(), scales.begin() + static_cast<long>(scales.size() / 2), scales.end());
        const Complex reference = std::polar(scales[scales.size() / 2], std::arg(direction) / n);
        transforms[j] = frame_of(reference);
        for (std::size_t c = 0; c < chosen.size(); ++c) {
            const double ratio = std::abs(relative[c]) / std::abs(reference);
            const double turn = std::abs(std::arg(folded(relative[c]) / folded(reference))) * 180.0 / M_PI / n;
            if (options_.frame_tolerance_deg > 0 &&
                (turn > options_.frame_tolerance_deg || ratio > options_.frame_scale_tolerance ||
                 ratio < 1.0 / options_.frame_scale_tolerance)) {
                keep[c] = 0;
            }
        }
    }
    std::size_t out = 0;
    for (std::size_t c = 0; c < chosen.size(); ++c) {
        if (!keep[c]) continue;
        if (out != c) chosen[out] = std::move(chosen[c]);
        fits[out] = fits[c];
        ++out;
    }
    chosen.resize(out);
    fits.resize(out);
}

} // namespace ggg::encoding_detail
