// Forward modelling: rules, embedding, derivation and grammar files (paper 3.2, 3.3, 7).
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <map>
#include <set>

#include <nlohmann/json.hpp>

#include "fixtures.hpp"
#include "ggg/error.hpp"
#include "ggg/io/grammar_file.hpp"
#include "ggg/io/graph_file.hpp"
#include "ggg/grammar/rewriting.hpp"

using namespace ggg;

namespace {

constexpr double deg = M_PI / 180.0;

Grammar sierpinski() { return read_grammar(std::string(GGG_SAMPLES_DIR) + "/sierpinski.grammar.json"); }

using Key = std::pair<long long, long long>;
Key key(const Vec2& p) { return {std::llround(p.x() * 1e6), std::llround(p.y() * 1e6)}; }

// The Sierpinski triangle after n subdivisions, as sets of corner positions and edges.
void sierpinski_reference(int n, std::set<Key>& corners, std::set<std::pair<Key, Key>>& edges) {
    std::vector<std::array<Vec2, 3>> triangles{{Vec2(-500, -288.67513459481287), Vec2(500, -288.67513459481287), Vec2(0, 577.3502691896257)}};
    for (int level = 0; level < n; ++level) {
        std::vector<std::array<Vec2, 3>> next;
        for (const auto& [a, b, c] : triangles) {
            const Vec2 ab = (a + b) / 2, bc = (b + c) / 2, ca = (c + a) / 2;
            next.push_back({a, ab, ca});
            next.push_back({ab, b, bc});
            next.push_back({ca, bc, c});
        }
        triangles.swap(next);
    }
    for (const auto& t : triangles) {
        for (int i = 0; i < 3; ++i) {
            corners.insert(key(t[i]));
            edges.insert(std::minmax(key(t[i]), key(t[(i + 1) % 3])));
        }
    }
}

std::size_t neighbours_at(const GeometricGraph& g, VertexId v, const Vec2& where) {
    std::size_t n = 0;
    for (const auto& [a, b] : g.edges) {
        const VertexId other = a == v ? b : b == v ? a : -1;
        if (other >= 0 && (g.positions[static_cast<std::size_t>(other)] - where).norm() < 1e-9) ++n;
    }
    return n;
}

VertexId vertex_at(const GeometricGraph& g, const Vec2& where) {
    for (std::size_t v = 0; v < g.vertex_count(); ++v) {
        if ((g.positions[v] - where).norm() < 1e-9) return static_cast<VertexId>(v);
    }
    return -1;
}

std::string grammar_error(const std::string& text) {
    try {
        parse_grammar(text, "g.json");
    } catch (const GrammarError& e) {
        return e.what();
    }
    return "(no GrammarError)";
}

} // namespace

TEST(Sierpinski, CountsFollowTheClosedForm) {
    const Grammar g = sierpinski();
    for (int n = 0; n <= 6; ++n) {
        GeometricGraph graph = g.axiom_graph();
        DeriveOptions options;
        options.max_steps = n;
        const DeriveReport report = derive(graph, g, options);
        EXPECT_EQ(report.steps, n);
        EXPECT_FALSE(report.stopped_by_budget);
        // Every P stands for one corner of one triangle: 3^(n+1) corners and edges. Two corners
        // of neighbouring triangles share a place, and each place is one vertex that carries
        // both rewrites: (3^(n+1) + 3) / 2 vertices, one graph.
        const auto three = static_cast<std::size_t>(std::pow(3, n + 1));
        EXPECT_EQ(graph.vertex_count(), (three + 3) / 2) << "n = " << n;
        EXPECT_EQ(graph.vertex_count() + graph.more_rewrites.size(), three) << "n = " << n;
        EXPECT_EQ(graph.edge_count(), three) << "n = " << n;
        EXPECT_EQ(check_simple(graph), "");
        std::set<Key> places;
        for (const Vec2& p : graph.positions) places.insert(key(p));
        EXPECT_EQ(places.size(), graph.vertex_count()) << "n = " << n;
        EXPECT_EQ(ggg::test::component_count(graph), 1u) << "n = " << n;
    }
}

TEST(Sierpinski, GeometryIsTheSierpinskiTriangle) {
    const Grammar g = sierpinski();
    for (int n : {1, 3, 5}) {
        GeometricGraph graph = g.axiom_graph();
        DeriveOptions options;
        options.max_steps = n;
        derive(graph, g, options);
        std::set<Key> corners, places;
        std::set<std::pair<Key, Key>> edges, reference_edges;
        sierpinski_reference(n, corners, reference_edges);
        for (const Vec2& p : graph.positions) places.insert(key(p));
        for (const auto& [a, b] : graph.edges) edges.insert(std::minmax(key(graph.positions[static_cast<std::size_t>(a)]), key(graph.positions[static_cast<std::size_t>(b)])));
        EXPECT_EQ(places, corners) << "n = " << n;
        EXPECT_EQ(edges, reference_edges) << "n = " << n;
        // Frames: each P points along its triangle's edge to the next corner, half the size per step.
        for (std::size_t v = 0; v < graph.vertex_count(); ++v) EXPECT_NEAR(graph.frames[v].scale(), 1000.0 / std::pow(2, n), 1e-9);
        for (const PendingRewrite& r : graph.more_rewrites) {
            EXPECT_NEAR(r.frame.scale(), 1000.0 / std::pow(2, n), 1e-9);
            EXPECT_LT((r.frame.t - graph.positions[static_cast<std::size_t>(r.vertex)]).norm(), 1e-6);
        }
    }
}

TEST(Rule, Figure3RuleWithTransformsAndEmbedding) {
    // q -> triangle a, b, c with embedding a: Rotate 90, {[-1,0]}; b: Scale 1/2, {[0,1]};
    // c: I, {[0,-1], [-1,0]}, applied to a q whose frame is scaled by 2 and turned 90 degrees.
    Grammar g;
    g.symbol_names = {"q"};
    Rule rule;
    rule.symbol = 1;
    rule.vertices = {{{0, 0}, 0, {1.0, 90.0}, {{{-1, 0}}}}, {{1, 0}, 0, {0.5, 0.0}, {{{0, 1}}}}, {{0.5, 1}, 0, {1.0, 0.0}, {{{0, -1}}, {{-1, 0}}}}};
    rule.edges = {{0, 1}, {1, 2}, {2, 0}};
    g.rules = {rule};
    g.axiom_vertices = {{{0, 0}, 1, {}}};
    const Similarity2 frame = Similarity2::from(2.0, 90 * deg, {10, 10});
    GeometricGraph host;
    const VertexId q = place_nonterminal(host, 1, {10, 10}, {2.0, 90.0});
    const std::vector<Vec2> expected_partners{frame.apply({-1, 0}), frame.apply({1, 1}), frame.apply({0.5, 0}), frame.apply({-0.5, 1})};
    for (const Vec2& p : expected_partners) host.add_edge(q, host.add_vertex(p), {});
    GeometricGraph graph = host;
    DeriveOptions options;
    const DeriveReport report = derive(graph, g, options);
    EXPECT_EQ(report.totals.rewrites, 1u);
    EXPECT_EQ(graph.vertex_count(), 7u);
    EXPECT_EQ(graph.edge_count(), 7u); // the triangle and four embedding edges; q's edges are gone
    EXPECT_EQ(report.totals.embedding_edges, 4u);
    const VertexId a = vertex_at(graph, frame.apply({0, 0}));
    const VertexId b = vertex_at(graph, frame.apply({1, 0}));
    const VertexId c = vertex_at(graph, frame.apply({0.5, 1}));
    ASSERT_GE(a, 0);
    ASSERT_GE(b, 0);
    ASSERT_GE(c, 0);
    EXPECT_EQ(neighbours_at(graph, a, expected_partners[0]), 1u);
    EXPECT_EQ(neighbours_at(graph, b, expected_partners[1]), 1u);
    EXPECT_EQ(neighbours_at(graph, c, expected_partners[2]), 1u);
    EXPECT_EQ(neighbours_at(graph, c, expected_partners[3]), 1u);
    // T_i composes with q's frame: a is turned 90 + 90 degrees at scale 2, b halves the scale.
    EXPECT_NEAR(graph.frames[static_cast<std::size_t>(a)].angle(), 180 * deg - (graph.frames[static_cast<std::size_t>(a)].angle() > 0 ? 0 : 360 * deg), 1e-12);
    EXPECT_NEAR(graph.frames[static_cast<std::size_t>(a)].scale(), 2.0, 1e-12);
    EXPECT_NEAR(graph.frames[static_cast<std::size_t>(b)].scale(), 1.0, 1e-12);
    EXPECT_NEAR(graph.frames[static_cast<std::size_t>(b)].angle(), 90 * deg, 1e-12);

    // Strict: with one expected partner missing the rule is not applied at all.
    GeometricGraph partial;
    const VertexId q2 = place_nonterminal(partial, 1, {10, 10}, {2.0, 90.0});
    for (std::size_t i = 0; i < 3; ++i) partial.add_edge(q2, partial.add_vertex(expected_partners[i]), {});
    GeometricGraph strict_graph = partial;
    options.strict = true;
    const DeriveReport strict = derive(strict_graph, g, options);
    EXPECT_EQ(strict.totals.refused, 1u);
    EXPECT_EQ(strict.steps, 0);
    EXPECT_EQ(strict_graph.vertex_count(), partial.vertex_count());
    EXPECT_EQ(strict_graph.symbols[static_cast<std::size_t>(q2)], 1u);
    // Relaxed: applied, the missing partner skipped.
    options.strict = false;
    GeometricGraph relaxed_graph = partial;
    const DeriveReport relaxed = derive(relaxed_graph, g, options);
    EXPECT_EQ(relaxed.totals.embedding_edges, 3u);
    EXPECT_EQ(relaxed.totals.missed_embeddings, 1u);
}

TEST(Rule, Figure5RelaxedEmbeddingDependsOnTheFrame) {
    // d is replaced by one vertex whose embedding points lie at (1, 0) and (-1, 0) of its frame;
    // around d: a at -45 degrees, b at 45, c at 135.
    Grammar g;
    g.symbol_names = {"D"};
    Rule rule;
    rule.symbol = 1;
    rule.vertices = {{{0, 0}, 0, {}, {{{1, 0}}, {{-1, 0}}}}};
    g.rules = {rule};
    g.axiom_vertices = {{{0, 0}, 1, {}}};
    const Vec2 a(std::cos(-45 * deg), std::sin(-45 * deg)), b(std::cos(45 * deg), std::sin(45 * deg)), c(std::cos(135 * deg), std::sin(135 * deg));
    struct Case {
        double rotation;
        std::vector<Vec2> connected;
    };
    for (const Case& k : {Case{0, {}}, Case{45, {b}}, Case{-45, {a, c}}}) {
        GeometricGraph host;
        const VertexId d = place_nonterminal(host, 1, {0, 0}, {1.0, k.rotation});
        for (const Vec2& p : {a, b, c}) host.add_edge(d, host.add_vertex(p), {});
        DeriveOptions options;
        options.tolerance = 0.1;
        const DeriveReport report = derive(host, g, options);
        EXPECT_EQ(report.totals.rewrites, 1u) << "the relaxed rule always applies";
        EXPECT_EQ(host.vertex_count(), 4u);
        EXPECT_EQ(host.edge_count(), k.connected.size()) << "rotation " << k.rotation;
        const VertexId x = vertex_at(host, {0, 0});
        for (const Vec2& p : k.connected) EXPECT_EQ(neighbours_at(host, x, p), 1u) << "rotation " << k.rotation;
    }
}

TEST(Rule, PlacedVerticesMergeWithExistingOnes) {
    // A rule that draws a segment ending where a street already has a vertex joins it.
    Grammar g;
    g.symbol_names = {"S"};
    Rule rule;
    rule.symbol = 1;
    rule.vertices = {{{0, 0}, 0, {}, {}}, {{1, 0}, 0, {}, {}}};
    rule.edges = {{0, 1}};
    g.rules = {rule};
    g.axiom_vertices = {{{0, 0}, 1, {}}};
    GeometricGraph host;
    const VertexId existing = host.add_vertex({100.02, 0});
    host.add_edge(existing, host.add_vertex({100, 50}), {});
    place_nonterminal(host, 1, {0, 0}, {100.0, 0.0});
    DeriveOptions options;
    options.tolerance = 0.5;
    options.tolerance_relative = false; // metres
    const DeriveReport report = derive(host, g, options);
    EXPECT_EQ(report.totals.merged_vertices, 1u);
    EXPECT_EQ(host.vertex_count(), 3u);
    EXPECT_EQ(host.edge_count(), 2u);
}

TEST(Derivation, SelfDoublingGrammarStopsAtTheVertexBudgetQuickly) {
    Grammar g;
    g.symbol_names = {"X"};
    Rule rule;
    rule.symbol = 1;
    // X -> two half-size X: one where X was, one a unit further and turned: V doubles per step.
    rule.vertices = {{{0, 0}, 1, {0.5, 0.0}, {}}, {{1, 0}, 1, {0.5, 90.0}, {}}};
    rule.edges = {{0, 1}};
    g.rules = {rule};
    g.axiom_vertices = {{{0, 0}, 1, {}}};
    GeometricGraph graph = g.axiom_graph();
    DeriveOptions options;
    options.max_steps = 1'000'000;
    options.max_vertices = 100'000;
    const auto start = std::chrono::steady_clock::now();
    const DeriveReport report = derive(graph, g, options);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_TRUE(report.stopped_by_budget);
    EXPECT_LE(graph.vertex_count(), options.max_vertices);
    EXPECT_GT(graph.vertex_count(), options.max_vertices / 2);
    EXPECT_LT(report.steps, 40);
    EXPECT_LT(seconds, 30.0) << "a runaway grammar must end at its budget, not run on";
}

TEST(Derivation, AFixedPointEndsTheDerivation) {
    Grammar g;
    g.symbol_names = {"P"};
    Rule rule; // P -> P, the same vertex in the same frame
    rule.symbol = 1;
    rule.vertices = {{{0, 0}, 1, {}, {}}};
    g.rules = {rule};
    g.axiom_vertices = {{{0, 0}, 1, {}}};
    GeometricGraph graph = g.axiom_graph();
    DeriveOptions options;
    options.max_steps = 1'000'000'000;
    const DeriveReport report = derive(graph, g, options);
    EXPECT_TRUE(report.converged);
    EXPECT_EQ(report.steps, 1);
    EXPECT_EQ(graph.vertex_count(), 1u);
}

TEST(Derivation, AStepThatOnlyMovesAFrameOrAnEdgeIsNotAFixedPoint) {
    // P -> P at half the scale, embedded at (1, 0): the first step connects P to the vertex at
    // (1000, 0); the second, at half the scale, to the one at (500, 0). Positions stay put.
    Grammar g;
    g.symbol_names = {"P"};
    Rule rule;
    rule.symbol = 1;
    rule.vertices = {{{0, 0}, 1, {0.5, 0.0}, {{{1, 0}}}}};
    g.rules = {rule};
    g.axiom_vertices = {{{0, 0}, 1, {1000.0, 0.0}}, {{1000, 0}, 0, {}}, {{500, 0}, 0, {}}};
    GeometricGraph graph = g.axiom_graph();
    DeriveOptions options;
    options.max_steps = 3;
    const DeriveReport report = derive(graph, g, options);
    EXPECT_FALSE(report.converged);
    EXPECT_EQ(report.steps, 3);
}

TEST(Derivation, SourceVerticesTellWhereEachVertexCameFrom) {
    // A street of three vertices plus one nonterminal: after growing, the street's vertices
    // are found again through source_vertex, the placed ones have -1.
    const Grammar g = sierpinski();
    GeometricGraph host;
    const VertexId a = host.add_vertex({5000, 0});
    const VertexId b = host.add_vertex({5100, 0});
    const VertexId c = host.add_vertex({5200, 0});
    host.add_edge(a, b, {});
    host.add_edge(b, c, {});
    place_nonterminal(host, 1, {0, 0}, {1000.0, 0.0});
    const GeometricGraph before = host;
    DeriveOptions options;
    options.max_steps = 2;
    const DeriveReport report = derive(host, g, options);
    ASSERT_EQ(report.source_vertex.size(), host.vertex_count());
    std::size_t kept = 0;
    for (std::size_t v = 0; v < host.vertex_count(); ++v) {
        const VertexId s = report.source_vertex[v];
        if (s < 0) continue;
        ++kept;
        EXPECT_EQ(host.positions[v], before.positions[static_cast<std::size_t>(s)]);
    }
    EXPECT_EQ(kept, 3u); // the street; the nonterminal was rewritten away
    EXPECT_EQ(host.vertex_count(), 3u + 6u); // one P becomes 3 corners, then 9 corners at 6 places
}

TEST(Derivation, ASharedCornerStaysOneVertexThroughAGraphFile) {
    // Two steps, written to a graph file and read back, then one more step: the same graph as
    // three steps at once. The corners two triangles share carry both rewrites in the file.
    const Grammar g = sierpinski();
    GeometricGraph direct = g.axiom_graph(), resumed = g.axiom_graph();
    DeriveOptions options;
    options.max_steps = 3;
    derive(direct, g, options);
    options.max_steps = 2;
    derive(resumed, g, options);
    ASSERT_FALSE(resumed.more_rewrites.empty());
    const nlohmann::json file = graph_to_json(resumed);
    EXPECT_EQ(file["version"], 2);
    EXPECT_EQ(graph_to_json(g.axiom_graph())["version"], 1); // nothing shared: readable by older programs
    resumed = graph_from_json(file, "two-steps.ggraph");
    options.max_steps = 1;
    derive(resumed, g, options);
    EXPECT_EQ(resumed.positions, direct.positions);
    EXPECT_EQ(resumed.edges, direct.edges);
    EXPECT_EQ(resumed.more_rewrites.size(), direct.more_rewrites.size());

    // A pending rewrite at a terminal vertex, or out of vertex order, is refused with its place.
    nlohmann::json bad = file;
    bad["vertices"]["more_rewrites"]["vertex"][0] = 100000;
    EXPECT_THROW(graph_from_json(bad, "bad.ggraph"), InputError);
    bad = file;
    auto& order = bad["vertices"]["more_rewrites"]["vertex"];
    std::swap(order[0], order[order.size() - 1]);
    try {
        graph_from_json(bad, "bad.ggraph");
        ADD_FAILURE() << "out of order pending rewrites were read";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("vertices.more_rewrites.vertex["), std::string::npos) << e.what();
    }
}

TEST(Derivation, SameInputSameOutput) {
    const Grammar g = sierpinski();
    GeometricGraph a = g.axiom_graph(), b = g.axiom_graph();
    DeriveOptions options;
    options.max_steps = 4;
    derive(a, g, options);
    derive(b, g, options);
    EXPECT_EQ(a.positions, b.positions);
    EXPECT_EQ(a.edges, b.edges);
}

TEST(GrammarFile, RoundTripIsIdentical) {
    const Grammar g = sierpinski();
    const nlohmann::json once = grammar_to_json(g);
    const Grammar back = grammar_from_json(once, "memory");
    EXPECT_TRUE(back == g);
    EXPECT_EQ(grammar_to_json(back).dump(), once.dump());
    const std::string path = ggg::test::temp_path(".json");
    write_grammar(g, path);
    EXPECT_TRUE(read_grammar(path) == g);
}

TEST(GrammarFile, MalformedFilesNameThePlace) {
    const std::string head = R"({"format":"ggg-grammar","version":1,"rules":[{"symbol":"P","vertices":[)";
    const std::string axiom = R"(,"axiom":{"vertices":[{"position":[0,0],"symbol":"P"}]}})";
    struct Case {
        std::string text;
        std::string expected;
    };
    const std::vector<Case> cases{
        {head + R"({"position":[0,0],"symbol":"Q"}],"edges":[]}])" + axiom, "rules[0].vertices[0].symbol: unknown symbol 'Q'"},
        {head + R"({"position":[0,"NaN"]}],"edges":[]}])" + axiom, "rules[0].vertices[0].position[1]: must be a number"},
        {head + R"({"position":[0,0,0]}],"edges":[]}])" + axiom, "rules[0].vertices[0].position: must be [x, y]"},
        {head + R"({"position":[0,0]}],"edges":[[0]]}])" + axiom, "rules[0].edges[0]"},
        {head + R"({"position":[0,0]}],"edges":[[0,3]]}])" + axiom, "rules[0].edges[0]: vertex index out of range"},
        {head + R"({"position":[0,0],"transform":{"scale":0}}],"edges":[]}])" + axiom, "rules[0].vertices[0].transform.scale: must be > 0"},
        {head + R"({"position":[0,0]}],"edges":[]}]})", "missing \"axiom\""},
        {head + R"({"position":[0,0]}],"edges":[]}],"axiom":{"vertices":[]}})", "missing axiom"},
        {head + R"({"position":[0,0]}],"edges":[]},{"symbol":"P","vertices":[{"position":[0,0]}],"edges":[]}])" + axiom,
         "rules[1].symbol: a second rule"},
        {R"({"format":"ggg-grammar","version":7})", "newer than this program"},
        {R"({"format":"ggg-grammar","version":1,"rules":[{"symbol":"P","vertices":[{"position":[0,0]}],"edges":[]})", "not valid JSON"},
        {R"({"type":"FeatureCollection"})", "not a grammar file"},
        {head + R"({"position":[0,1e400]}],"edges":[]}])" + axiom, "not valid JSON (number overflow"},
        {head + R"({"position":[0,0]}],"edges":[]}],"origin_latlon":[1]})", "origin_latlon: must be [latitude, longitude]"},
    };
    for (const Case& c : cases) {
        const std::string message = grammar_error(c.text);
        EXPECT_NE(message.find(c.expected), std::string::npos) << "expected '" << c.expected << "' in: " << message;
        EXPECT_EQ(message.rfind("g.json: ", 0), 0u) << message;
    }
    EXPECT_THROW(read_grammar("/nonexistent/g.json"), GrammarError);
}

TEST(CliDerive, PrintsCountsAndWritesTheGraph) {
    const std::string grammar = std::string(GGG_SAMPLES_DIR) + "/sierpinski.grammar.json";
    const std::string out = ggg::test::temp_path(".ggraph");
    const auto result = ggg::test::run_cli("derive '" + grammar + "' --steps 3 -o '" + out + "'");
    ASSERT_EQ(result.code, 0) << result.err;
    const auto summary = nlohmann::json::parse(result.out);
    EXPECT_EQ(summary["vertices"], 42); // 81 corners, two to a shared place
    EXPECT_EQ(summary["edges"], 81);
    EXPECT_EQ(summary["steps"], 3);
    EXPECT_EQ(summary["stopped_by_budget"], false);
    const auto info = ggg::test::run_cli("info '" + out + "'");
    EXPECT_EQ(nlohmann::json::parse(info.out)["edges"], 81);

    const auto budget = ggg::test::run_cli("derive '" + grammar + "' --steps 40 --max-vertices 1000 -o '" + out + "'");
    ASSERT_EQ(budget.code, 0) << budget.err;
    EXPECT_EQ(nlohmann::json::parse(budget.out)["stopped_by_budget"], true);
    EXPECT_EQ(nlohmann::json::parse(budget.out)["vertices"], 366);
    EXPECT_NE(budget.err.find("--max-vertices"), std::string::npos);
}

TEST(CliDerive, ErrorsAndUsage) {
    const std::string bad = ggg::test::temp_file(R"({"format":"ggg-grammar","version":1,"rules":[]})", ".json");
    auto r = ggg::test::run_cli("derive '" + bad + "' -o '" + ggg::test::temp_path(".geojson") + "'");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("error: " + bad + ": file: missing \"axiom\""), std::string::npos) << r.err;
    const std::string grammar = std::string(GGG_SAMPLES_DIR) + "/sierpinski.grammar.json";
    for (const std::string& args : std::vector<std::string>{"--steps -1", "--tolerance 0.1 --tolerance-m 2", "--max-vertices 0"}) {
        r = ggg::test::run_cli("derive '" + grammar + "' " + args + " -o '" + ggg::test::temp_path(".geojson") + "'");
        EXPECT_EQ(r.code, 2) << args << ": " << r.err;
    }
}

TEST(Derivation, RunawayScaleEndsInAnErrorNotInfinity) {
    Grammar g;
    g.symbol_names = {"P"};
    Rule rule; // P -> P one unit further at twice the scale: coordinates double every step
    rule.symbol = 1;
    rule.vertices = {{{1, 0}, 1, {2.0, 0.0}, {}}};
    g.rules = {rule};
    g.axiom_vertices = {{{0, 0}, 1, {}}};
    GeometricGraph graph = g.axiom_graph();
    DeriveOptions options;
    options.max_steps = 5000;
    EXPECT_THROW(derive(graph, g, options), GrammarError);
}
