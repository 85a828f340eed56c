#pragma once
// The stages of growth into a region (synthesis/growth.hpp), private to it: each rule derived
// to the streets one placement adds (growth_prototypes.cpp), the rules placed one at a time on
// the frontier (growth_placement.cpp), and the dead ends closed and the short stubs cut once
// the region is full (growth_dead_ends.cpp). growth.cpp runs them (Grower::run) with the
// streets traced into the region first (street_tracing.hpp) and the grown streets tidied last
// (street_cleanup.hpp); it holds the indexes that every stage queries.
#include <array>
#include <cmath>
#include <cstddef>
#include <optional>
#include <random>
#include <utility>
#include <vector>

#include "ggg/grammar/grammar.hpp"
#include "ggg/graph/geometric_graph.hpp"
#include "ggg/graph/plane_geometry.hpp"
#include "ggg/graph/spatial_index.hpp"
#include "ggg/progress.hpp"
#include "ggg/synthesis/growth.hpp"

namespace ggg::growth_detail {

// A rule derived all the way to streets, at unit size: what one placement adds.
struct Prototype {
    Symbol symbol = 0;
    double size_m = 1.0;
    double weight = 1.0;
    std::vector<Vec2> positions;
    std::vector<std::array<int, 2>> edges;
    std::vector<int> attach; // vertices that can sit on a frontier vertex: the ends and corners
    Vec2 centroid = Vec2::Zero();
    double radius = 0.0;    // farthest vertex from the centroid
    double edge_length = 0.0; // median
    // Its streets' directions modulo 90 degrees (length-weighted four-fold mean): how square
    // the rule is (1: every street along one of two perpendicular directions), and which way.
    double squareness = 0.0;
    double square_angle = 0.0; // radians, in [-pi/4, pi/4)
};

// Prototypes (growth_prototypes.cpp)

// Length-weighted four-fold mean of segment directions: (squareness, angle modulo 90 degrees).
std::pair<double, double> four_fold(const std::vector<std::pair<Vec2, Vec2>>& segments);

inline double wrap_quarter(double a) { // into [-pi/4, pi/4)
    return a - M_PI / 2 * std::floor((a + M_PI / 4) / (M_PI / 2));
}

// The rule derived `depth` levels deep, at unit size, with its weight for the random choice
// of a rule (how often its streets occur, more for the blocks it closes).
Prototype prototype_of(const Grammar& grammar, const Rule& rule, int depth, const GrowOptions& o);

// A street a rule can be glued onto: one of the rule's edges is laid on it (the rule's two
// vertices merge with its ends), on the side the placement chooses.
struct FrontierEdge {
    VertexId a = -1;
    VertexId b = -1;
    int failures = 0;
};

// Growth into one region (grow_region): the graph, its indexes and the frontier, and the
// stages that change them.
class Grower {
public:
    Grower(const GeometricGraph& base, const Grammar& grammar, const std::vector<Vec2>& region, const GrowOptions& o,
           const ProgressCallback& progress)
        : g_(base), grammar_(grammar), region_(region), o_(o), progress_(progress), rng_(o.seed) {}

    // Rules placed until the region is full, then the dead ends and stubs, the streets
    // tidied and the main roads continued (growth.cpp).
    GeometricGraph run(GrowReport& report);

private:
    // ---- the graph and its indexes (growth.cpp) --------------------------------------------

    // The base, as the city whose junctions traced streets copy (for a hand-written grammar).
    const GeometricGraph& base_copy_for_style();

    // The indexes again, after the streets were traced (the base stays the base).
    void reindex();

    // The base's size (what growth never changes), the adjacency and the indexes.
    void index_graph();

    void index_edge(EdgeId e) { segments_.insert({spatial::edge_box(g_, e), e}); }

    bool near_region(const Vec2& p, double border) const { return inside(region_, p) || distance_to_ring(region_, p) <= border; }

    // Whether the segment ab crosses a street of the graph.
    bool crosses(const Vec2& a, const Vec2& b) const;

    // ---- placement (growth_placement.cpp) --------------------------------------------------

    // The region's long axis (a unit vector).
    Vec2 principal_axis() const;

    // One try at the street ab: a rule chosen by its frequency, one of its edges of about
    // the street's length laid on ab, on one side or the other.
    bool glue(const FrontierEdge& at);

    // Where no edge of the rule fits the street: one of the rule's ends or corners is put on
    // an end of the street, the rule turned to lie beyond it, along the grid if there is one.
    bool attach(const Prototype& p, const FrontierEdge& at);

    // No street reaches the region: the most frequent rule that fits goes in its middle,
    // along the region's long axis.
    void seed_at_centre();

    // A rule placed by hand (GrowOptions::placements), its outcome recorded in the report.
    void place_by_hand(const RulePlacement& placed);

    // Counts a placement refused for `why` and remembers it (for the rules placed by hand).
    bool reject(PlacementOutcome why);

    // Derives the rule at `origin` in a copy of the streets around it and keeps the result
    // if it fits. True when it was kept.
    bool place(const Prototype& p, const Frame& frame, const Vec2& origin, VertexId anchor, bool by_hand = false);

    // ---- dead ends and stubs (growth_dead_ends.cpp) ----------------------------------------

    // Whether a street from v to w would close a block smaller than the city's small ones.
    bool closes_small_block(VertexId v, VertexId w);

    // The smallest angle (radians) between the direction d leaving w and the streets already
    // there (along their first piece, as `ggg compare` measures junction angles); pi where none.
    double clearance_at(VertexId w, const Vec2& d) const;

    // The first piece of each street at v, pointing away from it (zero-length ones left out).
    std::vector<Vec2> first_pieces_at(VertexId v) const;

    // A dead end (a grown one, or one of the base that points into the region with nothing
    // grown on) is joined to the vertex ahead of it that is closest, where the joining street
    // crosses nothing: streets meet the ones around instead of stopping short.
    void close_dead_ends();

    // Grown dead-end streets (from the dead end through its bends to a junction) shorter than
    // o_.prune_stubs times the typical grown street are cut off: they are the ends of rules'
    // streets that led on to a neighbouring block in the city and that nothing was grown
    // onto. Longer ones, up to two typical streets, shortest first, go too while the grown
    // streets have a larger share of dead ends than the city around the region. One pass,
    // so that a street is shortened by one stub at most.
    void prune_stubs();

    // The share of dead ends among the base's ends and junctions (its vertices of other than two
    // streets) around the region, `margin` metres clear of it and of the extract's edges; none
    // where there are too few to say.
    std::optional<double> city_dead_end_share(double margin) const;

    // The base's ends and junctions (its vertices of other than two streets) around the region,
    // `margin` metres clear of it and of the extract's edges.
    std::vector<VertexId> city_around(double margin) const;

    // The narrowest junction angles (radians) of the city around the region, `margin` metres
    // clear of it: the angle 3 % of its junctions' angles are below, at least 10 and at most
    // 30 degrees (30 where there are too few junctions to say).
    double city_narrow_angle(double margin) const;

    // The dead end v continued straight ahead onto the first street it meets within reach,
    // when that is a grown street, the meeting point keeps its distance from the street's
    // ends and the angle there is min_angle (radians) or more: the street is split there into
    // a T-junction. False when nothing was joined.
    bool join_street_ahead(VertexId v, const Vec2& ahead, double reach, const EdgeAttributes& attributes, double min_angle);

    // The dead end v joined to the nearest point of a grown street within reach and within
    // 45 degrees of straight ahead (a carriageway merging into the street beside it), split
    // there into a T-junction, when the joining street crosses nothing. False when nothing was.
    bool join_street_beside(VertexId v, const Vec2& ahead, double reach, const EdgeAttributes& attributes);

    // The street from v to the point x of the grown street `hit`, split there into a
    // T-junction, when x keeps its distance from the street's ends, the street meets it at
    // min_angle (radians) or more, stays in the region and leaves no block smaller than the
    // city's small ones. False when it does not fit.
    bool t_junction(VertexId v, EdgeId hit, const Vec2& x, const EdgeAttributes& attributes, double min_angle);

    GeometricGraph g_;
    GeometricGraph style_city_; // the city whose junctions traced streets copy
    const Grammar& grammar_;
    const std::vector<Vec2>& region_;
    const GrowOptions& o_;
    const ProgressCallback& progress_;
    std::mt19937_64 rng_;
    GrowReport* report_ = nullptr;
    PlacementOutcome last_outcome_ = PlacementOutcome::nothing_new;
    std::vector<Prototype> prototypes_;
    std::vector<double> weights_;
    int depth_ = 1;
    std::size_t base_vertices_ = 0, base_edges_ = 0;
    std::vector<std::vector<VertexId>> adjacency_;
    spatial::RTree<spatial::VertexEntry> vertices_;
    spatial::RTree<spatial::EdgeEntry> segments_;
    std::vector<FrontierEdge> frontier_;
    Vec2 centre_ = Vec2::Zero();
    bool grid_city_ = false;
    double min_block_m2_ = 0.0;   // smallest block a placement may close (0: any)
    double split_block_m2_ = 0.0; // smallest half of a block that a T-junction may leave
    double small_block_share_ = 0.0; // of the city's blocks above the sliver floor, those smaller than split_block_m2_
    std::optional<double> grid_angle_; // the grid the growth keeps to (modulo 90 degrees), once there is one
    bool grid_around_ = false; // the base's streets next to the region run on a grid
    // The city's metres of street and junctions per square metre next to the region, as
    // tracing measured them, and the radius of the disc a placement is held to them in (0: no cap).
    double street_density_ = 0.0;
    double junction_density_ = 0.0;
    double density_radius_ = 0.0;
};

} // namespace ggg::growth_detail
