#include "ggg/grammar/rewriting.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_map>
#include <unordered_set>


#include "ggg/error.hpp"
#include "ggg/graph/spatial_index.hpp"

namespace ggg {
namespace {

namespace bgi = spatial::bgi;
using Entry = spatial::VertexEntry;

bool same_frame(const Similarity2& a, const Similarity2& b, double tolerance) {
    const double scale = std::max(a.scale(), b.scale());
    return std::abs(a.a - b.a) <= 1e-9 * scale && std::abs(a.b - b.b) <= 1e-9 * scale && (a.t - b.t).norm() <= tolerance;
}

std::uint64_t edge_key(VertexId u, VertexId v) {
    const auto lo = static_cast<std::uint32_t>(std::min(u, v));
    const auto hi = static_cast<std::uint32_t>(std::max(u, v));
    return (static_cast<std::uint64_t>(lo) << 32) | hi;
}

// The graph being built by one step: survivors first, then what the rewrites place.
class StepBuilder {
public:
    StepBuilder(const GeometricGraph& old, const std::vector<char>& erased) : old_(old) {
        next_.origin = old.origin;
        new_id_.assign(old.vertex_count(), -1);
        for (std::size_t v = 0; v < old.vertex_count(); ++v) {
            if (erased[v]) continue;
            const VertexId id = next_.add_vertex(old.positions[v], old.vertex_osm_ids[v]);
            next_.symbols.back() = old.symbols[v];
            next_.frames.back() = old.frames[v];
            copy_more_rewrites(old, static_cast<VertexId>(v), next_, id);
            instances_.push_back(old.instance_of(static_cast<VertexId>(v)));
            new_id_[v] = id;
            index(id);
        }
        for (std::size_t e = 0; e < old.edge_count(); ++e) {
            const auto [u, v] = old.edges[e];
            const VertexId a = new_id_[static_cast<std::size_t>(u)];
            const VertexId b = new_id_[static_cast<std::size_t>(v)];
            if (a < 0 || b < 0) continue;
            const EdgeId id = static_cast<EdgeId>(e);
            std::vector<Vec2> line(old.geometry_begin(id), old.geometry_begin(id) + old.geometry_size(id));
            add_edge(a, b, old.edge_attributes(id), line);
        }
        survivors_ = static_cast<VertexId>(next_.vertex_count());
    }

    VertexId survivor_count() const { return survivors_; }

    // Old vertex of each vertex of the graph being built (-1 for placed ones).
    std::vector<VertexId> sources() const {
        std::vector<VertexId> out(next_.vertex_count(), -1);
        for (std::size_t v = 0; v < new_id_.size(); ++v) {
            if (new_id_[v] >= 0) out[static_cast<std::size_t>(new_id_[v])] = static_cast<VertexId>(v);
        }
        return out;
    }

    // The nearest vertex within `tolerance` of p that passes `accept`, or -1.
    template <typename Accept>
    VertexId nearest(const Vec2& p, double tolerance, Accept accept) const {
        if (tolerance < 0) return -1;
        const spatial::Box box = spatial::around(p, tolerance);
        VertexId best = -1;
        double best_distance = tolerance;
        for (auto it = tree_.qbegin(bgi::intersects(box)); it != tree_.qend(); ++it) {
            const VertexId v = it->second;
            const double d = (next_.positions[static_cast<std::size_t>(v)] - p).norm();
            if (d <= best_distance && accept(v) && (best < 0 || d < best_distance || v < best)) {
                best = v;
                best_distance = d;
            }
        }
        return best;
    }

    // The `rank`-th nearest vertex to p (from 0) among those that pass `accept`, or -1.
    // Nearness is the squared distance, as the learner measures it when it names a rank
    // (grammar_assembly.cpp), which it does only where no other vertex is as near as the
    // partner: ties never decide. A rank is at most RuleInstance::max_rank (validate), so the
    // search stays small.
    template <typename Accept>
    VertexId ranked(const Vec2& p, std::size_t rank, Accept accept) const {
        const std::size_t k = std::min(rank + 2, next_.vertex_count());
        std::vector<std::pair<double, VertexId>> found;
        found.reserve(k);
        const auto query = bgi::nearest(spatial::point(p), static_cast<unsigned>(k)) && bgi::satisfies([&](const Entry& e) { return accept(e.second); });
        for (auto it = tree_.qbegin(query); it != tree_.qend(); ++it) {
            found.emplace_back((next_.positions[static_cast<std::size_t>(it->second)] - p).squaredNorm(), it->second);
        }
        if (found.size() <= rank) return -1;
        std::nth_element(found.begin(), found.begin() + static_cast<std::ptrdiff_t>(rank), found.end());
        return found[rank].second;
    }

    // Places a vertex, merging it into one within `tolerance` when that is the same place:
    // one vertex per place. A nonterminal that lands on another with a different rewrite
    // becomes one more rewrite pending there. Vertices of learned instances never merge with
    // other nonterminals (their decoding depends on each keeping its own vertex).
    VertexId place(const Vec2& p, Symbol symbol, const Similarity2& frame, std::int32_t instance, double tolerance, bool& merged) {
        const VertexId existing = nearest(p, tolerance, [&](VertexId v) {
            const Symbol s = next_.symbols[static_cast<std::size_t>(v)];
            if (s == 0 || symbol == 0) return true;
            const std::int32_t there = instances_[static_cast<std::size_t>(v)];
            return there == instance && (instance < 0 || (s == symbol && same_frame(next_.frames[static_cast<std::size_t>(v)], frame, tolerance)));
        });
        if (existing >= 0) {
            merged = true;
            const auto e = static_cast<std::size_t>(existing);
            if (symbol != 0 && next_.symbols[e] == 0) {
                next_.symbols[e] = symbol;
                next_.frames[e] = frame;
                instances_[e] = instance;
            } else if (symbol != 0 && !pending_at(existing, symbol, frame, tolerance)) {
                added_at_.emplace(existing, added_rewrites_.size());
                added_rewrites_.push_back({existing, symbol, frame});
            }
            return existing;
        }
        merged = false;
        const VertexId id = next_.add_vertex(p);
        next_.symbols.back() = symbol;
        next_.frames.back() = frame;
        instances_.push_back(instance);
        index(id);
        return id;
    }

    bool add_edge(VertexId a, VertexId b, const EdgeAttributes& attributes, const std::vector<Vec2>& line = {}) {
        if (a == b || !edge_keys_.insert(edge_key(a, b)).second) return false;
        next_.add_edge(a, b, attributes, line);
        return true;
    }

    GeometricGraph take() {
        if (!added_rewrites_.empty()) {
            next_.more_rewrites.insert(next_.more_rewrites.end(), added_rewrites_.begin(), added_rewrites_.end());
            std::stable_sort(next_.more_rewrites.begin(), next_.more_rewrites.end(),
                             [](const PendingRewrite& a, const PendingRewrite& b) { return a.vertex < b.vertex; });
        }
        if (std::any_of(instances_.begin(), instances_.end(), [](std::int32_t i) { return i >= 0; })) next_.instances = std::move(instances_);
        return std::move(next_);
    }
    const GeometricGraph& graph() const { return next_; }

private:
    // Whether v already has the rewrite (symbol, frame) pending.
    bool pending_at(VertexId v, Symbol symbol, const Similarity2& frame, double tolerance) const {
        const auto i = static_cast<std::size_t>(v);
        if (next_.symbols[i] == symbol && same_frame(next_.frames[i], frame, tolerance)) return true;
        const auto same = [&](const PendingRewrite& r) { return r.vertex == v && r.symbol == symbol && same_frame(r.frame, frame, tolerance); };
        if (v < survivors_) {
            const auto [first, last] = next_.more_rewrites_at(v);
            if (std::any_of(first, last, same)) return true;
        }
        const auto [first, last] = added_at_.equal_range(v);
        for (auto it = first; it != last; ++it) {
            if (same(added_rewrites_[it->second])) return true;
        }
        return false;
    }

    void index(VertexId id) {
        const Vec2& p = next_.positions[static_cast<std::size_t>(id)];
        tree_.insert({spatial::point(p), id});
    }

    const GeometricGraph& old_;
    GeometricGraph next_;
    std::vector<VertexId> new_id_;
    std::vector<std::int32_t> instances_; // per vertex of next_
    VertexId survivors_ = 0;
    spatial::RTree<Entry> tree_;
    std::unordered_set<std::uint64_t> edge_keys_;
    std::vector<PendingRewrite> added_rewrites_; // by this step, in the order they came
    std::unordered_multimap<VertexId, std::size_t> added_at_; // vertex -> its entries in added_rewrites_
};

double world_tolerance(const DeriveOptions& options, const Similarity2& frame) {
    return options.tolerance_relative ? options.tolerance * frame.scale() : options.tolerance;
}

// What a rewrite places where: the rule, and the instance of a learned grammar if the
// vertex carries one (its correction applies to the vertex's frame).
struct Rewrite {
    const Rule* rule = nullptr;
    const RuleInstance* instance = nullptr;
    std::int32_t instance_id = -1;
    Similarity2 frame;
    std::vector<VertexId> ids;
    std::vector<Vec2> positions;
};

double rewrite_tolerance(const DeriveOptions& options, const Rewrite& w) {
    return w.instance && w.instance->tolerance_m > 0 ? w.instance->tolerance_m : world_tolerance(options, w.frame);
}

// Strict mode: can every embedding point of this rewrite find a host vertex that the step
// does not rewrite? `host` indexes exactly those vertices.
bool embedding_complete(const spatial::RTree<Entry>& host, const GeometricGraph& g, const Rule& rule,
                        const Similarity2& frame, double tolerance) {
    for (const RuleVertex& rv : rule.vertices) {
        for (const EmbeddingPoint& ep : rv.embedding) {
            const Vec2 target = frame.apply(rv.position + ep.offset);
            const spatial::Box box = spatial::around(target, tolerance);
            bool found = false;
            for (auto it = host.qbegin(bgi::intersects(box)); it != host.qend() && !found; ++it) {
                found = (g.positions[static_cast<std::size_t>(it->second)] - target).norm() <= tolerance;
            }
            if (!found) return false;
        }
    }
    return true;
}

} // namespace

VertexId place_nonterminal(GeometricGraph& graph, Symbol symbol, const Vec2& position, const Frame& frame) {
    if (!std::isfinite(position.x()) || !std::isfinite(position.y()) || !(frame.scale > 0) || !std::isfinite(frame.scale) ||
        !std::isfinite(frame.rotation_deg)) {
        throw UsageError("a placed rule needs a finite position, a scale > 0 and a finite rotation");
    }
    const VertexId id = graph.add_vertex(position);
    graph.symbols.back() = symbol;
    graph.frames.back() = frame.at(position);
    return id;
}

bool derive_step(GeometricGraph& g, const Grammar& grammar, const DeriveOptions& options, StepReport* report_out, bool* over_budget,
                 std::vector<VertexId>* source, std::vector<Placement>* placed_out) {
    StepReport report;
    if (over_budget) *over_budget = false;
    const std::size_t n = g.vertex_count();
    // Every rewrite pending at each vertex, its own first: pending[first[v] .. first[v+1]).
    std::vector<PendingRewrite> pending;
    std::vector<std::size_t> first(n + 1, 0);
    {
        std::size_t extra = 0;
        for (std::size_t v = 0; v < n; ++v) {
            first[v] = pending.size();
            if (g.symbols[v] != 0) pending.push_back({static_cast<VertexId>(v), g.symbols[v], g.frames[v]});
            for (; extra < g.more_rewrites.size() && g.more_rewrites[extra].vertex == static_cast<VertexId>(v); ++extra) {
                pending.push_back(g.more_rewrites[extra]);
            }
        }
        first[n] = pending.size();
    }
    // A vertex is rewritten when a rule rewrites any of what is pending there.
    std::vector<char> erased(n, 0);
    for (std::size_t v = 0; v < n; ++v) {
        for (std::size_t k = first[v]; k < first[v + 1] && !erased[v]; ++k) erased[v] = grammar.rule_for(pending[k].symbol) != nullptr;
    }
    // Strict mode decides against the host as it is before the step, less what it rewrites.
    spatial::RTree<Entry> host;
    if (options.strict) {
        std::vector<Entry> entries;
        for (std::size_t v = 0; v < n; ++v) {
            if (!erased[v]) entries.emplace_back(spatial::point(g.positions[v]), static_cast<VertexId>(v));
        }
        host = spatial::RTree<Entry>(entries.begin(), entries.end());
    }
    std::vector<std::size_t> rewrites; // into `pending`
    std::vector<std::size_t> kept;     // into `pending`: nonterminals with no rule at a rewritten vertex
    std::size_t placed_upper_bound = 0, erased_count = 0;
    for (std::size_t v = 0; v < n; ++v) {
        if (!erased[v]) continue;
        if (options.strict) {
            for (std::size_t k = first[v]; k < first[v + 1] && erased[v]; ++k) {
                const Rule* rule = grammar.rule_for(pending[k].symbol);
                const Similarity2& frame = pending[k].frame;
                if (rule && !embedding_complete(host, g, *rule, frame, world_tolerance(options, frame))) erased[v] = 0;
            }
            if (!erased[v]) {
                ++report.refused;
                continue;
            }
        }
        ++erased_count;
        for (std::size_t k = first[v]; k < first[v + 1]; ++k) {
            const Rule* rule = grammar.rule_for(pending[k].symbol);
            (rule ? rewrites : kept).push_back(k);
            placed_upper_bound += rule ? rule->vertices.size() : 1;
        }
    }
    if (report_out) *report_out = report;
    if (rewrites.empty()) return false;
    if (n - erased_count + placed_upper_bound > options.max_vertices) {
        if (over_budget) *over_budget = true;
        return false;
    }

    StepBuilder builder(g, erased);
    std::vector<Rewrite> placed(rewrites.size());
    std::vector<Placement> placements;
    // What has no rule stays pending where it was, at the place the vertex's rewrites fill.
    for (std::size_t k : kept) {
        bool merged = false;
        const PendingRewrite& p = pending[k];
        const bool own = k == first[static_cast<std::size_t>(p.vertex)];
        const VertexId v = builder.place(g.positions[static_cast<std::size_t>(p.vertex)], p.symbol, p.frame,
                                         own ? g.instance_of(p.vertex) : -1, world_tolerance(options, p.frame), merged);
        if (!merged && placed_out) placements.resize(static_cast<std::size_t>(v) + 1);
    }
    // Steps 1-3 for every rewrite: S in q's frame, q erased (by the builder), S placed.
    for (std::size_t r = 0; r < rewrites.size(); ++r) {
        const PendingRewrite& pr = pending[rewrites[r]];
        const auto q = static_cast<std::size_t>(pr.vertex);
        Rewrite& w = placed[r];
        w.rule = grammar.rule_for(pr.symbol);
        w.frame = pr.frame;
        // Only a vertex's own rewrite can be an instance of a learned grammar: those never share a place.
        const std::int32_t id = rewrites[r] == first[q] ? g.instance_of(pr.vertex) : -1;
        if (id >= 0 && static_cast<std::size_t>(id) < grammar.encoding.instances.size() &&
            grammar.encoding.instances[static_cast<std::size_t>(id)].symbol == pr.symbol) {
            w.instance = &grammar.encoding.instances[static_cast<std::size_t>(id)];
            w.instance_id = id;
            w.frame = w.frame * w.instance->correction.at(Vec2::Zero());
            w.frame.t += w.instance->shift;
        }
        const double tolerance = rewrite_tolerance(options, w);
        for (std::size_t i = 0; i < w.rule->vertices.size(); ++i) {
            const RuleVertex& rv = w.rule->vertices[i];
            Vec2 p = w.frame.apply(rv.position);
            if (w.instance && !w.instance->residuals.empty()) p += w.instance->residuals[i];
            Similarity2 child = w.frame * rv.transform.at(rv.position);
            child.t = p;
            const std::int32_t child_instance = w.instance && !w.instance->children.empty() ? w.instance->children[i] : -1;
            bool merged = false;
            // The vertices of a learned instance are distinct from every other by construction:
            // they never merge (a merge could only lose a street).
            const VertexId v = builder.place(p, rv.symbol, child, rv.symbol ? child_instance : -1, w.instance ? -1.0 : tolerance, merged);
            w.ids.push_back(v);
            w.positions.push_back(p);
            report.merged_vertices += merged;
            if (!merged && placed_out) {
                placements.resize(static_cast<std::size_t>(v) + 1);
                placements[static_cast<std::size_t>(v)] = {w.instance_id, static_cast<std::int32_t>(i)};
            }
        }
        for (std::size_t e = 0; e < w.rule->edges.size(); ++e) {
            const GrammarEdge& edge = w.rule->edges[e];
            EdgeAttributes a;
            a.highway = edge.highway;
            if (w.instance) {
                for (const auto& [index, highway] : w.instance->edge_classes) {
                    if (static_cast<std::size_t>(index) == e) a.highway = highway;
                }
            }
            builder.add_edge(w.ids[static_cast<std::size_t>(edge.a)], w.ids[static_cast<std::size_t>(edge.b)], a);
        }
    }
    // Step 4: embedding points connect to the nearest vertex within the tolerance that is
    // not part of the same rewrite.
    for (Rewrite& w : placed) {
        const double tolerance = rewrite_tolerance(options, w);
        const auto& own = w.ids;
        // The street from rule vertex i to its partner, if there is one.
        auto join = [&](std::size_t i, VertexId partner, HighwayClass highway) {
            if (partner < 0) {
                ++report.missed_embeddings;
                return;
            }
            EdgeAttributes a;
            a.highway = highway;
            report.embedding_edges += builder.add_edge(own[i], partner, a);
        };
        auto connect = [&](std::size_t i, const EmbeddingPoint& ep) {
            const Vec2 target = w.positions[i] + w.frame.apply_linear(ep.offset);
            join(i, builder.nearest(target, tolerance, [&](VertexId v) { return std::find(own.begin(), own.end(), v) == own.end(); }),
                 ep.highway);
        };
        if (w.instance) {
            if (!w.instance->rule_points.empty()) {
                std::vector<std::pair<std::size_t, const EmbeddingPoint*>> points;
                for (std::size_t i = 0; i < w.rule->vertices.size(); ++i) {
                    for (const EmbeddingPoint& ep : w.rule->vertices[i].embedding) points.emplace_back(i, &ep);
                }
                for (std::int32_t p : w.instance->rule_points) {
                    const auto& [i, ep] = points[static_cast<std::size_t>(p)];
                    connect(i, *ep);
                }
            }
            for (const RuleInstance::Link& link : w.instance->embedding) connect(static_cast<std::size_t>(link.vertex), link.point);
            // The instance's own vertices, sorted: the last rule of a complete encoding has
            // most of a city's.
            std::vector<VertexId> sorted_own;
            if (!w.instance->neighbours.empty()) {
                sorted_own = own;
                std::sort(sorted_own.begin(), sorted_own.end());
            }
            for (const RuleInstance::Neighbour& link : w.instance->neighbours) {
                const auto i = static_cast<std::size_t>(link.vertex);
                join(i, builder.ranked(w.positions[i], static_cast<std::size_t>(link.rank),
                                       [&](VertexId v) { return !std::binary_search(sorted_own.begin(), sorted_own.end(), v); }),
                     link.highway);
            }
        } else {
            for (std::size_t i = 0; i < w.rule->vertices.size(); ++i) {
                for (const EmbeddingPoint& ep : w.rule->vertices[i].embedding) connect(i, ep);
            }
        }
    }
    report.rewrites = rewrites.size();
    if (source) *source = builder.sources();
    if (placed_out) {
        placements.resize(builder.graph().vertex_count());
        *placed_out = std::move(placements);
    }
    g = builder.take();
    if (report_out) *report_out = report;
    return true;
}

DeriveReport derive(GeometricGraph& g, const Grammar& grammar, const DeriveOptions& options, const ProgressCallback& progress) {
    if (!options.grammar_validated) validate(grammar);
    if (options.max_steps < 0) throw UsageError("steps: the number of steps must be >= 0");
    if (options.max_vertices < 1) throw UsageError("max_vertices: must be at least 1");
    if (!(options.tolerance >= 0) || !std::isfinite(options.tolerance)) throw UsageError("tolerance: must be a finite number >= 0");
    DeriveReport result;
    result.source_vertex.resize(g.vertex_count());
    std::iota(result.source_vertex.begin(), result.source_vertex.end(), 0);
    result.placed_by.assign(g.vertex_count(), Placement{});
    std::vector<VertexId> step_source;
    std::vector<Placement> step_placed;
    for (int step = 0; step < options.max_steps; ++step) {
        report(progress, static_cast<double>(step) / options.max_steps, "derivation step " + std::to_string(step + 1));
        StepReport s;
        bool over_budget = false;
        const std::size_t vertices_before = g.vertex_count();
        const std::vector<Vec2> positions_before = g.positions;
        const std::vector<Symbol> symbols_before = g.symbols;
        const std::vector<Similarity2> frames_before = g.frames;
        const std::vector<std::array<VertexId, 2>> edges_before = g.edges;
        const std::vector<PendingRewrite> more_before = g.more_rewrites;
        if (!derive_step(g, grammar, options, &s, &over_budget, &step_source, &step_placed)) {
            result.stopped_by_budget = over_budget;
            result.nothing_to_rewrite = !over_budget;
            result.totals.refused += s.refused;
            break;
        }
        const bool finite = std::all_of(g.positions.begin(), g.positions.end(), [](const Vec2& p) {
            return p.allFinite() && p.cwiseAbs().maxCoeff() < 1e12;
        }) && std::all_of(g.frames.begin(), g.frames.end(), [](const Similarity2& f) {
            return std::isfinite(f.a) && std::isfinite(f.b) && f.scale() > 0;
        }) && std::all_of(g.more_rewrites.begin(), g.more_rewrites.end(), [](const PendingRewrite& r) {
            return std::isfinite(r.frame.a) && std::isfinite(r.frame.b) && r.frame.t.allFinite() && r.frame.scale() > 0;
        });
        if (!finite) {
            throw GrammarError("derivation step " + std::to_string(step + 1) +
                               " leaves the range of usable coordinates (a rule grows or shrinks its frame without bound); "
                               "derive fewer steps");
        }
        ++result.steps;
        std::vector<VertexId> composed(step_source.size(), -1);
        for (std::size_t v = 0; v < step_source.size(); ++v) {
            if (step_source[v] >= 0) composed[v] = result.source_vertex[static_cast<std::size_t>(step_source[v])];
        }
        result.source_vertex.swap(composed);
        for (std::size_t v = 0; v < step_source.size(); ++v) {
            if (step_source[v] >= 0) step_placed[v] = result.placed_by[static_cast<std::size_t>(step_source[v])];
        }
        result.placed_by.swap(step_placed);
        result.totals.rewrites += s.rewrites;
        result.totals.refused += s.refused;
        result.totals.embedding_edges += s.embedding_edges;
        result.totals.missed_embeddings += s.missed_embeddings;
        result.totals.merged_vertices += s.merged_vertices;
        const bool same_frames = std::equal(g.frames.begin(), g.frames.end(), frames_before.begin(), frames_before.end(),
                                            [](const Similarity2& x, const Similarity2& y) { return x.a == y.a && x.b == y.b && x.t == y.t; });
        if (g.vertex_count() == vertices_before && g.edges == edges_before && g.positions == positions_before &&
            g.symbols == symbols_before && same_frames &&
            std::equal(g.more_rewrites.begin(), g.more_rewrites.end(), more_before.begin(), more_before.end(),
                       [](const PendingRewrite& x, const PendingRewrite& y) {
                           return x.vertex == y.vertex && x.symbol == y.symbol && x.frame.a == y.frame.a && x.frame.b == y.frame.b &&
                                  x.frame.t == y.frame.t;
                       })) {
            result.converged = true;
            break;
        }
    }
    report(progress, 1.0, "done");
    return result;
}

} // namespace ggg
