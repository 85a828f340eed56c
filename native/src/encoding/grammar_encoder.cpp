// The encoder: levels of rules from the analyzer's isogroups, then the instances' frame
// corrections, residuals and embedding against a real derivation. See grammar_encoder.hpp.
#include "ggg/encoding/grammar_encoder.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <complex>
#include <limits>
#include <unordered_map>
#include <unordered_set>

#include "ggg/encoding/decoding.hpp"
#include "ggg/error.hpp"
#include "ggg/grammar/rewriting.hpp"
#include "ggg/graph/spatial_index.hpp"
#include "ggg/analysis/isogroup_selection.hpp"
#include "ggg/analysis/non_overlapping.hpp"

namespace ggg {
namespace {

using Clock = std::chrono::steady_clock;
using Complex = std::complex<double>;

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// Rounded to a multiple of 1 / inverse_step, where inverse_step is a power of ten: the
// result is the double nearest to a short decimal, which the JSON writer prints as such.
double round_to(double x, double inverse_step) {
    double r = 0.0;
    if (inverse_step >= 1.0) {
        r = std::round(x * inverse_step) / inverse_step;
    } else {
        const double step = std::round(1.0 / inverse_step);
        r = std::round(x / step) * step;
    }
    return r == 0.0 ? 0.0 : r; // no "-0.0" in the file
}
Vec2 round_to(const Vec2& p, double inverse_step) { return {round_to(p.x(), inverse_step), round_to(p.y(), inverse_step)}; }

// The power of ten 10^k with 10^-k <= step (so rounding to it errs by at most step / 2).
double inverse_power_of_ten(double step) { return std::pow(10.0, std::ceil(-std::log10(step))); }

double round_significant(double x, int digits) {
    if (x == 0.0 || !std::isfinite(x)) return x;
    const int exponent = static_cast<int>(std::floor(std::log10(std::abs(x))));
    return round_to(x, std::pow(10.0, digits - 1 - exponent));
}

Complex linear(const Similarity2& s) { return {s.a, s.b}; }

// The distance between the two closest vertices (infinity for fewer than two).
double closest_pair_distance(const std::vector<Vec2>& positions) {
    namespace bgi = spatial::bgi;
    using Entry = std::pair<spatial::Point, std::size_t>;
    std::vector<Entry> entries;
    entries.reserve(positions.size());
    for (std::size_t i = 0; i < positions.size(); ++i) entries.emplace_back(spatial::point(positions[i]), i);
    const spatial::RTree<Entry> tree(entries.begin(), entries.end());
    double closest = std::numeric_limits<double>::infinity();
    for (const Entry& e : entries) {
        for (auto it = tree.qbegin(bgi::nearest(e.first, 2)); it != tree.qend(); ++it) {
            if (it->second != e.second) closest = std::min(closest, (positions[it->second] - positions[e.second]).norm());
        }
    }
    return closest;
}

// Frames the derivation corrects afterwards (the axiom's, the rules' T_i) need few digits;
// an instance's correction is what places it, to about 1e-7 of its size.
Frame frame_of(Complex z) { return {round_significant(std::abs(z), 4), round_to(std::arg(z) * 180.0 / M_PI, 100)}; }
Frame correction_of(Complex z) { return {round_significant(std::abs(z), 7), round_to(std::arg(z) * 180.0 / M_PI, 1e5)}; }

// A vertex of a level's graph: a street vertex of the input, or a nonterminal standing for
// an instance.
struct Node {
    bool nonterminal = false;
    std::int32_t id = 0; // input vertex, or instance
};

struct InstanceDraft {
    Symbol symbol = 0;
    std::vector<Node> members;  // per rule vertex
    Similarity2 fit;            // rule coordinates -> metres, least squares over the occurrence
    Similarity2 frame;          // the same with t = the nonterminal's position
    std::int32_t parent = -1;   // the instance whose rule placed this one's nonterminal
};

struct RuleDraft {
    Rule rule;
    int level = 0;
};

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

class Encoder {
public:
    // How the copies of a group are taken: only where the rule pays for itself (the default),
    // wherever it repeats (complete encoding, when nothing pays any more), the user's seed
    // (whatever it saves), or once (complete encoding's last rule: what never repeated).
    enum class Take { paying, repeating, seed, once };

    Encoder(const GeometricGraph& input, const LearnOptions& options, const ProgressCallback& progress)
        : input_(input), options_(options), progress_(progress) {}

    LearnResult run() {
        const auto start = Clock::now();
        start_ = start;
        start_level_graph();
        const int max_levels = options_.max_levels > 0 ? options_.max_levels : 1'000'000;
        int level = 1;
        if (!options_.seed.empty()) encode_level(level++, true);
        for (; level <= max_levels; ++level) {
            // Complete encoding: where nothing pays any more, whatever still repeats keeps the
            // encoding going (smaller patterns, down to a pair of vertices).
            if (!encode_level(level, false) && !(options_.complete && !result_.stopped_by_budget && encode_level(level, false, Take::repeating))) break;
            if (result_.stopped_by_budget) break;
        }
        // ... and what never repeated becomes one rule, used once: the axiom is one vertex.
        if (options_.complete && graph_.vertex_count() > 1) encode_rest(level);
        report(progress_, 0.92, "building the grammar");
        result_.axiom_edges = graph_.edge_count();
        Grammar grammar = build_grammar();
        report(progress_, 0.94, "computing each instance's frame and residuals");
        simulate(grammar);
        report(progress_, 0.97, "joining the instances to their streets");
        embed(grammar);
        result_.grammar = std::move(grammar);
        report(progress_, 0.98, "decoding the grammar to check it");
        check_roundtrip();
        result_.encoding_seconds = seconds_since(start) - result_.analysis_seconds;
        report(progress_, 1.0, "done");
        return std::move(result_);
    }

private:
    void start_level_graph() {
        graph_.origin = input_.origin;
        graph_.reserve(input_.vertex_count(), input_.edge_count(), 2 * input_.edge_count());
        for (std::size_t v = 0; v < input_.vertex_count(); ++v) {
            graph_.add_vertex(input_.positions[v]);
            nodes_.push_back({false, static_cast<std::int32_t>(v)});
        }
        for (std::size_t e = 0; e < input_.edge_count(); ++e) {
            EdgeAttributes a;
            a.highway = input_.edge_highway[e];
            graph_.add_edge(input_.edges[e][0], input_.edges[e][1], a);
        }
    }

    Vec2 node_position(const Node& n) const {
        return n.nonterminal ? instances_[static_cast<std::size_t>(n.id)].frame.t : input_.positions[static_cast<std::size_t>(n.id)];
    }

    // One level: analyse, take the groups that pay, contract their occurrences. False when
    // nothing was encoded.
    bool encode_level(int level, bool seeded, Take take = Take::paying) {
        if (graph_.edge_count() == 0) return false;
        const auto level_start = Clock::now();
        // Each level takes half of what is left of the first 90 %: the count of levels is not
        // known in advance, and the first levels, on the largest graphs, take longest.
        const double done = progress_done_;
        const double share = (0.9 - done) * 0.5;
        progress_done_ += share;
        ProgressCallback stage;
        if (progress_) {
            const std::string prefix = "level " + std::to_string(level) + ": ";
            stage = [&, prefix](double f, std::string_view message) { return progress_(done + share * f, prefix + std::string(message)); };
        }
        report(stage, 0.0, "analysing " + std::to_string(graph_.vertex_count()) + " vertices");
        const auto analysis_start = Clock::now();
        AnalyzeOptions analysis_options = options_.analysis;
        if (seeded) analysis_options.seed = options_.seed;
        // The analysis budget is the whole learning's: each level gets what is left of it.
        if (const double budget = time_budget_seconds(options_.analysis.detection); budget > 0) {
            const double left = budget - seconds_since(start_);
            if (left <= 0) {
                result_.stopped_by_budget = true;
                return false;
            }
            analysis_options.detection.max_seconds = left;
        }
        const Analysis analysis = analyze(graph_, analysis_options, stage);
        result_.analysis_seconds += seconds_since(analysis_start);
        if (analysis.stopped_by_budget) result_.stopped_by_budget = true;

        const Adjacency adj(graph_);
        std::vector<char> used(graph_.vertex_count(), 0);
        std::vector<std::int32_t> level_instances;
        LevelReport lr;
        lr.level = level;
        lr.vertices = graph_.vertex_count();
        lr.edges = graph_.edge_count();
        for (const AnalyzedIsogroup& ag : analysis.isogroups) {
            if (seeded && &ag != &analysis.isogroups.front()) break; // the seed's own group only
            // Ranked by gain: nothing after the first group that does not pay pays either.
            if (!seeded && take == Take::paying && ag.selection.gain <= 0) break;
            if (ag.group.order() < 2 || ag.group.pattern.edges.empty()) continue;
            if (ag.selection.non_overlapping.size() < options_.analysis.detection.min_count) continue;
            encode_group(ag.group, seeded ? Take::seed : take, level, adj, used, level_instances, lr);
        }
        if (level_instances.empty()) {
            if (seeded) lr.seconds = seconds_since(level_start), result_.levels.push_back(lr);
            return false;
        }
        contract(level_instances, used);
        occurrence_of_.clear();
        lr.seconds = seconds_since(level_start);
        result_.levels.push_back(lr);
        return true;
    }

    // Complete encoding's last level: the whole graph left becomes the right side of one rule
    // used once, and the axiom its single nonterminal.
    void encode_rest(int level) {
        const auto level_start = Clock::now();
        const Adjacency adj(graph_);
        std::vector<VertexId> all(graph_.vertex_count());
        for (std::size_t v = 0; v < all.size(); ++v) all[v] = static_cast<VertexId>(v);
        Similarity2 frame;
        Isogroup rest;
        rest.pattern = induced_pattern(graph_, adj, all, &frame);
        rest.vertices = all;
        rest.transforms.push_back(frame);
        LevelReport lr;
        lr.level = level;
        lr.vertices = graph_.vertex_count();
        lr.edges = graph_.edge_count();
        std::vector<char> used(graph_.vertex_count(), 0);
        std::vector<std::int32_t> level_instances;
        encode_group(rest, Take::once, level, adj, used, level_instances, lr);
        if (level_instances.empty()) return;
        contract(level_instances, used);
        occurrence_of_.clear();
        lr.seconds = seconds_since(level_start);
        result_.levels.push_back(lr);
    }

    // Makes a rule of `group` from those of its occurrences that are free, fit its shape and
    // sit in consistent frames, and records an instance for each; nothing when too few are
    // left (or, paying, when they no longer pay).
    void encode_group(const Isogroup& group, Take take, int level, const Adjacency& adj, std::vector<char>& used,
                      std::vector<std::int32_t>& level_instances, LevelReport& lr) {
        const std::size_t k = group.order();
        const std::size_t min_count = take == Take::once ? 1 : options_.analysis.detection.min_count;
        std::vector<std::vector<VertexId>> occs;
        for (std::size_t o = 0; o < group.frequency(); ++o) {
            const auto occ = group.occurrence(o);
            if (std::none_of(occ.begin(), occ.end(), [&](VertexId v) { return used[static_cast<std::size_t>(v)]; })) {
                occs.emplace_back(occ.begin(), occ.end());
            }
        }
        if (occs.size() < min_count) return;

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
            if (options_.max_vertex_error_m > 0 && worst_street_misfit(group.pattern, best.transform, labelled) > options_.max_vertex_error_m) {
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
        if (occs.size() < min_count) return;
        std::vector<Frame> transforms(k);
        const std::size_t before = occs.size();
        consistent_frames(group, occs, fits, transforms);
        lr.frame_rejected += before - occs.size();
        if (occs.size() < min_count) return;
        std::size_t outside = 0;
        for (const auto& occ : occs) {
            std::size_t degrees = 0;
            for (VertexId v : occ) degrees += adj.degree(v);
            outside += degrees - 2 * group.pattern.edges.size();
        }
        if (take == Take::paying && description_gain(k, group.pattern.edges.size(), occs.size(), outside) <= 0) return;

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
            rv.position = round_to(group.pattern.positions[j] - origin, 1e7);
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
        draft.rule.size_m = round_significant(sizes[sizes.size() / 2], 4);
        lr.instances += occs.size();
        ++lr.rules;
        rules_.push_back(std::move(draft));
        rotations_.push_back(static_cast<int>(std::max<std::size_t>(1, symmetries.size())));
    }

    // The largest distance from a street vertex of the occurrence (labelled as the pattern)
    // to where `fit` puts the pattern's vertex: the vertex's paper-mode decoding error.
    // Nonterminals are left out, since their instances correct their own frames.
    double worst_street_misfit(const Pattern& pattern, const Similarity2& fit, const std::vector<VertexId>& occ) const {
        double worst = 0.0;
        for (std::size_t j = 0; j < occ.size(); ++j) {
            if (pattern.symbols[j] != 0) continue;
            worst = std::max(worst, (fit.apply(pattern.positions[j]) - graph_.positions[static_cast<std::size_t>(occ[j])]).norm());
        }
        return worst;
    }

    // The occurrences to encode: a largest set that shares no vertex, taken first among the
    // occurrences turned like most of them (modulo the pattern's n-fold symmetry), then among
    // the others. A district tiled by copies that all face one way is regular again one
    // level up, where a tiling of mixed orientations is not.
    void choose_aligned(std::vector<std::vector<VertexId>>& occs, std::vector<Similarity2>& fits, int n) const {
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

    // Keeps the occurrences whose nonterminals sit in the pattern's usual frame, and sets
    // the rule's transform T_i of each nonterminal vertex to that frame (the mean over the
    // occurrences in the most common 30-degree sector).
    void consistent_frames(const Isogroup& group, std::vector<std::vector<VertexId>>& chosen, std::vector<Similarity2>& fits,
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

    // The next level's graph: every occurrence replaced by its nonterminal, joined to what
    // the occurrence was joined to (the most important class where several streets merge).
    void contract(const std::vector<std::int32_t>& level_instances, const std::vector<char>& used) {
        GeometricGraph next;
        next.origin = graph_.origin;
        std::vector<Node> next_nodes;
        std::vector<VertexId> new_id(graph_.vertex_count(), -1);
        for (std::size_t v = 0; v < graph_.vertex_count(); ++v) {
            if (used[v]) continue;
            new_id[v] = next.add_vertex(graph_.positions[v]);
            next.symbols.back() = graph_.symbols[v];
            next.frames.back() = graph_.frames[v];
            next_nodes.push_back(nodes_[v]);
        }
        for (std::size_t i = 0; i < level_instances.size(); ++i) {
            const auto id = static_cast<std::size_t>(level_instances[i]);
            const InstanceDraft& inst = instances_[id];
            const VertexId n = next.add_vertex(inst.frame.t);
            next.symbols.back() = inst.symbol;
            next.frames.back() = inst.frame;
            next_nodes.push_back({true, static_cast<std::int32_t>(id)});
            for (VertexId v : occurrence_of_[i]) new_id[static_cast<std::size_t>(v)] = n;
        }
        std::unordered_map<std::uint64_t, EdgeId> seen;
        seen.reserve(graph_.edge_count());
        for (std::size_t e = 0; e < graph_.edge_count(); ++e) {
            const VertexId a = new_id[static_cast<std::size_t>(graph_.edges[e][0])];
            const VertexId b = new_id[static_cast<std::size_t>(graph_.edges[e][1])];
            if (a == b) continue;
            const std::uint64_t key = static_cast<std::uint64_t>(std::min(a, b)) << 32 | static_cast<std::uint32_t>(std::max(a, b));
            const auto [it, inserted] = seen.emplace(key, static_cast<EdgeId>(next.edge_count()));
            if (inserted) {
                EdgeAttributes attributes;
                attributes.highway = graph_.edge_highway[e];
                next.add_edge(a, b, attributes);
            } else if (highway_rank(graph_.edge_highway[e]) < highway_rank(next.edge_highway[static_cast<std::size_t>(it->second)])) {
                next.edge_highway[static_cast<std::size_t>(it->second)] = graph_.edge_highway[e];
            }
        }
        graph_ = std::move(next);
        nodes_ = std::move(next_nodes);
    }

    // Rules, the axiom (the last level's graph) and the instance skeletons.
    Grammar build_grammar() {
        Grammar g;
        g.name = "learned";
        g.origin = input_.origin;
        for (RuleDraft& r : rules_) {
            g.symbol_names.push_back("R" + std::to_string(r.rule.symbol));
            g.rules.push_back(std::move(r.rule));
        }
        Encoding& enc = g.encoding;
        enc.mode = options_.lossless ? "lossless" : "paper";
        // Levels of hierarchy: how deep instances nest, so the derivation steps that decode
        // the axiom (a pass of the analysis may add rules of street vertices only).
        int depth = 0;
        for (const InstanceDraft& d : instances_) {
            int n = 1;
            for (std::int32_t p = d.parent; p >= 0; p = instances_[static_cast<std::size_t>(p)].parent) ++n;
            depth = std::max(depth, n);
        }
        enc.levels = depth;
        enc.quantum_m = options_.quantum_m;
        // Decoding finds embedding partners and merges vertices within this distance: well
        // below the closest two input vertices, well above the rounding of what is stored.
        const double closest = closest_pair_distance(input_.positions);
        enc.tolerance_m = std::max(round_significant(0.25 * closest, 1), 100 * options_.quantum_m);
        // In paper mode vertices decode away from where they were, possibly towards each
        // other: the shared tolerance stays small, and each instance gets the room its
        // decoded surroundings leave (embed).
        if (!options_.lossless) enc.tolerance_m = std::min(enc.tolerance_m, std::max(1e-3, 100 * options_.quantum_m));
        placer_.assign(input_.vertex_count(), -1);
        axiom_index_.assign(input_.vertex_count(), -1);
        for (std::size_t i = 0; i < instances_.size(); ++i) {
            RuleInstance& ri = encoded_[i];
            const InstanceDraft& d = instances_[i];
            bool any_child = false;
            for (const Node& n : d.members) any_child |= n.nonterminal;
            for (std::size_t j = 0; j < d.members.size(); ++j) {
                const Node& n = d.members[j];
                if (any_child) ri.children.push_back(n.nonterminal ? n.id : -1);
                if (!n.nonterminal) placer_[static_cast<std::size_t>(n.id)] = static_cast<std::int32_t>(i);
            }
        }
        bool any_instance = false;
        for (std::size_t v = 0; v < graph_.vertex_count(); ++v) {
            const Node& n = nodes_[v];
            AxiomVertex av;
            av.position = round_to(graph_.positions[v], 1.0 / options_.quantum_m);
            av.symbol = graph_.symbols[v];
            if (n.nonterminal) av.frame = frame_of(linear(graph_.frames[v]));
            else axiom_index_[static_cast<std::size_t>(n.id)] = static_cast<std::int32_t>(v);
            g.axiom_vertices.push_back(av);
            enc.axiom_instances.push_back(n.nonterminal ? n.id : -1);
            any_instance |= n.nonterminal;
        }
        if (!any_instance) enc.axiom_instances.clear();
        for (std::size_t e = 0; e < input_.edge_count(); ++e) {
            const auto [u, v] = input_.edges[e];
            const std::int32_t a = axiom_index_[static_cast<std::size_t>(u)], b = axiom_index_[static_cast<std::size_t>(v)];
            if (a >= 0 && b >= 0) g.axiom_edges.push_back({a, b, input_.edge_highway[e]});
        }
        enc.instances = std::move(encoded_);
        return g;
    }

    // Derives the grammar level by level, as decoding will, and sets each instance's frame
    // correction (and residuals) against the frame the derivation hands it. Records where
    // every input vertex lands.
    void simulate(Grammar& grammar) {
        Encoding& enc = grammar.encoding;
        const double inverse_quantum = 1.0 / options_.quantum_m;
        decoded_.assign(input_.vertex_count(), Vec2::Zero());
        placed_.assign(input_.vertex_count(), 0);
        effective_.assign(instances_.size(), Similarity2{});
        for (std::size_t v = 0; v < input_.vertex_count(); ++v) {
            if (axiom_index_[v] >= 0) {
                decoded_[v] = grammar.axiom_vertices[static_cast<std::size_t>(axiom_index_[v])].position;
                placed_[v] = 1;
            }
        }
        GeometricGraph g = grammar.axiom_graph();
        const DeriveOptions derive_options = decode_options(grammar);
        step_nonterminals_.assign(1, {});
        for (std::size_t v = 0; v < g.vertex_count(); ++v) {
            if (g.symbols[v]) step_nonterminals_[0].push_back(g.positions[v]);
        }
        for (int step = 0; step < enc.levels; ++step) {
            for (std::size_t q = 0; q < g.vertex_count(); ++q) {
                const std::int32_t id = g.instance_of(static_cast<VertexId>(q));
                if (id < 0) continue;
                RuleInstance& ri = enc.instances[static_cast<std::size_t>(id)];
                const InstanceDraft& d = instances_[static_cast<std::size_t>(id)];
                ri.correction = correction_of(linear(d.fit) / linear(g.frames[q]));
                Similarity2 effective = g.frames[q] * ri.correction.at(Vec2::Zero());
                ri.shift = round_to(d.fit.t - effective.t, inverse_quantum);
                effective.t += ri.shift;
                effective_[static_cast<std::size_t>(id)] = effective;
                if (!options_.lossless) continue;
                const Rule& rule = *grammar.rule_for(ri.symbol);
                ri.residuals.resize(rule.vertices.size());
                for (std::size_t j = 0; j < rule.vertices.size(); ++j) {
                    ri.residuals[j] = round_to(node_position(d.members[j]) - effective.apply(rule.vertices[j].position), inverse_quantum);
                }
            }
            std::vector<VertexId> source;
            std::vector<Placement> placed;
            if (!derive_step(g, grammar, derive_options, nullptr, nullptr, &source, &placed)) break;
            step_nonterminals_.emplace_back();
            for (std::size_t v = 0; v < placed.size(); ++v) {
                const Placement& p = placed[v];
                if (p.instance < 0) continue;
                if (g.symbols[v]) step_nonterminals_.back().push_back(g.positions[v]);
                const Node& n = instances_[static_cast<std::size_t>(p.instance)].members[static_cast<std::size_t>(p.rule_vertex)];
                if (n.nonterminal) continue;
                decoded_[static_cast<std::size_t>(n.id)] = g.positions[v];
                placed_[static_cast<std::size_t>(n.id)] = 1;
            }
        }
        for (std::size_t v = 0; v < input_.vertex_count(); ++v) {
            if (!placed_[v]) decoded_[v] = input_.positions[v]; // merged into another vertex (paper mode)
        }
    }

    // Every input edge that is neither a rule edge nor an axiom edge becomes an embedding
    // point of one of its ends, aimed at where the derivation puts the other end.
    void embed(Grammar& grammar) {
        Encoding& enc = grammar.encoding;
        // The step in which each instance is rewritten: its depth below the axiom.
        std::vector<int> depth(instances_.size(), -1);
        for (std::size_t i = 0; i < instances_.size(); ++i) {
            int d = 0;
            for (std::int32_t p = instances_[i].parent; p >= 0; p = instances_[static_cast<std::size_t>(p)].parent) ++d;
            depth[i] = d;
        }
        auto step_of = [&](VertexId v) { // when the vertex appears: -1 for the axiom's
            const std::int32_t p = placer_[static_cast<std::size_t>(v)];
            return p < 0 ? -1 : depth[static_cast<std::size_t>(p)];
        };
        struct RawLink {
            std::int32_t vertex;
            VertexId x, y;
            HighwayClass highway;
        };
        std::vector<std::vector<RawLink>> raw(instances_.size());
        for (std::size_t e = 0; e < input_.edge_count(); ++e) {
            // The end that appears last carries the point (the other is there by then); on a
            // tie, the first end. An edge between two axiom vertices is an axiom edge.
            VertexId x = input_.edges[e][0];
            VertexId y = input_.edges[e][1];
            if (step_of(y) > step_of(x)) std::swap(x, y);
            const std::int32_t inst = placer_[static_cast<std::size_t>(x)];
            if (inst < 0 || placer_[static_cast<std::size_t>(y)] == inst) continue; // axiom edge, or a rule edge
            const InstanceDraft& d = instances_[static_cast<std::size_t>(inst)];
            std::int32_t j = 0;
            while (d.members[static_cast<std::size_t>(j)].nonterminal || d.members[static_cast<std::size_t>(j)].id != x) ++j;
            raw[static_cast<std::size_t>(inst)].push_back({j, x, y, input_.edge_highway[e]});
        }
        auto offset_of = [&](std::size_t inst, const RawLink& l) {
            return effective_[inst].inverse().apply_linear(decoded_[static_cast<std::size_t>(l.y)] - decoded_[static_cast<std::size_t>(l.x)]);
        };
        // Each rule's own embedding (for placing it by hand, and for its instances to reuse):
        // that of its best-joined instance.
        std::vector<std::int32_t> best(grammar.rules.size(), -1);
        for (std::size_t i = 0; i < raw.size(); ++i) {
            const std::size_t r = enc.instances[i].symbol - 1;
            if (best[r] < 0 || raw[i].size() > raw[static_cast<std::size_t>(best[r])].size()) best[r] = static_cast<std::int32_t>(i);
        }
        std::vector<std::vector<std::pair<std::int32_t, EmbeddingPoint>>> rule_points(grammar.rules.size());
        for (std::size_t r = 0; r < grammar.rules.size(); ++r) {
            if (best[r] < 0) continue;
            std::vector<RawLink> links = raw[static_cast<std::size_t>(best[r])];
            std::stable_sort(links.begin(), links.end(), [](const RawLink& a, const RawLink& b) { return a.vertex < b.vertex; });
            for (const RawLink& l : links) {
                EmbeddingPoint ep{round_to(offset_of(static_cast<std::size_t>(best[r]), l), 1e4), l.highway};
                grammar.rules[r].vertices[static_cast<std::size_t>(l.vertex)].embedding.push_back(ep);
                rule_points[r].emplace_back(l.vertex, ep);
            }
        }
        // How far apart things are around each place when an instance's embedding is
        // resolved, in the step that rewrites it: the streets placed by then (counted all,
        // which only errs on the safe side) and the nonterminals that step places.
        namespace bg = spatial::bg;
        namespace bgi = spatial::bgi;
        using Tree = spatial::RTree<spatial::Point>;
        auto tree_of = [](const std::vector<Vec2>& positions) {
            std::vector<spatial::Point> points;
            points.reserve(positions.size());
            for (const Vec2& p : positions) points.push_back(spatial::point(p));
            return Tree(points.begin(), points.end());
        };
        const Tree streets = tree_of(decoded_);
        std::vector<Tree> nonterminals;
        for (const auto& positions : step_nonterminals_) nonterminals.push_back(tree_of(positions));
        const double same_place = 10 * options_.quantum_m;
        auto nearest_other = [&](const Tree& tree, const Vec2& p) {
            for (auto it = tree.qbegin(bgi::nearest(spatial::point(p), 2)); it != tree.qend(); ++it) {
                const double d = std::hypot(bg::get<0>(*it) - p.x(), bg::get<1>(*it) - p.y());
                if (d > same_place) return d; // nearest first; a nearer one is the vertex itself
            }
            return std::numeric_limits<double>::infinity();
        };
        auto room = [&](const Vec2& p, int step) {
            const double d = nearest_other(streets, p);
            const auto s = static_cast<std::size_t>(step);
            return s < nonterminals.size() ? std::min(d, nearest_other(nonterminals[s], p)) : d;
        };
        for (std::size_t i = 0; i < raw.size(); ++i) {
            RuleInstance& ri = enc.instances[i];
            // Half the room around the instance's partners: an embedding point that lands
            // within half the tolerance of its partner has no other vertex nearer (the
            // instance's own vertices never merge, see derive_step).
            double r = std::numeric_limits<double>::infinity();
            for (const RawLink& l : raw[i]) r = std::min(r, room(decoded_[static_cast<std::size_t>(l.y)], depth[i] + 1));
            const double half = 0.5 * r;
            double tolerance = enc.tolerance_m;
            if (std::isfinite(half) && half > enc.tolerance_m) {
                const double unit = std::pow(10.0, std::floor(std::log10(half)));
                tolerance = std::floor(half / unit) * unit; // rounded down to one digit
            }
            if (tolerance > enc.tolerance_m) ri.tolerance_m = tolerance;
            const Similarity2& f = effective_[i];
            const auto& shared = rule_points[ri.symbol - 1];
            std::vector<char> taken(shared.size(), 0);
            for (const RawLink& l : raw[i]) {
                const Vec2 partner = decoded_[static_cast<std::size_t>(l.y)];
                bool reused = false;
                for (std::size_t p = 0; p < shared.size() && !reused; ++p) {
                    if (taken[p] || shared[p].first != l.vertex || shared[p].second.highway != l.highway) continue;
                    const Vec2 target = decoded_[static_cast<std::size_t>(l.x)] + f.apply_linear(shared[p].second.offset);
                    if ((target - partner).norm() <= 0.5 * tolerance) {
                        taken[p] = 1;
                        ri.rule_points.push_back(static_cast<std::int32_t>(p));
                        reused = true;
                    }
                }
                if (reused) continue;
                // Rounded so that the point errs by at most a twentieth of the tolerance.
                const double inverse_step = inverse_power_of_ten(tolerance / (20.0 * f.scale()));
                RuleInstance::Link link;
                link.vertex = l.vertex;
                link.point.offset = round_to(offset_of(i, l), inverse_step);
                link.point.highway = l.highway;
                ri.embedding.push_back(link);
            }
            std::sort(ri.rule_points.begin(), ri.rule_points.end());
        }
    }

    void check_roundtrip() {
        const Grammar& grammar = result_.grammar;
        DeriveReport report;
        const GeometricGraph decoded = decode_grammar(grammar, &report);
        result_.grammar.encoding.decoded_vertices = static_cast<std::int64_t>(decoded.vertex_count());
        result_.grammar.encoding.decoded_edges = static_cast<std::int64_t>(decoded.edge_count());
        std::vector<std::int32_t> original(decoded.vertex_count(), -1);
        std::vector<std::int32_t> axiom_vertex(grammar.axiom_vertices.size(), -1);
        for (std::size_t v = 0; v < input_.vertex_count(); ++v) {
            if (axiom_index_[v] >= 0) axiom_vertex[static_cast<std::size_t>(axiom_index_[v])] = static_cast<std::int32_t>(v);
        }
        for (std::size_t v = 0; v < decoded.vertex_count(); ++v) {
            const Placement& p = report.placed_by[v];
            if (p.instance >= 0) {
                const Node& n = instances_[static_cast<std::size_t>(p.instance)].members[static_cast<std::size_t>(p.rule_vertex)];
                if (!n.nonterminal) original[v] = n.id;
            } else if (report.source_vertex[v] >= 0) {
                original[v] = axiom_vertex[static_cast<std::size_t>(report.source_vertex[v])];
            }
        }
        RoundTrip& rt = result_.roundtrip;
        std::vector<char> seen(input_.vertex_count(), 0);
        double sum = 0.0;
        for (std::size_t v = 0; v < decoded.vertex_count(); ++v) {
            if (original[v] < 0) continue;
            const double d = (decoded.positions[v] - input_.positions[static_cast<std::size_t>(original[v])]).norm();
            rt.max_displacement_m = std::max(rt.max_displacement_m, d);
            sum += d;
            seen[static_cast<std::size_t>(original[v])] = 1;
        }
        rt.unplaced_vertices = static_cast<std::size_t>(std::count(seen.begin(), seen.end(), 0));
        const std::size_t matched = input_.vertex_count() - rt.unplaced_vertices;
        rt.mean_displacement_m = matched ? sum / static_cast<double>(matched) : 0.0;
        auto key = [](std::int64_t a, std::int64_t b) { return static_cast<std::uint64_t>(std::min(a, b)) << 32 | static_cast<std::uint64_t>(std::max(a, b)); };
        std::unordered_map<std::uint64_t, HighwayClass> expected;
        for (std::size_t e = 0; e < input_.edge_count(); ++e) expected.emplace(key(input_.edges[e][0], input_.edges[e][1]), input_.edge_highway[e]);
        std::unordered_set<std::uint64_t> found;
        bool classes = true;
        for (std::size_t e = 0; e < decoded.edge_count(); ++e) {
            const std::int32_t a = original[static_cast<std::size_t>(decoded.edges[e][0])];
            const std::int32_t b = original[static_cast<std::size_t>(decoded.edges[e][1])];
            const auto it = a >= 0 && b >= 0 ? expected.find(key(a, b)) : expected.end();
            if (it == expected.end()) {
                ++rt.extra_edges;
                continue;
            }
            found.insert(it->first);
            classes &= it->second == decoded.edge_highway[e];
        }
        rt.missing_edges = expected.size() - found.size();
        rt.edges_equal = rt.missing_edges == 0 && rt.extra_edges == 0 && decoded.edge_count() == input_.edge_count() &&
                         rt.unplaced_vertices == 0 && decoded.vertex_count() == input_.vertex_count();
        rt.classes_equal = rt.edges_equal && classes;
    }

    const GeometricGraph& input_;
    Clock::time_point start_;
    const LearnOptions& options_;
    IsomorphismOptions symmetry_options_ = [this] {
        IsomorphismOptions o;
        o.tolerance = options_.analysis.detection.merge_tolerance;
        return o;
    }();
    const ProgressCallback& progress_;
    LearnResult result_;
    double progress_done_ = 0.0;

    GeometricGraph graph_;   // the current level's graph
    std::vector<Node> nodes_; // per vertex of graph_
    std::vector<InstanceDraft> instances_;
    std::vector<RuleInstance> encoded_; // per instance: what goes into the grammar
    std::vector<std::vector<VertexId>> occurrence_of_; // this level's instances: vertices of graph_
    std::vector<RuleDraft> rules_;
    std::vector<int> rotations_; // per rule: the rotations that map its pattern onto itself
    std::vector<std::int32_t> placer_;      // per input vertex: the instance placing it, -1 = the axiom
    std::vector<std::int32_t> axiom_index_; // per input vertex: its axiom vertex, -1 = none
    std::vector<Vec2> decoded_;             // per input vertex: where the derivation puts it
    std::vector<char> placed_;
    std::vector<Similarity2> effective_;    // per instance: the frame its rule is placed in
    std::vector<std::vector<Vec2>> step_nonterminals_; // per derivation step (0 = the axiom): the nonterminals it places
};

} // namespace

void check_options(const LearnOptions& o) {
    check_options(o.analysis);
    if (!o.analysis.seed.empty()) throw UsageError("learning analyses the whole graph: it takes no seed");
    if (o.max_levels < 0) throw UsageError("levels: the number of levels must be >= 0 (0 = until nothing repeats)");
    const double exponent = std::log10(o.quantum_m);
    if (!(o.quantum_m >= 1e-9 && o.quantum_m <= 1e-3) || std::abs(exponent - std::round(exponent)) > 1e-9) {
        throw UsageError("the quantum must be a power of ten between 1e-9 and 1e-3 m");
    }
    if (!(o.max_shape_error >= 0) || !std::isfinite(o.max_shape_error)) throw UsageError("max_shape_error: the shape error must be a finite number >= 0");
    if (!(o.max_vertex_error_m >= 0) || !std::isfinite(o.max_vertex_error_m)) throw UsageError("max_vertex_error_m: the vertex error must be a finite number of metres >= 0");
    if (!(o.frame_tolerance_deg >= 0) || !(o.frame_scale_tolerance >= 1) || !std::isfinite(o.frame_scale_tolerance)) {
        throw UsageError("the frame tolerance must be >= 0 degrees and the scale tolerance a finite factor >= 1");
    }
}

LearnResult learn_grammar(const GeometricGraph& graph, const LearnOptions& options, const ProgressCallback& progress) {
    check_options(options);
    if (graph.edge_count() == 0) throw InputError("the graph has no streets to learn from");
    for (VertexId v : options.seed) {
        if (v < 0 || static_cast<std::size_t>(v) >= graph.vertex_count()) throw UsageError("a seed vertex is out of range");
    }
    return Encoder(graph, options, progress).run();
}

} // namespace ggg
