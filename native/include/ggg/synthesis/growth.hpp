#pragma once
// Growing a street network into a region with a grammar's rules (beyond the paper, whose
// Fig. 18 places rules by hand): the streets that reach the region's border, or rules the
// user placed, are the frontier; rules chosen by their learned frequencies are placed there
// one at a time, turned to continue the street they start from, until the region is filled
// or a budget is met.
//
// A placement is a forward derivation (rewriting.hpp) of the rule's nonterminal, put on the
// frontier vertex, in a copy of the streets around it: one of the rule's vertices lands on
// the frontier vertex and merges with it, and the relaxed embedding joins the rule to the
// streets it meets. It is kept only if its new streets stay inside the region, cross no
// street (old or new), keep their distance from the streets already there and close no
// block much smaller than the city's small ones; else it is
// undone and another rule, vertex or direction is tried. Dead ends left at the end are
// joined to a vertex close ahead of them where that crosses nothing (or, with none, to the
// grown street ahead, at a new T-junction), and the main roads
// that reach the grown streets are continued through them (street_hierarchy.hpp).
//
// Deterministic: the same inputs and seed give the same streets.
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

#include "ggg/graph/geometric_graph.hpp"
#include "ggg/grammar/grammar.hpp"
#include "ggg/progress.hpp"

namespace ggg {

// A rule placed by hand (with the 3D cursor): growth starts from it as well.
struct RulePlacement {
    Symbol symbol = 0;
    Vec2 position = Vec2::Zero();
    Frame frame; // scale 0 or less: the rule's learned size
};

struct GrowOptions {
    std::uint64_t seed = 1;
    std::size_t max_placements = 200; // rules placed at most
    std::size_t max_vertices = 200'000; // the whole graph, base included
    // Placements tried in a row without success after which the region counts as filled (0:
    // only the rules placed by hand are placed).
    std::size_t patience = 150;
    // A base vertex this close to the region (metres; < 0: 5 % of the region's size) is a
    // street that reaches it.
    double border_m = -1.0;
    // A placed vertex this close to a street vertex (relative to the rule's size, as the
    // derivation's tolerance) becomes that vertex: how rules snap onto the streets.
    double snap = 0.12;
    // New vertices keep this fraction of the rule's typical edge length from other vertices.
    double spacing = 0.35;
    // Random turn (degrees) and relative size change of each placement around its aim.
    double turn_deg = 20.0;
    double size_jitter = 0.1;
    // Size of a rule without a learned size (hand-written grammars), metres per unit.
    double default_size_m = 100.0;
    // When the grammar's city is a grid (its streets run mostly along two perpendicular
    // directions), square rules keep to the grid of the streets around the region (where they
    // form one) or of the first square rule placed, within this many degrees; 0 = any turn.
    double grid_tolerance_deg = 10.0;
    // How much more often a rule with a block (a cycle) is chosen: weight x (1 + this x cycles).
    double block_preference = 1.0;
    // No placement (and no street closing a dead end) may close a block smaller than six
    // tenths of this quantile of the blocks of the grammar's city: the city's smallest
    // blocks are mostly slivers. Learned grammars only, which decode to their city; 0 = any.
    double smallest_block = 0.1;
    // Join dead ends to a vertex ahead of them within this multiple of the typical grown edge
    // length (grown streets are traced whole, so their edges are long).
    double close_dead_ends = 1.6;
    // At the end, grown dead ends shorter than this fraction of the typical grown street are
    // cut off (the loose ends of rules' streets that nothing was grown onto); 0 = keep them.
    double prune_stubs = 0.75;
    // Main roads that reach the grown streets continue through them (street_hierarchy.hpp).
    bool continue_hierarchy = true;
    // The streets that reach the region are first traced on into it, each new junction shaped
    // like one of the grammar's city's (street_tracing.hpp); rules then fill what is left.
    bool trace_streets = true;
    // Grown junctions become roundabouts as often as the base's near the region are ones
    // (street_cleanup.hpp).
    bool roundabouts = true;
    // Grown blocks get dead-end streets (cul-de-sacs, courts) as many as the base's blocks of
    // about their area near the region hold (street_cleanup.hpp).
    bool cul_de_sacs = true;
    // Last, grown streets are split where only two streets meet as often as the base's are
    // near the region (most maps split a street wherever one of its tags changes), so that
    // the grown district's graph has the city's share of such vertices (street_cleanup.hpp).
    bool split_streets = true;
    std::vector<RulePlacement> placements; // rules placed by hand, grown from first
};

// Every option of growth but the placements, as the CLI and Python offer it: visit(keyword,
// flag, help, field) for each, where keyword is ggg.grow_region's, flag is `ggg grow`'s (a bool
// whose flag starts with "--no-" is turned off by it) and field is a reference into `options`.
// The flags, the keywords, their defaults (ggg.option_defaults) and the docs' tables are made
// from this list, so a new option is a field of GrowOptions, a line here, its range in
// check_options, and its use.
template <typename Options, typename Visit> // Options: GrowOptions or const GrowOptions
void visit_grow_options(Options& o, Visit&& visit) {
    visit("seed", "--seed", "Seed of the random choices: the same seed gives the same streets", o.seed);
    visit("max_placements", "--max-placements", "Most rules placed", o.max_placements);
    visit("max_vertices", "--max-vertices", "Most vertices in the result, the base included", o.max_vertices);
    visit("patience", "--patience",
          "Failed placements in a row after which the region counts as full (0: only the rules placed by hand)", o.patience);
    visit("border_m", "--border", "How near the region (metres) a base street must end to be grown from; < 0: 5 % of its size",
          o.border_m);
    visit("snap", "--snap", "A placed vertex this close to a street vertex (relative to the rule's size) becomes that vertex", o.snap);
    visit("spacing", "--spacing", "New vertices keep this fraction of the rule's typical edge length from other vertices, and new streets from streets alongside them", o.spacing);
    visit("turn_deg", "--turn", "Random turn (degrees) of each placement around its aim", o.turn_deg);
    visit("size_jitter", "--size-jitter", "Random relative size change of each placement (0 to below 1)", o.size_jitter);
    visit("default_size_m", "--default-size", "Size (metres per unit) of a rule without a learned size (hand-written grammars)",
          o.default_size_m);
    visit("grid_tolerance_deg", "--grid-tolerance",
          "In a grid city, square rules keep to the grid around within this many degrees (0: any turn)", o.grid_tolerance_deg);
    visit("block_preference", "--block-preference", "How much more often a rule with a block is chosen: weight x (1 + this x cycles)",
          o.block_preference);
    visit("smallest_block", "--smallest-block",
          "No new street closes a block smaller than six tenths of this quantile of the city's blocks (0: any)", o.smallest_block);
    visit("close_dead_ends", "--close-dead-ends",
          "Join dead ends to a vertex ahead within this multiple of the typical grown edge length", o.close_dead_ends);
    visit("prune_stubs", "--prune-stubs", "Cut off grown dead ends shorter than this fraction of the typical grown street (0: keep)",
          o.prune_stubs);
    visit("continue_hierarchy", "--no-main-roads", "Do not continue the main roads that reach the grown streets through them",
          o.continue_hierarchy);
    visit("trace_streets", "--no-tracing", "Grow with rules alone: do not first trace the streets that reach the region on into it",
          o.trace_streets);
    visit("roundabouts", "--no-roundabouts", "Make no roundabouts: keep every grown junction a junction, whatever the base's are",
          o.roundabouts);
    visit("cul_de_sacs", "--no-cul-de-sacs",
          "Add no dead-end streets into the grown blocks, whatever the base's blocks of their size hold", o.cul_de_sacs);
    visit("split_streets", "--no-split-streets",
          "Keep grown streets whole between junctions: do not split them as often as the base's streets are split", o.split_streets);
}

// What became of one rule placed by hand: placed, or why it did not fit (a rule that does
// not fit changes nothing, so a user can be told which of their rules were used).
enum class PlacementOutcome : std::uint8_t {
    placed,
    outside,     // a new vertex would lie outside the region
    crossing,    // a new street would cross another
    crowded,     // a new vertex would come too close to another, or the streets around be denser than the city's
    star,        // a junction of more than four streets
    sharp,       // a new street would meet another at a sharp corner (under 30 degrees)
    small_block, // a new street would close a block smaller than the city's
    nothing_new, // every vertex landed on one already there
};
// "placed", "outside", ...: the words of the report.
std::string_view outcome_name(PlacementOutcome outcome);

struct GrowReport {
    std::size_t placements = 0;      // rules placed (the ones by hand included)
    std::size_t attempts = 0;
    std::size_t rejected_outside = 0;  // a new vertex outside the region
    std::size_t rejected_crossing = 0; // a new street crossing another
    std::size_t rejected_crowded = 0;  // a new vertex too close to another, or the streets around denser than the city's
    std::size_t rejected_off_grid = 0; // a square rule turned off the grid around
    std::size_t rejected_small_block = 0; // a new street closing a block smaller than the city's
    std::size_t rejected_star = 0;     // a junction of more than four streets
    std::size_t rejected_sharp = 0;    // a new street meeting another at a sharp corner
    std::size_t traced_seeds = 0;       // streets reaching the region that were traced on into it (where none does: the one laid to it)
    std::size_t traced_streets = 0;     // streets added by tracing
    std::size_t traced_joined = 0;      // traced streets that ended at a junction already there
    std::size_t traced_t_junctions = 0; // traced streets that ended on a street, split there
    std::size_t traced_dense = 0;       // streets not traced: the streets around were already as dense as the city's
    std::size_t traced_across = 0;      // streets of the base joined straight across to one facing them
    std::size_t traced_avenues = 0;     // main roads across the grid laid on straight until two meet
    std::size_t traced_crossed = 0;     // traced streets sent on across a street they met, as often as the city's junctions are crossings
    std::size_t traced_empty_ground = 0;     // streets opened into ground farther from every street than the city's ground around the region is
    std::size_t thinned_streets = 0; // grown streets between two grown T-junctions taken out where the grown junctions were denser than the city's
    std::size_t traced_closed_corners = 0; // grown corners (a street turning without a junction) made T-junctions: one of the two streets went on across to the street it met
    std::size_t traced_joined_offsets = 0; // grown offset crossings (two T's a few metres apart) made one crossing, where more grew than the city has
    std::size_t traced_offset_crossings = 0; // grown crossings made two T-junctions a few metres apart, as often as the city has them
    std::size_t traced_junction_islands = 0; // short streets cutting the corner of a grown T-junction (a fork, a slip road), as often as the city has them
    std::size_t added_vertices = 0;
    std::size_t added_edges = 0;
    std::size_t border_connections = 0; // placements that started from a base street
    std::size_t closing_edges = 0;      // dead ends joined at the end to a vertex ahead
    std::size_t t_junctions = 0;        // dead ends joined at the end to a grown street ahead, split there
    std::size_t pruned_stubs = 0;       // grown dead-end streets cut off at the end: the short ones, and longer ones while the grown streets end in the open more often than the city's
    std::size_t roundabouts = 0;        // grown junctions made roundabouts, as often as the city's junctions are ones
    std::size_t cul_de_sacs = 0;        // dead-end streets added into grown blocks, as many as the city's blocks of their size hold
    std::size_t squared_junctions = 0;  // grown T-junctions a little askew slid along their street until square, as often as the city's are square
    std::size_t dissolved_vertices = 0; // grown vertices between two grown streets of one class (and nothing else), made bends of one street
    std::size_t split_vertices = 0;     // vertices added along grown streets, so that as many grown vertices are bends (two streets) as the city's around the region
    std::size_t removed_crossing_streets = 0; // grown streets taken out again because they crossed a street
    std::size_t island_streets = 0;     // streets laid from grown streets joined to nothing (no base street reached them) to the nearest street of the city
    std::size_t main_road_routes = 0;   // main roads joined through the grown streets
    std::size_t raised_streets = 0;     // grown streets on those routes, now of a main road's class
    std::size_t main_road_connectors = 0; // main roads joined by a straight new main road
    std::size_t intersections = 0;      // grown streets split where such a connector crosses
    std::size_t main_road_extensions = 0; // main roads that ended at the region continued straight to a grown street
    bool grid = false;                 // the grammar's city is a grid: square rules kept to one
    bool filled = false;               // stopped because nothing more fits (or no frontier left)
    bool stopped_by_budget = false;    // stopped at max_placements or max_vertices
    std::vector<PlacementOutcome> hand_placements; // one per GrowOptions::placements, in order
};

// Throws UsageError naming the first option out of its range (NaN and infinities included).
void check_options(const GrowOptions& options);

// Growth continues a city: a region farther than this from every street of the base (metres)
// is refused as misplaced.
inline constexpr double max_distance_from_base_m = 20'000.0;

// The base graph with the grown streets added (base vertices and edges keep their ids).
// `region` is a simple polygon in the base graph's metres (not closed: the last point is not
// a copy of the first). Throws UsageError for a region with fewer than three points, no area
// or sides that cross, a region farther than max_distance_from_base_m from a base that has
// streets, a grammar without rules, a placement of an unknown symbol, and GrammarError for a
// malformed grammar.
GeometricGraph grow_region(const GeometricGraph& base, const Grammar& grammar, const std::vector<Vec2>& region,
                           const GrowOptions& options = {}, GrowReport* report = nullptr,
                           const ProgressCallback& progress = {});

} // namespace ggg
