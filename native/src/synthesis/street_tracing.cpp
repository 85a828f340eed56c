// Streets traced into a region after the city's own junctions; see street_tracing.hpp.
#include "street_tracing.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <queue>
#include <tuple>


#include "ggg/graph/road_class.hpp"
#include "ggg/graph/plane_geometry.hpp"
#include "ggg/graph/spatial_index.hpp"

namespace ggg::growth_detail {
namespace {

using namespace spatial; // bg, bgi, Point, Box, point, RTree, VertexEntry, EdgeEntry

double angle_of(const Vec2& d) { return std::atan2(d.y(), d.x()); }
Vec2 unit(double angle) { return {std::cos(angle), std::sin(angle)}; }
double wrap(double a) { // into (-pi, pi]
    while (a <= -M_PI) a += 2 * M_PI;
    while (a > M_PI) a -= 2 * M_PI;
    return a;
}

// Main roads (and their links) are traced before the streets between them.
bool main_class(HighwayClass c) { return highway_rank(c) <= highway_rank(HighwayClass::tertiary_link); }

// Motorways, trunk roads and the links of any road are not traced: they are not streets of a
// district's pattern but routes through it, with ramps instead of junctions (the main roads
// are continued across the grown streets afterwards, street_hierarchy.hpp).
bool traced_class(HighwayClass c) {
    switch (c) {
    case HighwayClass::motorway: case HighwayClass::trunk: case HighwayClass::motorway_link: case HighwayClass::trunk_link:
    case HighwayClass::primary_link: case HighwayClass::secondary_link: case HighwayClass::tertiary_link:
        return false;
    default:
        return true;
    }
}

// One street leaving an example junction, seen from a street arriving at it: its turn from
// straight ahead, its length (end to end) and its shape in a frame where it runs from (0, 0)
// to (1, 0).
struct Branch {
    double turn = 0.0;
    double length = 0.0;
    std::vector<Vec2> shape;
    HighwayClass highway = HighwayClass::residential;
    // Of the class of the street the example was seen from: a street that goes on keeps its
    // own class (the example only says that it does not change there).
    bool keeps_class = false;
};

// One of the city's junctions seen from one of its streets: what leaves it (nothing, at a dead end).
struct Example {
    std::vector<Branch> branches;
};

// A street to trace: from `from`, turned `heading` (radians), `length` metres, bent like `shape`.
struct Street {
    VertexId from = -1;
    double heading = 0.0;
    double length = 0.0;
    std::vector<Vec2> shape;
    HighwayClass highway = HighwayClass::residential;
    bool main = false;
    std::size_t generation = 0;
    std::size_t order = 0;
    int retries = 0;         // a street from the base that reaches the region is tried again
    double min_length = 0.0; // (and must still reach into the region)
};

struct Later {
    // Main roads first, then by generation (so that growth moves inward from every street at
    // once), then in the order they were proposed.
    bool operator()(const Street& a, const Street& b) const {
        return std::make_tuple(!a.main, a.generation, a.order) > std::make_tuple(!b.main, b.generation, b.order);
    }
};

// The point of edge e next to its end `at` (where its polyline leaves that end).
Vec2 leaving(const GeometricGraph& g, EdgeId e, VertexId at) {
    const Vec2* p = g.geometry_begin(e);
    const std::size_t n = g.geometry_size(e);
    return g.edges[static_cast<std::size_t>(e)][0] == at ? p[1] : p[n - 2];
}

class Tracer {
public:
    Tracer(GeometricGraph& g, std::size_t base_vertices, const GeometricGraph& city, const std::vector<Vec2>& region,
           const TracingSettings& settings, std::mt19937_64& rng, const ProgressCallback& progress)
        : g_(g), base_vertices_(base_vertices), region_(region), s_(settings), rng_(rng), progress_(progress) {
        // The streets around the region are the closest example of how the streets it continues
        // run (their curves included, which a grammar's city, decoded from rules, has not);
        // the grammar's city is the example where the base has too few of them.
        double size = 0.0;
        for (const Vec2& p : region_) size = std::max(size, (p - region_.front()).norm());
        // The nearest streets first (the parts of a city differ), further out until there are
        // enough of them.
        for (double radius = 0.25 * size; radius <= 2.0 * size; radius *= 2) {
            main_examples_.clear();
            other_examples_.clear();
            learn_examples(g_, radius);
            if (main_examples_.size() + other_examples_.size() >= 400) break;
        }
        if (main_examples_.size() + other_examples_.size() < 200) {
            main_examples_.clear();
            other_examples_.clear();
            learn_examples(city, std::numeric_limits<double>::infinity());
        }
    }

    TracingReport run() {
        if (main_examples_.empty() && other_examples_.empty()) return report_;
        fixed_edges_ = g_.edge_count();
        index();
        seed();
        std::size_t steps = 0;
        const std::size_t max_steps = 50 * s_.max_vertices + 1000;
        while (!queue_.empty() && g_.vertex_count() < s_.max_vertices && steps++ < max_steps) {
            Street street = queue_.top();
            queue_.pop();
            if (steps % 256 == 0) report(progress_, std::min(0.99, static_cast<double>(report_.streets) / static_cast<double>(expected_streets_)), "tracing streets");
            trace(street);
        }
        return report_;
    }

private:
    // ---- the city's junctions --------------------------------------------------------------

    // The junctions of `city` within `radius` of the region, each seen from each of its streets.
    void learn_examples(const GeometricGraph& city, double radius) {
        const std::size_t n = city.vertex_count();
        if (city.edge_count() == 0) return;
        std::vector<std::vector<EdgeId>> at(n);
        for (std::size_t e = 0; e < city.edge_count(); ++e) {
            const auto [a, b] = city.edges[e];
            if (a == b) continue;
            at[static_cast<std::size_t>(a)].push_back(static_cast<EdgeId>(e));
            at[static_cast<std::size_t>(b)].push_back(static_cast<EdgeId>(e));
        }
        std::vector<double> lengths;
        for (std::size_t e = 0; e < city.edge_count(); ++e) {
            const auto [a, b] = city.edges[e];
            const Vec2 pa = city.positions[static_cast<std::size_t>(a)], pb = city.positions[static_cast<std::size_t>(b)];
            if (std::isfinite(radius) && distance_to_ring(region_, pa) > radius) continue;
            lengths.push_back((pb - pa).norm());
        }
        if (lengths.empty()) return;
        std::nth_element(lengths.begin(), lengths.begin() + static_cast<long>(lengths.size() / 2), lengths.end());
        typical_ = std::max(1.0, lengths[lengths.size() / 2]);
        std::nth_element(lengths.begin(), lengths.begin() + static_cast<long>(9 * lengths.size() / 10), lengths.end());
        long_ = lengths[9 * lengths.size() / 10];
        // The city's own edges are not examples: its dead ends there are where its map was cut
        // (the extract's border, or this very region when it was cut out of the city).
        Vec2 lo = city.positions[0], hi = city.positions[0];
        for (const Vec2& p : city.positions) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
        auto at_a_border = [&](const Vec2& p) {
            const double margin = typical_;
            if ((p - lo).minCoeff() < margin || (hi - p).minCoeff() < margin) return true;
            return inside(region_, p) || distance_to_ring(region_, p) < 1.5 * typical_;
        };
        std::vector<std::size_t> class_counts(highway_class_count, 0);
        std::size_t right = 0, angles = 0;
        for (std::size_t c = 0; c < n; ++c) {
            const auto& edges = at[c];
            if (edges.empty() || edges.size() > 4) continue;
            const Vec2 pc = city.positions[c];
            if (at_a_border(pc)) continue;
            if (std::isfinite(radius) && distance_to_ring(region_, pc) > radius) continue;
            if (edges.size() >= 3) {
                std::vector<double> around;
                for (const EdgeId e : edges) around.push_back(angle_of(leaving(city, e, static_cast<VertexId>(c)) - pc));
                std::sort(around.begin(), around.end());
                for (std::size_t i = 0; i < around.size(); ++i) {
                    const double gap = (i + 1 < around.size() ? around[i + 1] : around[0] + 2 * M_PI) - around[i];
                    right += std::abs(gap - M_PI / 2) <= M_PI / 12;
                    ++angles;
                }
            }
            for (const EdgeId in : edges) {
                if (!traced_class(city.edge_highway[static_cast<std::size_t>(in)])) continue;
                const Vec2 before = leaving(city, in, static_cast<VertexId>(c));
                if ((pc - before).norm() < 1e-6) continue;
                const double arriving = angle_of(pc - before);
                Example example;
                bool main = false;
                bool usable = true;
                for (const EdgeId out : edges) {
                    if (out == in) {
                        main = main_class(city.edge_highway[static_cast<std::size_t>(out)]);
                        continue;
                    }
                    if (!traced_class(city.edge_highway[static_cast<std::size_t>(out)])) continue;
                    const auto [a, b] = city.edges[static_cast<std::size_t>(out)];
                    const bool forward = a == static_cast<VertexId>(c);
                    const Vec2 far = city.positions[static_cast<std::size_t>(forward ? b : a)];
                    const double chord = (far - pc).norm();
                    if (chord < 1e-3) {
                        usable = false;
                        break;
                    }
                    Branch branch;
                    branch.length = chord;
                    branch.highway = city.edge_highway[static_cast<std::size_t>(out)];
                    branch.keeps_class = branch.highway == city.edge_highway[static_cast<std::size_t>(in)];
                    const double heading = angle_of(far - pc);
                    branch.turn = wrap(heading - arriving);
                    const Vec2* p = city.geometry_begin(out);
                    const std::size_t m = city.geometry_size(out);
                    const Vec2 x = unit(-heading);
                    for (std::size_t k = 0; k < m; ++k) {
                        const Vec2 d = (forward ? p[k] : p[m - 1 - k]) - pc;
                        // Rotated by -heading and scaled to a unit chord.
                        branch.shape.push_back(Vec2(x.x() * d.x() - x.y() * d.y(), x.y() * d.x() + x.x() * d.y()) / chord);
                    }
                    branch.shape.front() = Vec2(0, 0);
                    branch.shape.back() = Vec2(1, 0);
                    example.branches.push_back(std::move(branch));
                }
                if (!usable) continue;
                for (const Branch& b : example.branches) ++class_counts[static_cast<std::size_t>(b.highway)];
                (main ? main_examples_ : other_examples_).push_back(std::move(example));
            }
        }
        pick_common_class(class_counts);
        if (angles > 0) right_share_ = static_cast<double>(right) / static_cast<double>(angles);
    }

    void pick_common_class(const std::vector<std::size_t>& class_counts) {
        const auto most = std::max_element(class_counts.begin(), class_counts.end());
        if (*most > 0) common_class_ = static_cast<HighwayClass>(most - class_counts.begin());
    }

    const Example& example_for(bool main) {
        const auto& pool = (main && !main_examples_.empty()) || other_examples_.empty() ? main_examples_ : other_examples_;
        std::uniform_int_distribution<std::size_t> pick(0, pool.size() - 1);
        return pool[pick(rng_)];
    }

    // ---- the graph and its indexes ---------------------------------------------------------

    void index() {
        adjacency_.assign(g_.vertex_count(), {});
        for (std::size_t e = 0; e < g_.edge_count(); ++e) {
            const auto [a, b] = g_.edges[e];
            adjacency_[static_cast<std::size_t>(a)].push_back(static_cast<EdgeId>(e));
            adjacency_[static_cast<std::size_t>(b)].push_back(static_cast<EdgeId>(e));
            index_edge(static_cast<EdgeId>(e));
        }
        for (std::size_t v = 0; v < g_.vertex_count(); ++v) vertices_.insert({point(g_.positions[v]), static_cast<VertexId>(v)});
        double area = 0.0;
        for (std::size_t i = 0, j = region_.size() - 1; i < region_.size(); j = i++) area += cross(region_[j], region_[i]);
        expected_streets_ = std::max(1.0, 2.0 * std::abs(area) / 2.0 / (typical_ * typical_));
    }

    void index_edge(EdgeId e) { segments_.insert({edge_box(g_, e), e}); }

    std::size_t degree(VertexId v) const { return adjacency_[static_cast<std::size_t>(v)].size(); }

    VertexId other_end(EdgeId e, VertexId v) const {
        const auto& ends = g_.edges[static_cast<std::size_t>(e)];
        return ends[0] == v ? ends[1] : ends[0];
    }

    bool adjacent(VertexId v, VertexId w) const {
        for (const EdgeId e : adjacency_[static_cast<std::size_t>(v)]) {
            if (other_end(e, v) == w) return true;
        }
        return false;
    }

    // The smallest angle between direction d leaving v and the streets already at v.
    double clearance(VertexId v, const Vec2& d) const {
        double smallest = M_PI;
        const Vec2 pv = g_.positions[static_cast<std::size_t>(v)];
        for (const EdgeId e : adjacency_[static_cast<std::size_t>(v)]) {
            const Vec2 other = leaving(g_, e, v) - pv;
            smallest = std::min(smallest, std::abs(wrap(angle_of(other) - angle_of(d))));
        }
        return smallest;
    }

    // The first place where the polyline meets a street other than those at `from` (or at
    // `to`, when given): (index of its piece, point, edge hit).
    struct Hit {
        std::size_t piece = 0;
        double t = 0.0;
        Vec2 where = Vec2::Zero();
        EdgeId edge = -1;
        std::size_t edge_piece = 0;
    };
    std::optional<Hit> first_hit(const std::vector<Vec2>& line, VertexId from, VertexId to = -1, EdgeId ignore = -1) const {
        for (std::size_t k = 0; k + 1 < line.size(); ++k) {
            const Vec2 a = line[k], b = line[k + 1];
            Box box(point(a), point(a));
            bg::expand(box, point(b));
            std::optional<Hit> best;
            for (auto it = segments_.qbegin(bgi::intersects(box)); it != segments_.qend(); ++it) {
                const EdgeId e = it->second;
                if (e == ignore) continue;
                const auto [u, v] = g_.edges[static_cast<std::size_t>(e)];
                const bool at_from = u == from || v == from;
                const bool at_to = to >= 0 && (u == to || v == to);
                const Vec2* q = g_.geometry_begin(e);
                for (std::size_t i = 0; i + 1 < g_.geometry_size(e); ++i) {
                    const auto m = segment_meeting(a, b, q[i], q[i + 1]);
                    if (m) {
                        // Streets at this street's own ends meet it there, which is no crossing.
                        if ((at_from && k == 0 && m->first < 1e-6) || (at_to && k + 2 == line.size() && m->first > 1 - 1e-6)) continue;
                        if (!best || m->first < best->t) best = Hit{k, m->first, a + m->first * (b - a), e, i};
                    } else if (segments_meet(a, b, q[i], q[i + 1])) {
                        // Overlapping (parallel) pieces: counted as meeting at this piece's start.
                        if ((at_from && k == 0) || (at_to && k + 2 == line.size())) continue;
                        if (!best) best = Hit{k, 0.0, a, e, i};
                    }
                }
            }
            if (best) return best;
        }
        return std::nullopt;
    }

    bool leaves_region(const std::vector<Vec2>& line, std::size_t from_piece) const {
        for (std::size_t k = from_piece; k < line.size(); ++k) {
            if (!inside(region_, line[k])) return true;
        }
        return false;
    }

    // Whether a street from v to w (its polyline from v) would close a block smaller than allowed.
    bool closes_small_block(VertexId v, VertexId w) const {
        if (s_.min_block_m2 <= 0) return false;
        auto neighbours = [&](VertexId x) -> std::vector<VertexId> {
            std::vector<VertexId> out;
            for (const EdgeId e : adjacency_[static_cast<std::size_t>(x)]) out.push_back(other_end(e, x));
            if (x == v) out.push_back(w);
            if (x == w) out.push_back(v);
            return out;
        };
        const double left = block_left_of(g_.positions, neighbours, v, w);
        const double right = block_left_of(g_.positions, neighbours, w, v);
        return (left > 0 && left < s_.min_block_m2) || (right > 0 && right < s_.min_block_m2);
    }

    VertexId add_vertex(const Vec2& p) {
        const VertexId v = g_.add_vertex(p);
        adjacency_.emplace_back();
        vertices_.insert({point(p), v});
        return v;
    }

    void add_street(VertexId v, VertexId w, const std::vector<Vec2>& line, HighwayClass highway) {
        EdgeAttributes attributes;
        attributes.highway = highway;
        const EdgeId e = g_.add_edge(v, w, attributes, line);
        adjacency_[static_cast<std::size_t>(v)].push_back(e);
        adjacency_[static_cast<std::size_t>(w)].push_back(e);
        index_edge(e);
        ++report_.streets;
    }

    VertexId split(EdgeId e, const Vec2& where) {
        const VertexId b = g_.edges[static_cast<std::size_t>(e)][1];
        const VertexId x = g_.split_edge(e, where);
        const auto second = static_cast<EdgeId>(g_.edge_count() - 1);
        adjacency_.emplace_back();
        vertices_.insert({point(where), x});
        auto& at_b = adjacency_[static_cast<std::size_t>(b)];
        std::replace(at_b.begin(), at_b.end(), e, second);
        adjacency_[static_cast<std::size_t>(x)] = {e, second};
        index_edge(second); // e stays indexed by its whole box, which holds its first half
        return x;
    }

    // ---- tracing ------------------------------------------------------------------------

    // The base's streets that reach the region: a dead end or a junction with an open side
    // that points into the region, close enough to reach it with one street.
    void seed() {
        const double reach = s_.border_m + std::max(3.0 * typical_, long_);
        std::vector<std::pair<double, Street>> seeds;
        for (std::size_t v = 0; v < base_vertices_; ++v) {
            const auto id = static_cast<VertexId>(v);
            if (degree(id) >= 4) continue;
            const Vec2 p = g_.positions[v];
            const bool in = inside(region_, p);
            if (!in && distance_to_ring(region_, p) > reach) continue;
            // Straight on from each street at v, where that leaves room and enters the region.
            std::optional<std::pair<double, Street>> best;
            for (const EdgeId e : adjacency_[v]) {
                if (!traced_class(g_.edge_highway[static_cast<std::size_t>(e)])) continue;
                const Vec2 back = leaving(g_, e, id) - p;
                if (back.norm() < 1e-9) continue;
                const Vec2 ahead = -back.normalized();
                if (clearance(id, ahead) < M_PI / 3) continue;
                const double enters = entry_distance(p, ahead, reach);
                if (enters < 0) continue;
                Street s;
                s.from = id;
                s.heading = angle_of(ahead);
                s.highway = g_.edge_highway[static_cast<std::size_t>(e)];
                s.main = main_class(s.highway);
                if (!best || enters < best->first) best = std::pair{enters, s};
            }
            // A junction whose streets leave one side open towards the region (a street of it
            // was cut there): a street across that side, down the middle of the gap.
            if (!best && degree(id) >= 2) {
                std::vector<double> angles;
                for (const EdgeId e : adjacency_[v]) angles.push_back(angle_of(leaving(g_, e, id) - p));
                std::sort(angles.begin(), angles.end());
                double gap = 0.0, middle = 0.0;
                for (std::size_t i = 0; i < angles.size(); ++i) {
                    const double next = i + 1 < angles.size() ? angles[i + 1] : angles[0] + 2 * M_PI;
                    if (next - angles[i] > gap) gap = next - angles[i], middle = angles[i] + 0.5 * (next - angles[i]);
                }
                const double enters = gap >= 0.8 * M_PI ? entry_distance(p, unit(middle), reach) : -1.0;
                if (enters >= 0) {
                    Street s;
                    s.from = id;
                    s.heading = wrap(middle);
                    s.highway = common_class_;
                    s.main = false;
                    best = std::pair{enters, s};
                }
            }
            // Else straight to the region, where that leaves room at v (a vertex whose streets
            // all ran into the region has none left to go on from).
            if (!best && !in) {
                const Vec2 towards = nearest_on_ring(p) - p;
                const double enters = towards.norm();
                if (enters > 1e-9 && clearance(id, towards) >= M_PI / 3) {
                    Street s;
                    s.from = id;
                    s.heading = angle_of(towards);
                    s.highway = common_class_;
                    s.main = false;
                    best = std::pair{enters, s};
                }
            }
            if (!best) continue;
            seeds.push_back(*best);
        }
        // Each seed continues with a street of the city that goes on about straight.
        for (auto& [enters, s] : seeds) {
            const Branch* through = nullptr;
            for (int attempt = 0; attempt < 64 && !through; ++attempt) {
                const Example& example = example_for(s.main);
                for (const Branch& b : example.branches) {
                    if (std::abs(b.turn) < M_PI / 6) through = &b;
                }
            }
            if (!through) continue;
            // Straight until it is in the region: the base's street goes on as it ran.
            s.min_length = enters + 0.25 * typical_;
            s.length = std::max(through->length, s.min_length);
            s.shape = {Vec2(0, 0), Vec2(1, 0)};
            s.order = order_++;
            queue_.push(s);
            ++report_.seeds;
        }
    }

    Vec2 nearest_on_ring(const Vec2& p) const {
        Vec2 best = region_.front();
        double best_d = std::numeric_limits<double>::infinity();
        for (std::size_t i = 0, j = region_.size() - 1; i < region_.size(); j = i++) {
            const Vec2 d = region_[i] - region_[j];
            const double t = std::clamp((p - region_[j]).dot(d) / std::max(d.squaredNorm(), 1e-300), 0.0, 1.0);
            const Vec2 q = region_[j] + t * d;
            if ((q - p).norm() < best_d) best = q, best_d = (q - p).norm();
        }
        return best;
    }

    // How far along the ray from p the region begins (0 inside it), or -1 beyond `reach`.
    double entry_distance(const Vec2& p, const Vec2& d, double reach) const {
        if (inside(region_, p)) return 0.0;
        const Vec2 q = p + reach * d;
        double first = -1;
        for (std::size_t i = 0, j = region_.size() - 1; i < region_.size(); j = i++) {
            const auto m = segment_meeting(p, q, region_[j], region_[i]);
            if (m && (first < 0 || m->first < first)) first = m->first;
        }
        return first < 0 ? -1.0 : first * reach;
    }

    // Where the streets around a point run on a grid (most of their length along two
    // perpendicular directions), a street traced from there keeps to it: a heading within a
    // few degrees of the grid is turned onto it, so that the small bends of the examples do not
    // add up. Local, so that a grid district and a winding one next to it each keep their own.
    std::optional<double> local_grid(const Vec2& p) const {
        const double r = 3.0 * typical_;
        const Box window = spatial::around(p, r);
        double c = 0.0, sn = 0.0, total = 0.0;
        for (auto it = segments_.qbegin(bgi::intersects(window)); it != segments_.qend(); ++it) {
            const EdgeId e = it->second;
            const Vec2* q = g_.geometry_begin(e);
            for (std::size_t i = 0; i + 1 < g_.geometry_size(e); ++i) {
                if ((0.5 * (q[i] + q[i + 1]) - p).squaredNorm() > r * r) continue;
                const Vec2 d = q[i + 1] - q[i];
                const double length = d.norm();
                const double a = 4.0 * angle_of(d);
                c += length * std::cos(a);
                sn += length * std::sin(a);
                total += length;
            }
        }
        if (total < 2.0 * typical_ || std::hypot(c, sn) / total < 0.5) return std::nullopt;
        return std::atan2(sn, c) / 4.0;
    }

    double on_grid(double heading, const Vec2& p) const {
        const std::optional<double> grid = local_grid(p);
        if (!grid) return heading;
        const double quarter = M_PI / 2;
        const double k = std::round((heading - *grid) / quarter);
        const double snapped = *grid + k * quarter;
        return std::abs(wrap(heading - snapped)) <= grid_tolerance_ ? snapped : heading;
    }

    std::vector<Vec2> lay(const Street& s) const { return lay_from(g_.positions[static_cast<std::size_t>(s.from)], s); }

    std::vector<Vec2> lay_from(const Vec2& p, const Street& s) const {
        const Vec2 x = s.length * unit(on_grid(s.heading, p));
        std::vector<Vec2> line;
        for (const Vec2& q : s.shape) line.push_back(p + Vec2(x.x() * q.x() - x.y() * q.y(), x.y() * q.x() + x.x() * q.y()));
        return line;
    }

    // The polyline bent so that its end lands on `to` (its other points move in proportion).
    static std::vector<Vec2> warped(std::vector<Vec2> line, const Vec2& to) {
        const Vec2 start = line.front(), end = line.back();
        const Vec2 old_chord = end - start, new_chord = to - start;
        const double old_length = old_chord.norm(), new_length = new_chord.norm();
        if (old_length < 1e-9 || new_length < 1e-9) return {start, to};
        const double turn = angle_of(new_chord) - angle_of(old_chord);
        const double scale = new_length / old_length;
        const Vec2 r = unit(turn) * scale;
        for (Vec2& q : line) {
            const Vec2 d = q - start;
            q = start + Vec2(r.x() * d.x() - r.y() * d.y(), r.y() * d.x() + r.x() * d.y());
        }
        line.back() = to;
        return line;
    }

    // Whether the street from `from` along `line` to the vertex `to` fits: crosses nothing,
    // leaves room at both ends and closes no sliver.
    bool fits_to_vertex(VertexId from, const std::vector<Vec2>& line, VertexId to) const {
        if (to == from || degree(to) >= 4 || adjacent(from, to)) return false;
        if (first_hit(line, from, to)) return false;
        const Vec2 arrive = line[line.size() - 2] - line.back();
        if (clearance(to, arrive) < min_angle_) return false;
        for (std::size_t k = 1; k + 1 < line.size(); ++k) {
            if (!inside(region_, line[k])) return false;
        }
        return !closes_small_block(from, to);
    }

    // A street ending on a street nearly square to it meets it square (a T-junction), and one
    // at a slant does so as often as the city's junctions are right angles: its last point moves
    // to the foot of the perpendicular from the point before it, where that stays on the street
    // near by and crosses nothing.
    void squared(const Street& s, std::vector<Vec2>& line, EdgeId e, std::size_t piece) {
        const Vec2 from_point = line[line.size() - 2];
        const Vec2* q = g_.geometry_begin(e);
        const Vec2 d = q[piece + 1] - q[piece];
        const double slant = std::abs(std::cos(angle_of(line.back() - from_point) - angle_of(d))); // 0: square
        if (slant > std::sin(M_PI / 5) && !std::bernoulli_distribution(right_share_)(rng_)) return;
        const double t = (from_point - q[piece]).dot(d) / std::max(d.squaredNorm(), 1e-300);
        if (t < 0.05 || t > 0.95) return;
        const Vec2 foot = q[piece] + t * d;
        if ((foot - line.back()).norm() > 0.5 * typical_ || (foot - from_point).norm() < 0.2 * typical_) return;
        std::vector<Vec2> moved = line;
        moved.back() = foot;
        if (first_hit(moved, s.from, -1, e)) return;
        line = std::move(moved);
    }

    // The street along `line`, bent to end at the junction w, added where it fits there.
    bool end_at(const Street& s, const std::vector<Vec2>& line, VertexId w) {
        const std::vector<Vec2> to_w = warped(line, g_.positions[static_cast<std::size_t>(w)]);
        if (!fits_to_vertex(s.from, to_w, w)) return false;
        add_street(s.from, w, to_w, s.highway);
        ++report_.joined;
        return true;
    }

    enum class Settled { joined, dropped, open };

    // The street along `line` joined to what it meets (a crossing, a junction or a street near
    // its end), or dropped where it cannot be; `open` when its end is on open ground.
    Settled settle(const Street& s, const std::vector<Vec2>& line) {
        const double snap = 0.3 * typical_;

        // A street it crosses: it stops there, at the junction near by or a new one.
        if (const auto hit = first_hit(line, s.from)) {
            std::vector<Vec2> cut(line.begin(), line.begin() + static_cast<long>(hit->piece) + 1);
            cut.push_back(hit->where);
            double travelled = 0.0;
            for (std::size_t k = 1; k < cut.size(); ++k) travelled += (cut[k] - cut[k - 1]).norm();
            if (travelled < 0.25 * typical_ || leaves_region_inside_line(cut)) return Settled::dropped;
            const auto [a, b] = g_.edges[static_cast<std::size_t>(hit->edge)];
            for (const VertexId end : {a, b}) {
                if ((g_.positions[static_cast<std::size_t>(end)] - hit->where).norm() < snap) {
                    return end_at(s, cut, end) ? Settled::joined : Settled::dropped;
                }
            }
            if (a == s.from || b == s.from) return Settled::dropped; // it would come back to where it started
            squared(s, cut, hit->edge, hit->edge_piece);
            const Vec2* q = g_.geometry_begin(hit->edge);
            const Vec2 along = q[hit->edge_piece + 1] - q[hit->edge_piece];
            const Vec2 arrive = cut[cut.size() - 2] - cut.back();
            const double crossing_angle = std::abs(std::sin(angle_of(arrive) - angle_of(along)));
            if (crossing_angle < std::sin(min_angle_)) return Settled::dropped;
            if (!inside(region_, cut.back()) || static_cast<std::size_t>(hit->edge) < fixed_edges_) return Settled::dropped;
            if (s_.min_block_m2 > 0 && splits_small_block(s.from, hit->edge, cut.back())) return Settled::dropped;
            const VertexId x = split(hit->edge, cut.back());
            add_street(s.from, x, cut, s.highway);
            ++report_.t_junctions;
            return Settled::joined;
        }
        // Out of the region: only to join a street there.
        const Vec2 end = line.back();
        if (leaves_region_inside_line(line) || !inside(region_, end)) {
            const auto w = nearest_vertex(end, snap, s.from);
            return w && end_at(s, line, *w) ? Settled::joined : Settled::dropped;
        }
        // A junction near its end: it ends there.
        if (const auto w = nearest_vertex(end, snap, s.from)) return end_at(s, line, *w) ? Settled::joined : Settled::dropped;
        // A street near its end: it meets it.
        if (const auto near = nearest_street(end, snap, s.from)) {
            const EdgeId e = near->edge;
            std::vector<Vec2> to_x = warped(line, near->where);
            squared(s, to_x, e, near->piece);
            const Vec2 x = to_x.back();
            const auto [a, b] = g_.edges[static_cast<std::size_t>(e)];
            const bool room = (g_.positions[static_cast<std::size_t>(a)] - x).norm() > snap && (g_.positions[static_cast<std::size_t>(b)] - x).norm() > snap;
            if (room && inside(region_, x) && static_cast<std::size_t>(e) >= fixed_edges_ && !first_hit(to_x, s.from, -1, e) && !(s_.min_block_m2 > 0 && splits_small_block(s.from, e, x))) {
                const VertexId junction = split(e, x);
                add_street(s.from, junction, to_x, s.highway);
                ++report_.t_junctions;
                return Settled::joined;
            }
            return Settled::dropped;
        }
        return Settled::open;
    }

    // A new junction at the end of `line`, shaped like `example` (none: a dead end).
    void open_end(const Street& s, const std::vector<Vec2>& line, const Example* example, bool mirror) {
        const VertexId v = add_vertex(line.back());
        add_street(s.from, v, line, s.highway);
        if (!example) return;
        const double arriving = angle_of(line.back() - line[line.size() - 2]);
        for (const Branch& b : example->branches) {
            Street next;
            next.from = v;
            next.heading = arriving + (mirror ? -b.turn : b.turn);
            next.length = b.length;
            next.shape = b.shape;
            if (mirror) {
                for (Vec2& q : next.shape) q.y() = -q.y();
            }
            next.highway = b.keeps_class ? s.highway : b.highway;
            next.main = main_class(next.highway);
            next.generation = s.generation + 1;
            next.order = order_++;
            queue_.push(std::move(next));
        }
    }

    // A street of the base that reaches the region is what joins the growth to the city: where
    // it fits nowhere, it is tried again turned a little further each time, and longer or shorter.
    void retry(const Street& s) {
        Street again = s;
        ++again.retries;
        const double step = (again.retries + 1) / 2 * (M_PI / 30); // 6, 6, 12, 12, ... degrees
        again.heading = s.heading + (again.retries % 2 ? step : -step);
        again.length = std::max(s.min_length, s.length * std::uniform_real_distribution<double>(0.7, 1.3)(rng_));
        again.order = order_++;
        queue_.push(std::move(again));
    }

    void trace(const Street& s) {
        if (degree(s.from) >= 4) return;
        std::vector<Vec2> line = lay(s);
        if (line.size() < 2 || clearance(s.from, line[1] - line[0]) < min_angle_) return;
        // Where the example is a bend of the street (a junction with one street on, of the same
        // class), the street goes on without a junction: a vertex of degree two would only
        // split one street in two. `open` is the line up to its last such bend.
        std::vector<Vec2> open;
        for (int bends = 0;; ++bends) {
            const Settled settled = settle(s, line);
            if (settled == Settled::joined) return;
            if (settled == Settled::dropped || nearest_vertex(line.back(), crowd_ * typical_, s.from)) {
                // Dropped: it ends at its last bend, if it had one.
                if (!open.empty() && !nearest_vertex(open.back(), crowd_ * typical_, s.from)) open_end(s, open, nullptr, false);
                else if (s.generation == 0 && s.retries < 8) retry(s);
                else drop();
                return;
            }
            const Example& example = example_for(s.main);
            const bool mirror = std::bernoulli_distribution(0.5)(rng_);
            if (bends < 16 && example.branches.size() == 1 && (example.branches.front().keeps_class || example.branches.front().highway == s.highway)) {
                const Branch& b = example.branches.front();
                Street on = s;
                on.heading = angle_of(line.back() - line[line.size() - 2]) + (mirror ? -b.turn : b.turn);
                on.length = b.length;
                on.shape = b.shape;
                if (mirror) {
                    for (Vec2& q : on.shape) q.y() = -q.y();
                }
                std::vector<Vec2> piece = lay_from(line.back(), on);
                open = line;
                line.insert(line.end(), piece.begin() + 1, piece.end());
                continue;
            }
            open_end(s, line, &example, mirror);
            return;
        }
    }

    bool leaves_region_inside_line(const std::vector<Vec2>& line) const {
        for (std::size_t k = 1; k + 1 < line.size(); ++k) {
            if (!inside(region_, line[k])) return true;
        }
        return false;
    }

    void drop() { ++report_.dropped; }

    std::optional<VertexId> nearest_vertex(const Vec2& p, double within, VertexId besides) const {
        std::optional<VertexId> best;
        double best_d = within;
        const Box window = spatial::around(p, within);
        for (auto it = vertices_.qbegin(bgi::intersects(window)); it != vertices_.qend(); ++it) {
            const VertexId w = it->second;
            if (w == besides || degree(w) == 0) continue;
            const double d = (g_.positions[static_cast<std::size_t>(w)] - p).norm();
            if (d < best_d) best = w, best_d = d;
        }
        return best;
    }

    struct Near {
        EdgeId edge = -1;
        Vec2 where = Vec2::Zero();
        std::size_t piece = 0;
    };
    std::optional<Near> nearest_street(const Vec2& p, double within, VertexId besides) const {
        std::optional<Near> best;
        double best_d = within;
        const Box window = spatial::around(p, within);
        for (auto it = segments_.qbegin(bgi::intersects(window)); it != segments_.qend(); ++it) {
            const EdgeId e = it->second;
            const auto [a, b] = g_.edges[static_cast<std::size_t>(e)];
            if (a == besides || b == besides) continue;
            const Vec2* q = g_.geometry_begin(e);
            for (std::size_t i = 0; i + 1 < g_.geometry_size(e); ++i) {
                const Vec2 d = q[i + 1] - q[i];
                const double t = std::clamp((p - q[i]).dot(d) / std::max(d.squaredNorm(), 1e-300), 0.0, 1.0);
                const Vec2 x = q[i] + t * d;
                const double dist = (x - p).norm();
                if (dist < best_d) best = Near{e, x, i}, best_d = dist;
            }
        }
        return best;
    }

    // Whether a street from v to a new junction at x on edge e would leave a block on either
    // side smaller than allowed.
    bool splits_small_block(VertexId v, EdgeId e, const Vec2& x) {
        const VertexId a = g_.edges[static_cast<std::size_t>(e)][0], b = g_.edges[static_cast<std::size_t>(e)][1];
        const auto x_id = static_cast<VertexId>(g_.vertex_count());
        std::vector<Vec2>& positions = g_.positions;
        positions.push_back(x);
        auto neighbours = [&](VertexId w) -> std::vector<VertexId> {
            std::vector<VertexId> out;
            if (w == x_id) return {a, b, v};
            for (const EdgeId f : adjacency_[static_cast<std::size_t>(w)]) {
                const VertexId o = other_end(f, w);
                if (f == e) out.push_back(x_id);
                else out.push_back(o);
            }
            if (w == v) out.push_back(x_id);
            return out;
        };
        const double left = block_left_of(positions, neighbours, v, x_id);
        const double right = block_left_of(positions, neighbours, x_id, v);
        positions.pop_back();
        return (left > 0 && left < s_.min_block_m2) || (right > 0 && right < s_.min_block_m2);
    }

    GeometricGraph& g_;
    std::size_t base_vertices_;
    const std::vector<Vec2>& region_;
    const TracingSettings& s_;
    std::mt19937_64& rng_;
    const ProgressCallback& progress_;
    TracingReport report_;
    std::vector<Example> main_examples_, other_examples_;
    std::size_t fixed_edges_ = 0; // the streets there before: never split (their ids and ends are kept)
    double right_share_ = 0.5; // of the examples' junctions: angles between neighbouring streets within 15 degrees of 90
    HighwayClass common_class_ = HighwayClass::residential; // of the examples' streets: that of a new side street
    double typical_ = 50.0; // median street of the examples, end to end
    double long_ = 100.0;   // their 90th percentile
    double expected_streets_ = 1.0;
    const double min_angle_ = M_PI / 6;
    // No new junction within this many typical streets of another: the spacing of junctions.
    const double crowd_ = 0.5;
    const double grid_tolerance_ = M_PI / 4;
    std::vector<std::vector<EdgeId>> adjacency_;
    RTree<VertexEntry> vertices_;
    RTree<EdgeEntry> segments_;
    std::priority_queue<Street, std::vector<Street>, Later> queue_;
    std::size_t order_ = 0;
};

} // namespace

TracingReport trace_streets(GeometricGraph& g, std::size_t base_vertices, const GeometricGraph& city,
                            const std::vector<Vec2>& region, const TracingSettings& settings, std::mt19937_64& rng,
                            const ProgressCallback& progress) {
    return Tracer(g, base_vertices, city, region, settings, rng, progress).run();
}

} // namespace ggg::growth_detail
