#include "ggg/io/reports.hpp"

namespace ggg {

nlohmann::json growth_report_json(const GrowReport& r) {
    return {
        {"placements", r.placements},
        {"attempts", r.attempts},
        {"rejected_outside", r.rejected_outside},
        {"rejected_crossing", r.rejected_crossing},
        {"rejected_crowded", r.rejected_crowded},
        {"rejected_off_grid", r.rejected_off_grid},
        {"rejected_small_block", r.rejected_small_block},
        {"rejected_star", r.rejected_star},
        {"traced_seeds", r.traced_seeds},
        {"traced_streets", r.traced_streets},
        {"traced_joined", r.traced_joined},
        {"traced_t_junctions", r.traced_t_junctions},
        {"added_vertices", r.added_vertices},
        {"added_edges", r.added_edges},
        {"border_connections", r.border_connections},
        {"closing_edges", r.closing_edges},
        {"t_junctions", r.t_junctions},
        {"pruned_stubs", r.pruned_stubs},
        {"dissolved_vertices", r.dissolved_vertices},
        {"removed_crossing_streets", r.removed_crossing_streets},
        {"main_road_routes", r.main_road_routes},
        {"raised_streets", r.raised_streets},
        {"main_road_connectors", r.main_road_connectors},
        {"intersections", r.intersections},
        {"grid", r.grid},
        {"filled", r.filled},
        {"stopped_by_budget", r.stopped_by_budget},
    };
}

} // namespace ggg
