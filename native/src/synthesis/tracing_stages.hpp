#pragma once
// The stages of tracing streets into a region (street_tracing.hpp), private to it: the city's
// junctions learned as examples (tracing_examples.cpp), the base's streets that reach the
// region found (tracing_seeds.cpp), each street's line laid along its heading and shape
// (tracing_lines.cpp) and joined to what it meets or dropped (tracing_constraints.cpp), with
// the graph and the indexes they all query and change (tracing_graph.cpp).
// street_tracing.cpp runs them: the streets, one at a time, main roads first.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <optional>
#include <queue>
#include <random>
#include <tuple>
#include <utility>
#include <vector>

#include "ggg/graph/geometric_graph.hpp"
#include "ggg/graph/road_class.hpp"
#include "ggg/graph/plane_geometry.hpp"
#include "ggg/graph/spatial_index.hpp"
#include "ggg/progress.hpp"
#include "street_tracing.hpp"

namespace ggg::growth_detail::tracing {

inline double angle_of(const Vec2& d) { return std::atan2(d.y(), d.x()); }
inline Vec2 unit(double angle) { return {std::cos(angle), std::sin(angle)}; }
inline double wrap(double a) { // into (-pi, pi]
    while (a <= -M_PI) a += 2 * M_PI;
    while (a > M_PI) a -= 2 * M_PI;
    return a;
}

// Main roads (and their links) are traced before the streets between them.
inline bool main_class(HighwayClass c) { return highway_rank(c) <= highway_rank(HighwayClass::tertiary_link); }

// Motorways, trunk roads and the links of any road are not traced: they are not streets of a
// district's pattern but routes through it, with ramps instead of junctions (the main roads
// are continued across the grown streets afterwards, street_hierarchy.hpp).
inline bool traced_class(HighwayClass c) {
    switch (c) {
    case HighwayClass::motorway: case HighwayClass::trunk: case HighwayClass::motorway_link: case HighwayClass::trunk_link:
    case HighwayClass::primary_link: case HighwayClass::secondary_link: case HighwayClass::tertiary_link:
        return false;
    default:
        return true;
    }
}

// A T-junction seen from its three streets (unit directions leaving it): two go on straight
// (within 30 degrees), the third is its side street, and `near` is the half of the through
// street at the sharper corner with it, `corner` that angle (radians, at most 90 degrees).
struct TShape {
    std::size_t side = 0, near = 0;
    double corner = 0.0;
};

inline std::optional<TShape> t_shape(const std::array<Vec2, 3>& out) {
    for (std::size_t k = 0; k < 3; ++k) {
        const std::size_t a = (k + 1) % 3, b = (k + 2) % 3;
        if (out[a].dot(out[b]) >= -std::cos(M_PI / 6)) continue;
        const std::size_t near = out[k].dot(out[a]) >= out[k].dot(out[b]) ? a : b;
        return TShape{k, near, std::acos(std::clamp(out[k].dot(out[near]), -1.0, 1.0))};
    }
    return std::nullopt;
}

// Junction islands are counted by the sharper corner of their T, in bins of 10 degrees.
inline constexpr std::size_t island_bins = 9;
inline std::size_t island_bin(double corner) {
    return std::min(island_bins - 1, static_cast<std::size_t>(std::max(0.0, corner) / (M_PI / 18)));
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
    // It goes on across the street it met (go_on_across): one street through a crossing, not
    // a new street from a junction, so the density cap that stops streets at junctions is
    // looser for it (trace).
    bool through = false;
    // It goes on straight across a grown corner (close_corners), to the street it meets.
    bool closes_corner = false;
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
inline Vec2 leaving(const GeometricGraph& g, EdgeId e, VertexId at) {
    const Vec2* p = g.geometry_begin(e);
    const std::size_t n = g.geometry_size(e);
    return g.edges[static_cast<std::size_t>(e)][0] == at ? p[1] : p[n - 2];
}

// The streets at each vertex of g (a street from a vertex to itself left out).
inline std::vector<std::vector<EdgeId>> streets_at(const GeometricGraph& g) {
    std::vector<std::vector<EdgeId>> at(g.vertex_count());
    for (std::size_t e = 0; e < g.edge_count(); ++e) {
        const auto [a, b] = g.edges[e];
        if (a == b) continue;
        at[static_cast<std::size_t>(a)].push_back(static_cast<EdgeId>(e));
        at[static_cast<std::size_t>(b)].push_back(static_cast<EdgeId>(e));
    }
    return at;
}

// Where the street e is the piece between the two T's of an offset crossing, their side
// streets (at e's first end, then at its second): both its ends T-junctions (`at`: the streets
// at each vertex) where of the two other streets one runs on straight (within 30 degrees) and
// the other leaves to one side, the two to opposite sides of the street. (Its length is the
// caller's to judge.)
inline std::optional<std::array<EdgeId, 2>> offset_sides(const GeometricGraph& g, const std::vector<std::vector<EdgeId>>& at, EdgeId e) {
    const auto [a, b] = g.edges[static_cast<std::size_t>(e)];
    if (a == b || at[static_cast<std::size_t>(a)].size() != 3 || at[static_cast<std::size_t>(b)].size() != 3) return std::nullopt;
    std::array<EdgeId, 2> side_streets{-1, -1};
    int sides[2] = {0, 0};
    for (int k = 0; k < 2; ++k) {
        const VertexId v = k == 0 ? a : b;
        const Vec2 pv = g.positions[static_cast<std::size_t>(v)];
        const Vec2 along = (leaving(g, e, v) - pv).normalized();
        std::array<EdgeId, 2> others{-1, -1};
        std::array<Vec2, 2> out;
        std::size_t n = 0;
        for (const EdgeId f : at[static_cast<std::size_t>(v)]) {
            if (f == e) continue;
            if (n == 2) return std::nullopt;
            others[n] = f;
            out[n++] = (leaving(g, f, v) - pv).normalized();
        }
        if (n != 2) return std::nullopt;
        const std::size_t on = along.dot(out[0]) < along.dot(out[1]) ? 0 : 1;
        if (along.dot(out[on]) > -std::cos(M_PI / 6)) return std::nullopt;
        sides[k] = cross(along, out[1 - on]) > 0 ? 1 : -1;
        side_streets[static_cast<std::size_t>(k)] = others[1 - on];
    }
    // Seen from either end, opposite sides of the street have the same sign.
    if (sides[0] != sides[1]) return std::nullopt;
    return side_streets;
}

// Traces the streets into one region (trace_streets).
class Tracer {
public:
    // Learns the examples: the base's junctions near the region, or the city's where the base
    // has too few (street_tracing.cpp).
    Tracer(GeometricGraph& g, std::size_t base_vertices, const GeometricGraph& city, const std::vector<Vec2>& region,
           const TracingSettings& settings, std::mt19937_64& rng, const ProgressCallback& progress);

    // The streets traced, one at a time from a queue, until none is left or the budget is
    // spent (street_tracing.cpp).
    TracingReport run();

private:
    // ---- the city's junctions (tracing_examples.cpp) ---------------------------------------

    // The junctions of `city` within `radius` of the region, each seen from each of its streets.
    void learn_examples(const GeometricGraph& city, double radius);

    // How many metres of street the city has per square metre of the ground it covers around
    // the region (density_; 0 where there is too little to say).
    void measure_density(const GeometricGraph& city, double radius);

    // The share of the ground measure_density measured on (every cell of it, not only those
    // with a street vertex near) that is farther than empty_reach typical streets from every
    // street: empty_share_.
    void measure_empty_ground(const GeometricGraph& city, double radius);

    // The class of a new side street: the examples' most common one.
    void pick_common_class(const std::vector<std::size_t>& class_counts);

    // An example junction at random: of a main road for a main road (where there are any).
    const Example& example_for(bool main);

    // ---- the graph and its indexes (tracing_graph.cpp) -------------------------------------

    // The adjacency and the indexes of the graph as it is, and the number of streets expected
    // (for the progress).
    void index();

    void index_edge(EdgeId e) { segments_.insert({spatial::edge_box(g_, e), e}); }

    std::size_t degree(VertexId v) const { return adjacency_[static_cast<std::size_t>(v)].size(); }

    VertexId other_end(EdgeId e, VertexId v) const {
        const auto& ends = g_.edges[static_cast<std::size_t>(e)];
        return ends[0] == v ? ends[1] : ends[0];
    }

    // The polyline of edge e read from its end v.
    std::vector<Vec2> line_from(EdgeId e, VertexId v) const { return polyline_from(g_, e, v); }

    // The end at v of street e moved to the vertex `to`, its polyline now `line` (read from its
    // far end, the same number of points, the last at `to`).
    void move_end(EdgeId e, VertexId v, VertexId to, std::vector<Vec2> line);

    // Whether a street joins v and w.
    bool adjacent(VertexId v, VertexId w) const;

    // The smallest angle between direction d leaving v and the streets already at v.
    double clearance(VertexId v, const Vec2& d) const;

    // The first place where the polyline meets a street other than those at `from` (or at
    // `to`, when given): (index of its piece, point, edge hit).
    struct Hit {
        std::size_t piece = 0;
        double t = 0.0;
        Vec2 where = Vec2::Zero();
        EdgeId edge = -1;
        std::size_t edge_piece = 0;
    };
    std::optional<Hit> first_hit(const std::vector<Vec2>& line, VertexId from, VertexId to = -1, EdgeId ignore = -1) const;

    // Whether the line has a point outside the region, from its point `from_piece` on.
    bool leaves_region(const std::vector<Vec2>& line, std::size_t from_piece) const;

    // Whether the line reaches into the region past its border (a tenth of a typical street in,
    // at one of its points after the first or the middle of one of its pieces).
    bool enters_region(const std::vector<Vec2>& line) const;

    // The share of the line's length inside the region, and its metres outside it.
    double share_inside(const std::vector<Vec2>& line) const;
    double length_outside(const std::vector<Vec2>& line) const;

    // Whether the line has a point outside the region between its ends.
    bool leaves_region_inside_line(const std::vector<Vec2>& line) const;

    // Whether a street from v to w (its polyline from v) would close a block smaller than allowed.
    // Asked last, just before the street is added: a block it allows is counted as made.
    bool closes_small_block(VertexId v, VertexId w);

    // Whether a street from v to a new junction at x on edge e would leave a block on either
    // side smaller than allowed. Asked last, as closes_small_block.
    bool splits_small_block(VertexId v, EdgeId e, const Vec2& x);

    // Whether blocks of these areas (0: not a closed block) may be made: none below the
    // sliver floor, small ones while they are no more common than in the city. Counts them.
    bool small_blocks(double left, double right);

    // The vertex (with a street) nearest p within `within`, other than `besides`.
    std::optional<VertexId> nearest_vertex(const Vec2& p, double within, VertexId besides) const;

    // The point of a street nearest p within `within`, of a street not at `besides`.
    struct Near {
        EdgeId edge = -1;
        Vec2 where = Vec2::Zero();
        std::size_t piece = 0;
    };
    std::optional<Near> nearest_street(const Vec2& p, double within, VertexId besides) const;

    // Whether v is a grown vertex of two streets that turn there by more than 45 degrees, or
    // a grown dead end where the density stopped the street on.
    bool corner_at(VertexId v) const;

    // The grown corner (or dead end) at v closed where it can be: one of its streets goes on
    // across it (trace), queued once a vertex; and every one left, at the end.
    void close_corner(VertexId v, std::size_t generation);
    void close_corners();
    std::vector<char> corner_tried_;
    std::vector<char> dense_end_; // grown ends the density stopped the first street on from

    // How far a street closing a corner goes to meet one, in typical streets, and how much
    // denser than the city's the streets where it ends may then be. (Three typical streets
    // made Porto's grown bearings more peaked than its own; half again the density made
    // Washington's grown district denser than the target allows.)
    static constexpr double corner_reach = 1.5;
    static constexpr double corner_slack = 1.25;

    // Whether the streets around the line, with it, would be denser than the city's: a
    // street is traced only where the ground around it still has fewer streets than the city
    // has on as much ground, and fewer junctions, so that a grown district is as dense as the
    // city it continues and its streets as long between junctions.
    // (`slack` times the city's density, for a street through a crossing.)
    bool denser_than_city(const std::vector<Vec2>& line, double slack = 1.0) const;

    // A vertex, a street (counted in the report) and a street split at `where` (the new
    // junction returned), with the adjacency and the indexes kept up.
    VertexId add_vertex(const Vec2& p);
    void add_street(VertexId v, VertexId w, const std::vector<Vec2>& line, HighwayClass highway);
    VertexId split(EdgeId e, const Vec2& where);

    // ---- streets joined across (tracing_across.cpp) -----------------------------------------

    // Loose ends of the base on opposite sides of the region that point at each other (within
    // a few degrees) are joined by a straight street, which crosses those joined before it in
    // new junctions. Such ends are not seeds any more (across_).
    void join_across();

    // A street joined across: from one loose end of the base to the other.
    struct Across {
        VertexId from = -1, to = -1;
        HighwayClass highway = HighwayClass::residential;
    };

    // A loose end of the base at the region's border, pointing into it.
    struct End {
        VertexId v;
        Vec2 ahead;
        HighwayClass highway;
    };

    // A straight street from `from` to `to` (vertices there), split into a junction at each of
    // `crossings` (a street and where it is crossed, in order along the way).
    void lay_straight(VertexId from, VertexId to, const std::vector<std::pair<EdgeId, Vec2>>& crossings, HighwayClass highway);

    // Whether the base's street runs straight up to `end`, for two typical streets back from it
    // (through the junctions on its way).
    bool runs_straight(const End& end) const;

    // Main roads that run straight across the grid up to the region (not `used` by a street
    // joined across) go on straight into it, two by two, to where their lines meet, crossing
    // the streets joined across on the way; they are added to `laid`.
    void lay_avenues(const std::vector<End>& ends, std::vector<char>& used, std::vector<Across>& laid);

    // Junctions along a street joined across, spaced as the city's streets run from junction
    // to junction, each opening the side streets of one of the city's junctions (traced then
    // as any other).
    void open_junctions(const Across& street);

    // ---- the seeds (tracing_seeds.cpp) -----------------------------------------------------

    // After tracing: a dead end of the base at the region that nothing was traced from, a
    // snap from a vertex with grown streets (most often the cut end of another street a few
    // metres along the cut, which was traced on), meets it there, as the two streets met a
    // few metres on in the city that was cut.
    void join_close_ends();

    // The base's streets that reach the region: a dead end or a junction with an open side
    // that points into the region, close enough to reach it with one street.
    void seed();

    // Where none does (TracingSettings::no_street_reaches): one street from the city's vertex
    // nearest the region that reaches it straight, crossing nothing (within `reach`), to
    // trace the district from, as a new district is reached by a road from the town.
    std::optional<std::pair<double, Street>> access_seed(double reach) const;

    // The point of the region's border nearest p.
    Vec2 nearest_on_ring(const Vec2& p) const;

    // How far along the ray from p the region begins (0 inside it), or -1 beyond `reach`.
    double entry_distance(const Vec2& p, const Vec2& d, double reach) const;

    // ---- a street's line (tracing_lines.cpp) -----------------------------------------------

    // Where the streets around a point run on a grid (most of their length along two
    // perpendicular directions), a street traced from there keeps to it: its heading is turned
    // onto the grid's nearest direction (grid_tolerance_, 45 degrees: every heading), so that
    // the small bends of the examples do not add up and streets meet square. Local, so that a
    // grid district and a winding one next to it each keep their own.
    std::optional<double> local_grid(const Vec2& p) const;

    // The heading turned onto the local grid at p, where it is within grid_tolerance_ of it.
    double on_grid(double heading, const Vec2& p) const;

    // The street's line from its start (or from p), along its heading (kept to the grid), its
    // length and its shape.
    std::vector<Vec2> lay(const Street& s) const { return lay_from(g_.positions[static_cast<std::size_t>(s.from)], s); }
    std::vector<Vec2> lay_from(const Vec2& p, const Street& s) const;

    // The polyline bent so that its end lands on `to` (its other points move in proportion).
    static std::vector<Vec2> warped(std::vector<Vec2> line, const Vec2& to);

    // ---- the local constraints (tracing_constraints.cpp) -----------------------------------

    // Whether the street from `from` along `line` to the vertex `to` fits: crosses nothing,
    // leaves room at both ends and closes no sliver.
    bool fits_to_vertex(VertexId from, const std::vector<Vec2>& line, VertexId to);

    // A street ending on a street nearly square to it meets it square (a T-junction), and one
    // at a slant does so as often as the city's junctions are right angles: its last point moves
    // to the foot of the perpendicular from the point before it, where that stays on the street
    // near by and crosses nothing.
    void squared(const Street& s, std::vector<Vec2>& line, EdgeId e, std::size_t piece);

    // A street that met another at the new junction x goes on across it, as often as the
    // city's junctions are crossings: a grid's streets run through, not into a T each.
    void go_on_across(const Street& s, const std::vector<Vec2>& line, VertexId x);

    // The street along `line`, bent to end at the junction w, added where it fits there.
    bool end_at(const Street& s, const std::vector<Vec2>& line, VertexId w);

    enum class Settled { joined, dropped, open };

    // The street along `line` joined to what it meets (a crossing, a junction or a street near
    // its end), or dropped where it cannot be; `open` when its end is on open ground.
    Settled settle(const Street& s, const std::vector<Vec2>& line);

    // ---- tracing (street_tracing.cpp) ------------------------------------------------------

    // Where more of the region is far from every street (empty_reach typical streets) than of
    // the ground around it (empty_share_), the farthest place of each empty piece (inside a grown
    // street that closed on itself, or where every street stopped short) gets a street: from
    // the nearest grown street, a new junction opened towards it, traced on as any other. False
    // where the region is no emptier than the city.
    bool open_empty_ground();

    // Offset crossings, as often as the city has them (offset_share_): at a grown crossing of
    // two straight streets, one side street moved a few metres (offsets_) along the street it
    // crosses, where it crosses nothing there. Two T's a few metres apart are the grain of
    // Porto or Monaco; a grid (Oakland) has none and keeps its crossings.
    void offset_crossings();

    // The two T's at the ends of the offset link `link` made one crossing: one of their side
    // streets `sides` (offset_sides; not a main road, nor one of the base) moved to end at the
    // other T, where it then crosses nothing and meets no street at less than min_angle_.
    // False where neither fits.
    bool join_offset(EdgeId link, const std::array<EdgeId, 2>& sides);

    // Junction islands, as often as the city's T's with the same corner on the same kind of
    // street have them (island_rate_): at a grown T-junction, a short street from the side street to the street
    // it meets, cutting the sharper corner between them, its ends as far along them as on
    // one of the city's islands (islands_). Porto's forks and slip roads close half of its
    // small blocks; the square T's of a grid seldom have one.
    void junction_islands();

    // The street that leaves the junction `from` as `branch` does, seen from a street arriving
    // along `arriving` (radians) of class `own`, mirrored or not; queued for tracing.
    void queue_branch(VertexId from, double arriving, const Branch& branch, bool mirror, HighwayClass own, std::size_t generation,
                      bool through = false);

    // A new junction at the end of `line`, shaped like `example` (none: a dead end).
    void open_end(const Street& s, const std::vector<Vec2>& line, const Example* example, bool mirror);

    // A street of the base that reaches the region is what joins the growth to the city: where
    // it fits nowhere, it is tried again turned a little further each time, and longer or shorter.
    void retry(const Street& s);

    // One street: laid, settled, and continued after an example junction (straight on
    // through the example's bends, which are no junctions).
    void trace(const Street& s);

    void drop() { ++report_.dropped; }

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
    double typical_ = 50.0; // median street of the examples, end to end, from junction to junction
    double long_ = 100.0;   // their 90th percentile
    double typical_edge_ = 50.0; // median edge of the examples' map (a street split where a tag changes, in pieces)
    // What the snaps of settle are shares of: how far a join may move a street's end. The
    // city's edges, not its streets, where its map splits them: moved further, a street's end
    // bends it off square.
    double snap_scale() const { return std::min(typical_, typical_edge_); }
    double density_ = 0.0;  // metres of street per square metre around the region (0: no cap)
    double junction_density_ = 0.0; // junctions (three streets or more) per square metre there
    std::size_t density_cells_ = 0; // cells of ground it was measured on
    // Of the ground around the region, the share farther than empty_reach typical streets from
    // every street (1: unknown).
    static constexpr double empty_reach = 2.0;
    double empty_share_ = 1.0;
    double expected_streets_ = 1.0;
    double region_size_ = 0.0; // the region's widest extent from its first corner
    const double min_angle_ = M_PI / 6;
    // No new junction within this many typical streets of another: the spacing of junctions.
    const double crowd_ = 0.5;
    const double grid_tolerance_ = M_PI / 4;
    std::vector<char> across_; // per base vertex: joined across the region (join_across)
    std::size_t blocks_closed_ = 0, small_blocks_closed_ = 0; // by tracing, for the city's share of small blocks
    // Of the city's crossings and offset crossings (two T's on a street a few metres apart,
    // their side streets to either side: Porto has as many as crossings, Oakland none), the
    // share of offset ones, and how far apart their two T's are.
    double offset_share_ = 0.0;
    std::vector<double> offsets_;
    // Of the city's T-junctions, by the street they meet (other or main) and their sharper
    // corner (island_bin), the share with a junction island, and each island's sides along
    // the side street and the street met.
    std::array<std::array<double, island_bins>, 2> island_rate_{};
    std::array<std::array<std::vector<std::pair<double, double>>, island_bins>, 2> islands_;
    // Junctions closer than the usual spacing (crowd_, the snap of settle) are made only as
    // often as the city has streets that short, and never closer than its shortest streets:
    // offset crossings, short links and the blocks they close are part of a city's grain.
    double short_share_ = 0.0;  // of the examples' streets, those shorter than crowd_ typical streets
    double shortest_ = 0.0;     // their 5th percentile
    std::size_t streets_made_ = 0, short_made_ = 0;
    bool short_allowed() const { return static_cast<double>(short_made_ + 1) <= short_share_ * static_cast<double>(streets_made_ + 1); }
    // The spacing kept from other junctions where `usual` is the rule: less while the city's
    // share of short streets allows.
    double spacing(double usual) const { return short_allowed() ? std::min(usual, std::max(shortest_, 1.0)) : usual; }
    void count_street(const Vec2& a, const Vec2& b);
    std::vector<std::vector<EdgeId>> adjacency_;
    spatial::RTree<spatial::VertexEntry> vertices_;
    spatial::RTree<spatial::EdgeEntry> segments_;
    std::priority_queue<Street, std::vector<Street>, Later> queue_;
    std::size_t order_ = 0;
};

} // namespace ggg::growth_detail::tracing
