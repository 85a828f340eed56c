#pragma once
// The reports of long operations as JSON: one definition of each report's fields, which the
// CLI prints and the Python module returns as a dict (docs/cli.md lists them).
#include <nlohmann/json.hpp>

#include "ggg/synthesis/growth.hpp"

namespace ggg {

// Every field of GrowReport, flat: "placements", "rejected_crossing", "traced_streets", ...
nlohmann::json growth_report_json(const GrowReport& report);

} // namespace ggg
