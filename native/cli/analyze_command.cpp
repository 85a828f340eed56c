#include "analyze_command.hpp"

#include <chrono>
#include <iostream>
#include <sstream>
#include <unordered_map>

#include <nlohmann/json.hpp>

#include "ggg/analysis/analyzer.hpp"
#include "ggg/error.hpp"
#include "ggg/io/read_graph.hpp"
#include "ggg/io/reports.hpp"

namespace ggg::cli {

namespace {

// "12x10" -> angle and distance cells.
void parse_grid(const std::string& text, DetectionOptions& o) {
    const auto x = text.find('x');
    try {
        if (x == std::string::npos) throw std::invalid_argument(text);
        std::size_t used_a = 0;
        std::size_t used_d = 0;
        const std::string a = text.substr(0, x);
        const std::string d = text.substr(x + 1);
        o.angle_cells = std::stoi(a, &used_a);
        o.distance_cells = std::stoi(d, &used_d);
        if (used_a != a.size() || used_d != d.size()) throw std::invalid_argument(text);
    } catch (const std::exception&) {
        throw UsageError("--grid: expected ANGLESxDISTANCES such as 12x10, got '" + text + "'");
    }
}

std::vector<std::int64_t> parse_ids(const std::string& text) {
    std::vector<std::int64_t> ids;
    std::stringstream in(text);
    std::string item;
    while (std::getline(in, item, ',')) {
        try {
            std::size_t used = 0;
            ids.push_back(std::stoll(item, &used));
            if (used != item.size()) throw std::invalid_argument(item);
        } catch (const std::exception&) {
            throw UsageError("--seed-osm-nodes: '" + item + "' is not an OSM node id");
        }
    }
    return ids;
}

} // namespace

std::vector<VertexId> seed_vertices(const GeometricGraph& graph, const std::string& osm_ids) {
    std::unordered_map<std::int64_t, VertexId> vertex_of;
    for (std::size_t v = 0; v < graph.vertex_count(); ++v) {
        if (graph.vertex_osm_ids[v] != 0) vertex_of.emplace(graph.vertex_osm_ids[v], static_cast<VertexId>(v));
    }
    std::vector<VertexId> seed;
    for (std::int64_t id : parse_ids(osm_ids)) {
        const auto it = vertex_of.find(id);
        if (it == vertex_of.end()) {
            throw UsageError("--seed-osm-nodes: OSM node " + std::to_string(id) +
                             " is not a vertex of the road graph (a seed is made of intersections and road ends; "
                             "--keep-shape-nodes makes every node a vertex)");
        }
        seed.push_back(it->second);
    }
    return seed;
}

void AnalysisFlags::add_to(CLI::App& c) {
    c.add_option("--grid", grid, "Polar grid of the vertex expansion: ANGLESxDISTANCES cells")->capture_default_str();
    c.add_option("--cut", cut, "Fraction of the least frequent patterns not grown further, once patterns are formed")
        ->check(number_in(0.0, 0.99))
        ->capture_default_str();
    c.add_flag("--full", full, "Grow every pattern (no frequency cut): slower, the reference for --cut");
    c.add_option("--max-order", max_order, "Largest pattern, in vertices (0 = until nothing repeats, within --max-seconds and --max-memory)")
        ->check(whole_number(0, 64))
        ->capture_default_str();
    c.add_option("--min-count", min_count, "Fewest occurrences for a pattern to count as repeated")
        ->check(count_from<std::size_t>(1))
        ->capture_default_str();
    c.add_option("--tolerance", tolerance, "How far a copy may be from a pattern (seed search, exact recount), relative to its size")
        ->check(number_in(0.0, 0.99))
        ->capture_default_str();
    c.add_option("--scale", scale, "How sizes compare: similarity (any size), rigid (same size), range (within 2x)")
        ->capture_default_str();
    c.add_option("--min-aspect", min_aspect, "Only patterns whose shape is at least this square (0..1)")
        ->check(number_in(0.0, 1.0));
    c.add_option("--min-leaves", min_leaves, "Only patterns with at least this many leaves")->check(count_from<std::size_t>(0));
    c.add_option("--min-irregularity", min_irregularity, "Only patterns at least this irregular, in degrees (0..45)")
        ->check(number_in(0.0, 45.0));
    c.add_option("--recount", recount, "Count the leading N patterns exactly: every copy within --tolerance of the mean of those copies (0 = off)")
        ->check(whole_number(0, 100'000))
        ->capture_default_str();
    c.add_option("--max-seconds", max_seconds,
                 "Time budget: stop growing patterns after this many seconds and keep what was found (0 = none; < 0: 120 with --max-order 0, else none)")
        ->check(finite_number)
        ->capture_default_str();
    c.add_option("--max-memory", max_memory_mb,
                 "Memory budget in MB for the patterns held: stop growing them beyond it and keep what was found (0 = none)")
        ->check(non_negative)
        ->capture_default_str();
}

AnalyzeOptions AnalysisFlags::options() const {
    AnalyzeOptions options;
    parse_grid(grid, options.detection);
    options.detection.cut = cut;
    options.detection.full = full;
    options.detection.max_order = max_order;
    options.detection.min_count = min_count;
    options.detection.max_seconds = max_seconds;
    options.detection.max_memory_mb = max_memory_mb;
    options.detection.scale_mode = scale_mode_from_name(scale);
    options.tolerance = tolerance;
    options.recount_top = recount;
    options.constraints.min_aspect = min_aspect;
    options.constraints.min_leaves = min_leaves;
    options.constraints.min_irregularity_deg = min_irregularity;
    check_options(options.detection);
    return options;
}

void AnalyzeCommand::add_to(CLI::App& app) {
    command_ = app.add_subcommand("analyze", "Find the street patterns that repeat (isogroups) and rank them; prints JSON");
    auto& c = *command_;
    c.add_option("INPUT", input_, "Input road graph (OSM, GeoJSON or .ggraph)")->required();
    import_.add_to(c);
    analysis_.add_to(c);
    c.add_option("--seed-osm-nodes", seed_osm_nodes_,
                 "Comma-separated OSM node ids: start from the subgraph they induce instead of every edge");
    c.add_flag("--seed-within-tolerance", seed_within_tolerance_,
               "The seed's copies are only those within --tolerance of the seed (default: also every copy the "
               "automatic analysis groups with it)");
    c.add_option("--top", top_, "Print only the best N isogroups (0 = all)")->check(count_from<std::size_t>(0));
    c.add_flag("--occurrences", occurrences_, "List the OSM node ids of every occurrence");
    c.add_flag("--stats", stats_, "Also report per-order counts and peak memory");
}

int AnalyzeCommand::run() const {
    AnalyzeOptions options = analysis_.options();

    const auto t0 = std::chrono::steady_clock::now();
    const GeometricGraph graph = read_graph(input_, import_.options(), nullptr, terminal_progress());
    const auto t1 = std::chrono::steady_clock::now();
    if (!seed_osm_nodes_.empty()) options.seed = seed_vertices(graph, seed_osm_nodes_);
    options.include_analysis_group = !seed_within_tolerance_;
    const Analysis analysis = analyze(graph, options, terminal_progress());
    const std::chrono::duration<double> seconds = std::chrono::steady_clock::now() - t1;
    const std::chrono::duration<double> import_seconds = t1 - t0;

    AnalysisReportOptions report;
    report.top = top_;
    report.occurrence_osm_nodes = occurrences_;
    report.orders = stats_;
    nlohmann::json out = analysis_report_json(graph, analysis, report);
    out["seconds"] = seconds.count();
    out["import_seconds"] = import_seconds.count();
    if (stats_) out["peak_memory_mb"] = peak_memory_mb();
    std::cout << out.dump() << std::endl;
    if (analysis.stopped_by_budget) std::cerr << "note: stopped growing patterns at the time or memory budget (--max-seconds, --max-memory); the patterns found so far are reported\n";
    return 0;
}

} // namespace ggg::cli
