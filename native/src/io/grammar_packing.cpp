#include "grammar_packing.hpp"

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <deque>

#include "ggg/error.hpp"
#include "ggg/io/grammar_file.hpp"
#include "json_util.hpp"

namespace ggg::io_detail {

using nlohmann::json;

namespace {

// The fixed units of the packed form, as inverse steps (a value is stored as the integer
// count of steps). Each is the rounding the encoder applies when it makes the value.
constexpr double rule_unit = 1e4;          // rule positions and embedding points, rule units
constexpr double frame_scale_unit = 1e4;   // scales of T_i
constexpr double axiom_scale_unit = 1e3;   // scales of the axiom's frames (metres)
constexpr double frame_degree_unit = 100;  // their rotations
constexpr double correction_scale_unit = 1e6;
constexpr double correction_degree_unit = 1e4;
constexpr double size_unit = 100; // a rule's size_m, in centimetres

} // namespace

double from_steps(std::int64_t k, double inverse) {
    if (inverse >= 1.0) return static_cast<double>(k) / inverse;
    return static_cast<double>(k) * std::round(1.0 / inverse);
}

double one_digit_decimal(double mantissa, int exponent) {
    return exponent >= 0 ? mantissa * std::pow(10.0, exponent) : mantissa / std::pow(10.0, -exponent);
}

int cbor_bytes(std::int64_t k) {
    const std::uint64_t a = k >= 0 ? static_cast<std::uint64_t>(k) : static_cast<std::uint64_t>(-(k + 1));
    return a < 24 ? 1 : a < 256 ? 2 : a < 65536 ? 3 : a < 4294967296ULL ? 5 : 9;
}

std::optional<std::size_t> column_place(std::string_view section, std::string_view name) {
    auto find = [&](const auto& names, std::size_t skip) -> std::optional<std::size_t> {
        for (std::size_t c = 0; c < names.size(); ++c) {
            if (name == names[c]) return skip + c;
        }
        return std::nullopt;
    };
    if (section == "rules") return find(rule_columns, 0);
    if (section == "axiom") return find(axiom_columns, 0);
    if (section == "graph") return find(graph_columns, 0);
    if (section != "encoding") return std::nullopt;
    if (const auto setting = find(encoding_settings, 0)) return setting;
    return find(instance_columns, encoding_settings.size());
}

void read_grammar_header(const JsonReader<GrammarError>& r, const json& doc, Grammar& g) {
    if (const json* n = r.optional(doc, "name")) {
        if (!n->is_string()) r.fail("name", "must be a string");
        g.name = n->get<std::string>();
    }
    if (const json* o = r.optional(doc, "origin_latlon")) {
        if (!o->is_array() || o->size() != 2) r.fail("origin_latlon", "must be [latitude, longitude]");
        g.origin = {r.number((*o)[0], "origin_latlon[0]"), r.number((*o)[1], "origin_latlon[1]")};
    }
}

namespace {

// The value `x` as a count of steps of 1/inverse (inverse a power of ten), when that count
// reads back to exactly x.
std::optional<std::int64_t> steps(double x, double inverse) {
    if (!std::isfinite(x) || std::abs(x * inverse) > 9e15) return std::nullopt;
    const auto k = std::llround(x * inverse);
    if (from_steps(k, inverse) != x) return std::nullopt;
    return k;
}

// The codes used (uses[c] > 0), most used first (ties by code), and each code's rank in that
// order: a column that stores ranks instead of codes takes one CBOR byte for the common ones.
struct ByUse {
    std::vector<std::int64_t> order;
    std::vector<std::int64_t> rank; // per code (0 for an unused one)
};

ByUse by_use(const std::vector<std::size_t>& uses) {
    ByUse out;
    for (std::size_t c = 0; c < uses.size(); ++c) {
        if (uses[c]) out.order.push_back(static_cast<std::int64_t>(c));
    }
    std::stable_sort(out.order.begin(), out.order.end(), [&](std::int64_t a, std::int64_t b) { return uses[static_cast<std::size_t>(a)] > uses[static_cast<std::size_t>(b)]; });
    out.rank.assign(uses.size(), 0);
    for (std::size_t r = 0; r < out.order.size(); ++r) out.rank[static_cast<std::size_t>(out.order[r])] = static_cast<std::int64_t>(r);
    return out;
}

// 0 = none; m × 10^e is 9e + m for e >= 0 (1 to 9 m: 1 to 9) and 9e + m - 9 below (all
// negative), so that the usual tolerances take one byte of CBOR.
std::optional<std::int64_t> tolerance_code(double t) {
    if (t == 0.0) return 0;
    if (!(t > 0) || !std::isfinite(t)) return std::nullopt;
    const int e = static_cast<int>(std::floor(std::log10(t)));
    for (int exponent : {e - 1, e, e + 1}) {
        const auto m = static_cast<int>(std::llround(t / std::pow(10.0, exponent)));
        if (m >= 1 && m <= 9 && exponent >= -30 && exponent <= 30 && one_digit_decimal(static_cast<double>(m), exponent) == t) {
            return 9 * exponent + m - (exponent < 0 ? 9 : 0);
        }
    }
    return std::nullopt;
}
std::optional<double> tolerance_of_code(std::int64_t code) {
    if (code == 0) return 0.0;
    if (code < -30 * 9 - 9 || code > 30 * 9 + 9) return std::nullopt;
    const auto e = static_cast<int>(code > 0 ? (code - 1) / 9 : -((-code) / 9));
    const auto m = static_cast<int>(code - 9 * e + (e < 0 ? 9 : 0));
    if (m < 1 || m > 9) return std::nullopt;
    return one_digit_decimal(static_cast<double>(m), e);
}

// The columns of `section` (named, as in the layout of version 5) in place order; a column missing or
// empty at the end is left out, one missing before a later one is [].
json by_place(const json& section, const auto& names) {
    json out = json::array();
    for (const char* name : names) out.push_back(section.contains(name) ? section.at(name) : json::array());
    while (!out.empty() && out.back().empty()) out.erase(out.size() - 1);
    return out;
}

bool default_symbol_names(const json& symbols) {
    for (std::size_t k = 0; k < symbols.size(); ++k) {
        if (symbols[k] != "R" + std::to_string(k + 1)) return false;
    }
    return true;
}

// A setting of metres as its one-digit decimal code (one or two bytes), else as the number.
json metres(double m) {
    if (const auto code = tolerance_code(m)) return *code;
    return m;
}

// Columns of values in a fixed unit of 10^-finest (the rules' embedding points, the axiom's
// frame scales) are written in version 6 in the coarsest power of ten that holds every value
// exactly, after its exponent: [e, values...], e from 0 to `finest`. The entries of that
// kind are those at `kind` (the x and y of each (x, y, class) point: {0, 1} of 3).
struct UnitColumn {
    const char* section;
    const char* name;
    std::size_t stride;
    std::vector<std::size_t> kind;
    int finest;
};
const std::array<UnitColumn, 2> unit_columns = {UnitColumn{"rules", "points", 3, {0, 1}, 4}, UnitColumn{"axiom", "frames", 2, {0}, 3}};

bool of_kind(const UnitColumn& c, std::size_t i) { return std::find(c.kind.begin(), c.kind.end(), i % c.stride) != c.kind.end(); }

json in_coarsest_unit(const json& column, const UnitColumn& c) {
    int e = c.finest;
    std::int64_t step = 1;
    while (e > 0) {
        const std::int64_t coarser = step * 10;
        bool exact = true;
        for (std::size_t i = 0; i < column.size() && exact; ++i) exact = !of_kind(c, i) || column[i].get<std::int64_t>() % coarser == 0;
        if (!exact) break;
        step = coarser;
        --e;
    }
    json out = json::array({e});
    for (std::size_t i = 0; i < column.size(); ++i) out.push_back(of_kind(c, i) ? column[i].get<std::int64_t>() / step : column[i].get<std::int64_t>());
    return out;
}

// Version 6 of a document laid out as version 5, its columns named (the Packer builds it so:
// a column is then found by its name; its values are version 6's).
json placed_form(json named) {
    for (const UnitColumn& c : unit_columns) {
        json& section = named.at(c.section);
        if (section.contains(c.name)) section[c.name] = in_coarsest_unit(section[c.name], c);
    }
    json doc = {{"format", "ggg-grammar"}, {"version", packed_grammar_version}, {"name", named.at("name")}, {"origin_latlon", named.at("origin_latlon")}};
    // Learned grammars name their symbols R1, R2, ...: implied where they do.
    if (!default_symbol_names(named.at("symbols"))) doc["symbols"] = named.at("symbols");
    doc["rules"] = by_place(named.at("rules"), rule_columns);
    doc["axiom"] = by_place(named.at("axiom"), axiom_columns);
    const json& enc = named.at("encoding");
    json encoding = {enc.at("mode"), enc.at("levels"), metres(enc.at("tolerance_m").get<double>()), metres(enc.at("quantum_m").get<double>()),
                     enc.contains("decodes_to") ? enc.at("decodes_to") : json::array()};
    for (json& column : by_place(enc, instance_columns)) encoding.push_back(std::move(column));
    doc["encoding"] = std::move(encoding);
    return doc;
}

class Packer {
public:
    explicit Packer(const Grammar& g) : g_(g) {}

    std::optional<json> run() {
        const Encoding& enc = g_.encoding;
        if (enc.empty() || !(enc.quantum_m >= 1e-9 && enc.quantum_m <= 1e-2)) return std::nullopt;
        if (g_.rules.size() != g_.symbol_names.size()) return std::nullopt;
        for (std::size_t k = 0; k < g_.rules.size(); ++k) {
            if (g_.rules[k].symbol != k + 1) return std::nullopt; // rule k rewrites symbol k + 1
            if (g_.rules[k].uses > static_cast<std::uint64_t>(INT64_MAX / 4)) return std::nullopt;
        }
        // Both counts or neither (the packed form stores them as a pair).
        if ((enc.decoded_vertices >= 0) != (enc.decoded_edges >= 0) || enc.decoded_vertices > INT32_MAX || enc.decoded_edges > INT32_MAX ||
            (enc.decoded_length_m >= 0 && enc.decoded_vertices < 0) || enc.decoded_length_m > INT64_MAX / 8) {
            return std::nullopt;
        }
        quantum_ = std::pow(10.0, std::round(-std::log10(enc.quantum_m)));
        if (from_steps(1, quantum_) != enc.quantum_m && std::abs(1.0 / quantum_ - enc.quantum_m) > 1e-18) return std::nullopt;
        json doc = {{"format", "ggg-grammar"}, {"version", packed_grammar_version}, {"name", g_.name},
                    {"origin_latlon", {g_.origin.lat, g_.origin.lon}}, {"symbols", g_.symbol_names}};
        json rules, axiom, encoding;
        if (!pack_rules(rules) || !pack_axiom(axiom) || !pack_instances(encoding)) return std::nullopt;
        encoding["mode"] = enc.mode;
        encoding["levels"] = enc.levels;
        encoding["tolerance_m"] = enc.tolerance_m;
        encoding["quantum_m"] = enc.quantum_m;
        if (enc.decoded_vertices >= 0) encoding["decodes_to"] = {enc.decoded_vertices, enc.decoded_edges};
        if (enc.decoded_vertices >= 0 && enc.decoded_length_m >= 0) encoding["decodes_to"].push_back(enc.decoded_length_m);
        // An empty column is left out: the reader takes a missing one as empty.
        for (json* section : {&rules, &axiom, &encoding}) {
            for (auto it = section->begin(); it != section->end();) {
                if (it->is_array() && it->empty()) it = section->erase(it);
                else ++it;
            }
        }
        doc["rules"] = std::move(rules);
        doc["axiom"] = std::move(axiom);
        doc["encoding"] = std::move(encoding);
        return placed_form(std::move(doc));
    }

private:
    // `lowest`: the reader's bound (a scale is at least one step).
    bool put(json& column, double x, double inverse, std::int64_t offset = 0, std::int64_t lowest = INT64_MIN / 4) {
        const auto k = steps(x, inverse);
        if (!k || *k < lowest) return false;
        column.push_back(*k - offset);
        return true;
    }

    bool pack_rules(json& out) {
        json uses = json::array(), size = json::array(), vertex_count = json::array(), edge_count = json::array(), x = json::array(),
             y = json::array(), symbol = json::array(), transform = json::array(), embedding = json::array(), points = json::array(),
             edges = json::array();
        for (const Rule& r : g_.rules) {
            uses.push_back(r.uses);
            if (!put(size, r.size_m, size_unit)) return false;
            vertex_count.push_back(r.vertices.size());
            edge_count.push_back(r.edges.size());
            for (const RuleVertex& v : r.vertices) {
                if (!put(x, v.position.x(), rule_unit) || !put(y, v.position.y(), rule_unit)) return false;
                symbol.push_back(v.symbol);
                if (v.symbol) {
                    if (!put(transform, v.transform.scale, frame_scale_unit, 0, 1) || !put(transform, v.transform.rotation_deg, frame_degree_unit)) return false;
                } else if (v.transform != Frame{}) {
                    return false;
                }
                embedding.push_back(v.embedding.size());
                for (const EmbeddingPoint& p : v.embedding) {
                    if (!put(points, p.offset.x(), rule_unit) || !put(points, p.offset.y(), rule_unit)) return false;
                    points.push_back(static_cast<int>(p.highway));
                }
            }
            for (const GrammarEdge& e : r.edges) edges.insert(edges.end(), {e.a, e.b, static_cast<int>(e.highway)});
        }
        out = {{"uses", std::move(uses)}, {"size_cm", std::move(size)}, {"vertices", std::move(vertex_count)},
               {"edges", std::move(edge_count)}, {"x", std::move(x)}, {"y", std::move(y)}, {"symbol", std::move(symbol)},
               {"transform", std::move(transform)}, {"embedding", std::move(embedding)}, {"points", std::move(points)},
               {"edge_list", std::move(edges)}};
        return true;
    }

    bool pack_axiom(json& out) {
        json x = json::array(), y = json::array(), nonterminals = json::array(), symbol = json::array(), frames = json::array(),
             symbol_order = json::array();
        // The axiom's symbols, most used first: a nonterminal stores its symbol's rank, which
        // for most is one byte.
        std::vector<std::size_t> uses(g_.symbol_names.size() + 1, 0);
        for (const AxiomVertex& v : g_.axiom_vertices) {
            if (static_cast<std::size_t>(v.symbol) >= uses.size()) return false;
            uses[static_cast<std::size_t>(v.symbol)] += v.symbol != 0;
        }
        const ByUse symbols = by_use(uses);
        symbol_order = symbols.order;
        std::int64_t px = 0, py = 0, run_start = -1, previous_end = 0;
        for (std::size_t i = 0; i < g_.axiom_vertices.size(); ++i) {
            const AxiomVertex& v = g_.axiom_vertices[i];
            const auto kx = steps(v.position.x(), quantum_), ky = steps(v.position.y(), quantum_);
            if (!kx || !ky) return false;
            x.push_back(*kx - px);
            y.push_back(*ky - py);
            px = *kx;
            py = *ky;
            const auto at = static_cast<std::int64_t>(i);
            // Nonterminals come in runs (the encoder appends them): each run is stored as
            // (step from the end of the previous run, length).
            if (v.symbol && run_start < 0) run_start = at;
            if (!v.symbol && run_start >= 0) {
                nonterminals.insert(nonterminals.end(), {run_start - previous_end, at - run_start});
                previous_end = at;
                run_start = -1;
            }
            if (!v.symbol) {
                if (v.frame != Frame{}) return false;
                continue;
            }
            symbol.push_back(symbols.rank[static_cast<std::size_t>(v.symbol)]);
            if (!put(frames, v.frame.scale, axiom_scale_unit, 0, 1) || !put(frames, v.frame.rotation_deg, frame_degree_unit)) return false;
        }
        if (run_start >= 0) {
            const auto end = static_cast<std::int64_t>(g_.axiom_vertices.size());
            nonterminals.insert(nonterminals.end(), {run_start - previous_end, end - run_start});
        }
        out = {{"x", std::move(x)}, {"y", std::move(y)}, {"nonterminals", std::move(nonterminals)}, {"symbol_order", std::move(symbol_order)},
               {"symbol", std::move(symbol)}, {"frames", std::move(frames)}, {"edges", edge_steps(g_.axiom_edges)}};
        return true;
    }

    // Instances in the order the derivation meets them: the axiom's nonterminals in order,
    // then, level by level, the nonterminals each instance places, in rule-vertex order.
    // That order is all the packed form says about which instance rewrites what.
    bool derivation_order(std::vector<std::int32_t>& order) {
        const Encoding& enc = g_.encoding;
        std::deque<std::int32_t> queue;
        std::vector<char> seen(enc.instances.size(), 0);
        auto visit = [&](std::int32_t id) {
            if (id < 0 || static_cast<std::size_t>(id) >= enc.instances.size() || seen[static_cast<std::size_t>(id)]) return false;
            seen[static_cast<std::size_t>(id)] = 1;
            queue.push_back(id);
            return true;
        };
        bool axiom_has_nonterminal = false;
        for (const AxiomVertex& v : g_.axiom_vertices) axiom_has_nonterminal |= v.symbol != 0;
        // The reader gives one entry per axiom vertex (-1 for a street vertex) exactly when
        // the axiom has a nonterminal.
        if (enc.axiom_instances.size() != (axiom_has_nonterminal ? g_.axiom_vertices.size() : 0)) return false;
        for (std::size_t i = 0; i < g_.axiom_vertices.size(); ++i) {
            if (!g_.axiom_vertices[i].symbol) {
                if (axiom_has_nonterminal && enc.axiom_instances[i] != -1) return false;
                continue;
            }
            if (!visit(enc.axiom_instances[i])) return false;
        }
        while (!queue.empty()) {
            const std::int32_t id = queue.front();
            queue.pop_front();
            order.push_back(id);
            const RuleInstance& inst = enc.instances[static_cast<std::size_t>(id)];
            const Rule* rule = g_.rule_for(inst.symbol);
            if (!rule) return false;
            bool any_nonterminal = false;
            for (std::size_t j = 0; j < rule->vertices.size(); ++j) {
                if (!rule->vertices[j].symbol) continue;
                any_nonterminal = true;
                if (inst.children.size() != rule->vertices.size() || !visit(inst.children[j])) return false;
            }
            if (!any_nonterminal && !inst.children.empty()) return false;
        }
        if (order.size() != enc.instances.size()) return false;
        // Numbered in that order already (the encoder does so): the packed form implies the
        // numbers, and a grammar must read back as it was written.
        for (std::size_t n = 0; n < order.size(); ++n) {
            if (order[n] != static_cast<std::int32_t>(n)) return false;
        }
        return true;
    }

    bool pack_instances(json& out) {
        const Encoding& enc = g_.encoding;
        std::vector<std::int32_t> order;
        if (!derivation_order(order)) return false;
        const bool lossless = enc.mode == "lossless";
        json correction = json::array(), shift = json::array(), residuals = json::array(), tolerance = json::array(),
             rule_points = json::array(), embedding = json::array(), classes = json::array(), link_classes = json::array(),
             neighbours = json::array();
        std::size_t axiom_nonterminals = 0;
        for (const AxiomVertex& v : g_.axiom_vertices) axiom_nonterminals += v.symbol != 0;
        // The links' classes, most common first: a link stores its rule vertex and its class's
        // rank in one number, which for most links is one byte.
        std::vector<std::size_t> class_uses(highway_class_count, 0);
        for (const RuleInstance& inst : enc.instances) {
            for (const RuleInstance::Link& l : inst.embedding) {
                if (static_cast<std::size_t>(l.point.highway) >= highway_class_count) return false;
                ++class_uses[static_cast<std::size_t>(l.point.highway)];
            }
            for (const RuleInstance::Neighbour& l : inst.neighbours) {
                if (static_cast<std::size_t>(l.highway) >= highway_class_count || l.rank < 0) return false;
                ++class_uses[static_cast<std::size_t>(l.highway)];
            }
            for (const auto& [edge, highway] : inst.edge_classes) {
                if (static_cast<std::size_t>(highway) >= highway_class_count) return false;
                ++class_uses[static_cast<std::size_t>(highway)];
            }
        }
        const ByUse classes_by_use = by_use(class_uses);
        link_classes = classes_by_use.order;
        const std::vector<std::int64_t>& rank = classes_by_use.rank;
        // Rule points, class changes, offsets and tolerances of their own are rare: stored only
        // for the instances that have them, each as (step from the previous such instance,
        // count, entries) or, for the tolerance, (step, code).
        std::size_t last_points = 0, last_classes = 0, last_links = 0, last_tolerance = 0;
        for (std::size_t n = 0; n < order.size(); ++n) {
            const RuleInstance& inst = enc.instances[static_cast<std::size_t>(order[n])];
            if (n < axiom_nonterminals) {
                // The axiom's instances take its frames as they are.
                if (inst.correction != Frame{} || inst.shift != Vec2::Zero()) return false;
            } else if (!put(correction, inst.correction.scale, correction_scale_unit, static_cast<std::int64_t>(correction_scale_unit), 1) ||
                       !put(correction, inst.correction.rotation_deg, correction_degree_unit) || !put(shift, inst.shift.x(), quantum_) ||
                       !put(shift, inst.shift.y(), quantum_)) {
                return false;
            }
            if (inst.residuals.size() != (lossless ? g_.rule_for(inst.symbol)->vertices.size() : 0)) return false;
            for (const Vec2& r : inst.residuals) {
                if (!put(residuals, r.x(), quantum_) || !put(residuals, r.y(), quantum_)) return false;
            }
            const auto code = tolerance_code(inst.tolerance_m);
            if (!code) return false;
            if (*code != 0) {
                tolerance.insert(tolerance.end(), {n - last_tolerance, *code});
                last_tolerance = n;
            }
            const Rule& rule = *g_.rule_for(inst.symbol);
            for (const std::int32_t p : inst.rule_points) {
                if (p < 0) return false;
            }
            for (const RuleInstance::Link& l : inst.embedding) {
                if (l.vertex < 0 || static_cast<std::size_t>(l.vertex) >= rule.vertices.size()) return false;
            }
            for (const RuleInstance::Neighbour& l : inst.neighbours) {
                if (l.vertex < 0 || static_cast<std::size_t>(l.vertex) >= rule.vertices.size()) return false;
            }
            for (const auto& [edge, highway] : inst.edge_classes) {
                if (edge < 0 || static_cast<std::size_t>(edge) >= rule.edges.size()) return false;
            }
            if (!inst.rule_points.empty()) {
                rule_points.insert(rule_points.end(), {n - last_points, inst.rule_points.size()});
                for (const std::int32_t p : inst.rule_points) rule_points.push_back(p);
                last_points = n;
            }
            if (!inst.embedding.empty()) {
                embedding.insert(embedding.end(), {n - last_links, inst.embedding.size()});
                if (!pack_links(inst.embedding, rule.vertices.size(), rank, embedding)) return false;
                last_links = n;
            }
            // Every instance: its links by rank after their count, each one number: its code
            // (rule vertex and class) plus the rank times the number of codes, so that a link
            // to the nearest vertex, the most common, takes one byte of CBOR.
            const auto codes = static_cast<std::int64_t>(rule.vertices.size() * link_classes.size());
            neighbours.push_back(inst.neighbours.size());
            for (const RuleInstance::Neighbour& l : inst.neighbours) {
                neighbours.push_back(static_cast<std::int64_t>(l.vertex) + static_cast<std::int64_t>(rule.vertices.size()) * rank[static_cast<std::size_t>(l.highway)] +
                                     codes * l.rank);
            }
            // A class change: the rule edge plus the class's rank times the rule's edges.
            if (!inst.edge_classes.empty()) {
                classes.insert(classes.end(), {n - last_classes, inst.edge_classes.size()});
                for (const auto& [edge, highway] : inst.edge_classes) {
                    classes.push_back(edge + static_cast<std::int64_t>(rule.edges.size()) * rank[static_cast<std::size_t>(highway)]);
                }
                last_classes = n;
            }
        }
        out = {{"correction", std::move(correction)}, {"shift", std::move(shift)}, {"residuals", std::move(residuals)},
               {"tolerance", std::move(tolerance)}, {"rule_points", std::move(rule_points)}, {"embedding", std::move(embedding)},
               {"link_classes", std::move(link_classes)}, {"edge_classes", std::move(classes)}, {"neighbours", std::move(neighbours)}};
        return true;
    }

    // An instance's own points are rounded to a power of ten that depends on its tolerance
    // and its frame: the coarsest power that holds them all exactly is stored first.
    static bool pack_links(const std::vector<RuleInstance::Link>& links, std::size_t rule_vertices,
                           const std::vector<std::int64_t>& rank, json& out) {
        for (int exponent = -6; exponent <= 12; ++exponent) {
            const double inverse = std::pow(10.0, exponent);
            json packed = json::array();
            bool exact = true;
            for (const RuleInstance::Link& l : links) {
                const auto kx = steps(l.point.offset.x(), inverse), ky = steps(l.point.offset.y(), inverse);
                if (!kx || !ky) {
                    exact = false;
                    break;
                }
                const std::int64_t code = l.vertex + static_cast<std::int64_t>(rule_vertices) * rank[static_cast<std::size_t>(l.point.highway)];
                packed.insert(packed.end(), {json(code), json(*kx), json(*ky)});
            }
            if (!exact) continue;
            out.push_back(exponent);
            out.insert(out.end(), packed.begin(), packed.end());
            return true;
        }
        return false;
    }

    const Grammar& g_;
    double quantum_ = 1.0;
};

} // namespace

json edge_steps(const std::vector<GrammarEdge>& edges) {
    json out = json::array();
    std::int64_t previous = 0;
    for (const GrammarEdge& e : edges) {
        out.insert(out.end(), {e.a - previous, static_cast<std::int64_t>(e.b) - e.a, static_cast<std::int64_t>(e.highway)});
        previous = e.a;
    }
    return out;
}

std::optional<json> pack_grammar(const Grammar& grammar) { return Packer(grammar).run(); }

json pack_graph(const GeometricGraph& g, double quantum_m) {
    const double inverse = std::pow(10.0, std::round(-std::log10(quantum_m)));
    json x = json::array(), y = json::array();
    std::int64_t px = 0, py = 0;
    for (const Vec2& p : g.positions) {
        const auto kx = std::llround(p.x() * inverse), ky = std::llround(p.y() * inverse);
        x.push_back(kx - px);
        y.push_back(ky - py);
        px = kx;
        py = ky;
    }
    std::vector<GrammarEdge> edges;
    for (std::size_t e = 0; e < g.edge_count(); ++e) edges.push_back({static_cast<std::int32_t>(g.edges[e][0]), static_cast<std::int32_t>(g.edges[e][1]), g.edge_highway[e]});
    // The header any file carries, as the grammar's does, and the columns by place.
    return {{"format", "ggg-graph"}, {"version", 2}, {"origin_latlon", {g.origin.lat, g.origin.lon}},
            {"graph", {std::move(x), std::move(y), edge_steps(edges)}}};
}

namespace {

class Unpacker : public JsonReader<GrammarError> {
public:
    using JsonReader::JsonReader;

    // Column `key` of `object`, every entry an integer in [lo, hi].
    std::vector<std::int64_t> ints(const json& object, const char* key, const std::string& where, std::int64_t lo = INT64_MIN / 4,
                                   std::int64_t hi = INT64_MAX / 4) const {
        const std::string at = where + "." + key;
        if (!object.is_object()) fail(where, "must be an object");
        std::vector<std::int64_t> out;
        const json* found = optional(object, key);
        if (!found) return out; // an empty column is left out
        const json& column = array(*found, at);
        out.reserve(column.size());
        for (std::size_t i = 0; i < column.size(); ++i) out.push_back(integer(column[i], at + "[" + std::to_string(i) + "]", lo, hi));
        return out;
    }
};

// Reads a column front to back; running past its end is an error naming the column.
struct Cursor {
    const Unpacker& r;
    std::vector<std::int64_t> values;
    std::string where;
    std::size_t next = 0;

    std::int64_t take(std::int64_t lo = INT64_MIN / 4, std::int64_t hi = INT64_MAX / 4) {
        if (next >= values.size()) r.fail(where, "ends early (" + std::to_string(values.size()) + " entries)");
        const std::int64_t v = values[next];
        if (v < lo || v > hi) r.fail(where + "[" + std::to_string(next) + "]", std::to_string(v) + " out of range [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
        ++next;
        return v;
    }
    void finish() const {
        if (next != values.size()) r.fail(where, "has " + std::to_string(values.size() - next) + " entries more than the grammar uses");
    }
};

// A column of versions 3 and 4 stored only for the instances that have entries: groups of (step from
// the previous such instance, count ≥ 1, entries). In version 2 every instance has its count.
struct Groups {
    Cursor& c;
    bool sparse;
    std::int64_t at = -1; // the instance the next group is for; -1: none left

    Groups(Cursor& column, bool sparse_groups) : c(column), sparse(sparse_groups) {
        if (sparse && c.next < c.values.size()) at = c.take(0, INT32_MAX);
    }
    // How many entries instance k has; the cursor then stands at them.
    std::int64_t count(std::int64_t k) {
        if (!sparse) return c.take(0, INT32_MAX);
        return at == k ? c.take(1, INT32_MAX) : 0;
    }
    // After instance k's entries were taken.
    void done(std::int64_t k) {
        if (sparse && at == k) at = c.next < c.values.size() ? k + c.take(1, INT32_MAX) : -1;
    }
    void finish() const {
        if (at >= 0) c.r.fail(c.where, "names instance " + std::to_string(at) + ", past the last");
        c.finish();
    }
};

} // namespace

namespace {

// Version 6 in the named layout of version 5, which the rest of the reader reads: a column
// out of place is then named as in any version ("rules.x[3]").
json named_form(const Unpacker& r, const json& doc) {
    json named = json::object();
    for (const char* key : {"format", "version", "name", "origin_latlon"}) {
        if (doc.contains(key)) named[key] = doc.at(key);
    }
    auto columns = [&](const char* section, const auto& names, std::size_t skip = 0) {
        const json& placed = r.array(r.member(doc, section, "file"), section);
        if (placed.size() > skip + names.size()) {
            r.fail(section, "has " + std::to_string(placed.size()) + " entries, at most " + std::to_string(skip + names.size()) + " (columns by place)");
        }
        json out = json::object();
        for (std::size_t c = skip; c < placed.size(); ++c) {
            const char* key = names[c - skip];
            const std::string where = std::string(section) + "[" + std::to_string(c) + "] (" + key + ")";
            r.array(placed[c], where);
            if (!placed[c].empty()) out[key] = placed[c];
        }
        return out;
    };
    named["rules"] = columns("rules", rule_columns);
    named["axiom"] = columns("axiom", axiom_columns);
    for (const UnitColumn& c : unit_columns) {
        json& section = named[c.section];
        if (!section.contains(c.name)) continue;
        const json& column = section[c.name];
        const std::string where = std::string(c.section) + "." + c.name;
        const std::int64_t e = r.integer(column[0], where + "[0] (its unit's exponent)", 0, c.finest);
        std::int64_t step = 1;
        for (std::int64_t k = e; k < c.finest; ++k) step *= 10;
        json values = json::array();
        for (std::size_t i = 1; i < column.size(); ++i) {
            // Bounded so that the value in the finest unit (at most 10^4 times more) fits.
            const std::int64_t v = r.integer(column[i], where + "[" + std::to_string(i) + "]", -100'000'000'000'000, 100'000'000'000'000);
            values.push_back(of_kind(c, i - 1) ? v * step : v);
        }
        section[c.name] = std::move(values);
    }
    json encoding = columns("encoding", instance_columns, encoding_settings.size());
    const json& placed = doc.at("encoding");
    if (placed.size() < encoding_settings.size()) r.fail("encoding", "must start with its settings: mode, levels, tolerance, quantum, decodes_to");
    auto setting_metres = [&](std::size_t at) {
        const std::string where = std::string("encoding[") + std::to_string(at) + "] (" + encoding_settings[at] + ")";
        const json& v = placed[at];
        if (v.is_number_integer()) {
            const auto m = tolerance_of_code(r.integer(v, where, INT32_MIN, INT32_MAX));
            if (!m) r.fail(where, "not a code of metres");
            return json(*m);
        }
        return json(r.number(v, where));
    };
    encoding["mode"] = placed[0];
    encoding["levels"] = placed[1];
    encoding["tolerance_m"] = setting_metres(2);
    encoding["quantum_m"] = setting_metres(3);
    if (!r.array(placed[4], "encoding[4] (decodes_to)").empty()) encoding["decodes_to"] = placed[4];
    named["encoding"] = std::move(encoding);
    if (const json* symbols = r.optional(doc, "symbols")) {
        named["symbols"] = *symbols;
    } else {
        // Implied: R1 ... Rn, one per rule (a rule per entry of rules.uses).
        json names = json::array();
        const std::size_t rules = named["rules"].contains("uses") && named["rules"]["uses"].is_array() ? named["rules"]["uses"].size() : 0;
        for (std::size_t k = 0; k < rules; ++k) names.push_back("R" + std::to_string(k + 1));
        named["symbols"] = std::move(names);
    }
    return named;
}

Grammar unpack_named(const json& doc, const std::string& name);

} // namespace

Grammar unpack_grammar(const json& doc, const std::string& name) {
    if (doc.at("version").get<std::int64_t>() >= 6) return unpack_named(named_form(Unpacker(name), doc), name);
    return unpack_named(doc, name);
}

namespace {

Grammar unpack_named(const json& doc, const std::string& name) {
    const Unpacker r(name);
    Grammar g;
    read_grammar_header(r, doc, g);
    const json& symbols = r.array(r.member(doc, "symbols", "file"), "symbols");
    for (std::size_t i = 0; i < symbols.size(); ++i) {
        if (!symbols[i].is_string() || symbols[i].get<std::string>().empty() || symbols[i].get<std::string>() == "terminal") {
            r.fail("symbols[" + std::to_string(i) + "]", "must be the name of a nonterminal");
        }
        g.symbol_names.push_back(symbols[i].get<std::string>());
    }
    const auto symbol_max = static_cast<std::int64_t>(g.symbol_names.size());
    const std::int64_t class_max = highway_class_count - 1;
    const json& enc_doc = r.member(doc, "encoding", "file");
    Encoding& enc = g.encoding;
    const json& mode = r.member(enc_doc, "mode", "encoding");
    if (!mode.is_string()) r.fail("encoding.mode", "must be \"paper\" or \"lossless\"");
    enc.mode = mode.get<std::string>();
    if (enc.mode != "paper" && enc.mode != "lossless") r.fail("encoding.mode", "must be \"paper\" or \"lossless\"");
    enc.levels = static_cast<int>(r.integer(r.member(enc_doc, "levels", "encoding"), "encoding.levels", 0, 1'000'000));
    enc.tolerance_m = r.number(r.member(enc_doc, "tolerance_m", "encoding"), "encoding.tolerance_m");
    enc.quantum_m = r.number(r.member(enc_doc, "quantum_m", "encoding"), "encoding.quantum_m");
    if (!(enc.quantum_m >= 1e-9 && enc.quantum_m <= 1e-2)) r.fail("encoding.quantum_m", "must lie between 1e-9 and 1e-2");
    const double quantum = std::pow(10.0, std::round(-std::log10(enc.quantum_m)));
    if (const json* d = r.optional(enc_doc, "decodes_to")) {
        // [vertices, edges], and in version 5 the length of the streets in metres.
        const json& counts = r.array(*d, "encoding.decodes_to");
        if (counts.size() != 2 && !(counts.size() == 3 && doc.at("version").get<std::int64_t>() >= 5)) {
            r.fail("encoding.decodes_to", doc.at("version").get<std::int64_t>() >= 5 ? "must be [vertices, edges] or [vertices, edges, metres]" : "must be [vertices, edges]");
        }
        enc.decoded_vertices = r.integer(counts[0], "encoding.decodes_to[0]", 0, INT32_MAX);
        enc.decoded_edges = r.integer(counts[1], "encoding.decodes_to[1]", 0, INT32_MAX);
        if (counts.size() == 3) enc.decoded_length_m = r.integer(counts[2], "encoding.decodes_to[2]", 0, INT64_MAX / 8);
    }

    // Rules.
    const json& rules = r.member(doc, "rules", "file");
    const auto uses = r.ints(rules, "uses", "rules", 0);
    const std::size_t rule_count = uses.size();
    if (rule_count != g.symbol_names.size()) r.fail("rules.uses", "needs one entry per symbol");
    auto column = [&](const json& object, const char* key, const std::string& where, std::size_t size) {
        auto v = r.ints(object, key, where);
        if (size != JsonReader<GrammarError>::any_size && v.size() != size) {
            r.fail(where + "." + key, "has " + std::to_string(v.size()) + " entries, expected " + std::to_string(size));
        }
        return Cursor{r, std::move(v), where + "." + key};
    };
    Cursor size = column(rules, "size_cm", "rules", rule_count);
    Cursor vertex_count = column(rules, "vertices", "rules", rule_count);
    Cursor edge_count = column(rules, "edges", "rules", rule_count);
    Cursor x = column(rules, "x", "rules", JsonReader<GrammarError>::any_size);
    Cursor y = column(rules, "y", "rules", x.values.size());
    Cursor symbol = column(rules, "symbol", "rules", x.values.size());
    Cursor transform = column(rules, "transform", "rules", JsonReader<GrammarError>::any_size);
    Cursor embedding = column(rules, "embedding", "rules", x.values.size());
    Cursor points = column(rules, "points", "rules", JsonReader<GrammarError>::any_size);
    Cursor edges = column(rules, "edge_list", "rules", JsonReader<GrammarError>::any_size);
    for (std::size_t k = 0; k < rule_count; ++k) {
        Rule rule;
        rule.symbol = static_cast<Symbol>(k + 1);
        rule.uses = static_cast<std::uint64_t>(uses[k]);
        rule.size_m = from_steps(size.take(0), size_unit);
        const auto n = vertex_count.take(0, INT32_MAX);
        for (std::int64_t i = 0; i < n; ++i) {
            RuleVertex v;
            v.position = {from_steps(x.take(), rule_unit), from_steps(y.take(), rule_unit)};
            v.symbol = static_cast<Symbol>(symbol.take(0, symbol_max));
            if (v.symbol) {
                v.transform.scale = from_steps(transform.take(1), frame_scale_unit);
                v.transform.rotation_deg = from_steps(transform.take(), frame_degree_unit);
            }
            const auto m = embedding.take(0, INT32_MAX);
            for (std::int64_t j = 0; j < m; ++j) {
                EmbeddingPoint p;
                p.offset = {from_steps(points.take(), rule_unit), from_steps(points.take(), rule_unit)};
                p.highway = static_cast<HighwayClass>(points.take(0, class_max));
                v.embedding.push_back(p);
            }
            rule.vertices.push_back(std::move(v));
        }
        const auto e = edge_count.take(0, INT32_MAX);
        for (std::int64_t j = 0; j < e; ++j) {
            GrammarEdge edge;
            edge.a = static_cast<std::int32_t>(edges.take(0, n - 1));
            edge.b = static_cast<std::int32_t>(edges.take(0, n - 1));
            edge.highway = static_cast<HighwayClass>(edges.take(0, class_max));
            rule.edges.push_back(edge);
        }
        g.rules.push_back(std::move(rule));
    }
    for (const Cursor* c : {&x, &y, &symbol, &transform, &embedding, &points, &edges}) c->finish();

    // Axiom.
    const json& axiom = r.member(doc, "axiom", "file");
    Cursor ax = column(axiom, "x", "axiom", JsonReader<GrammarError>::any_size);
    Cursor ay = column(axiom, "y", "axiom", ax.values.size());
    Cursor nonterminals = column(axiom, "nonterminals", "axiom", JsonReader<GrammarError>::any_size);
    std::int64_t px = 0, py = 0;
    for (std::size_t i = 0; i < ax.values.size(); ++i) {
        px += ax.take();
        py += ay.take();
        g.axiom_vertices.push_back({{from_steps(px, quantum), from_steps(py, quantum)}, 0, Frame{}});
    }
    // Which axiom vertices are nonterminals: version 4 stores runs of them, (step from the end of
    // the previous run, length); before, the step from the previous nonterminal, one by one.
    const std::int64_t version = doc.at("version").get<std::int64_t>();
    const auto axiom_size = static_cast<std::int64_t>(g.axiom_vertices.size());
    const std::int64_t vertex_max = axiom_size - 1;
    std::vector<std::size_t> nonterminal_at;
    if (version >= 4) {
        if (nonterminals.values.size() % 2) r.fail("axiom.nonterminals", "must hold (step, length) pairs");
        std::int64_t end = 0;
        while (nonterminals.next < nonterminals.values.size()) {
            const std::int64_t start = end + nonterminals.take(0, axiom_size);
            const std::int64_t length = nonterminals.take(1, axiom_size);
            if (start + length > axiom_size) r.fail("axiom.nonterminals", "points past the last axiom vertex");
            for (std::int64_t i = start; i < start + length; ++i) nonterminal_at.push_back(static_cast<std::size_t>(i));
            end = start + length;
        }
    } else {
        std::int64_t at = 0;
        for (std::size_t k = 0; k < nonterminals.values.size(); ++k) {
            at += nonterminals.take(k ? 1 : 0, vertex_max);
            if (at > vertex_max) r.fail("axiom.nonterminals", "points past the last axiom vertex");
            nonterminal_at.push_back(static_cast<std::size_t>(at));
        }
    }
    // Version 4 stores a nonterminal's symbol as its rank in symbol_order.
    std::vector<std::int64_t> symbol_order;
    if (version >= 4) {
        Cursor order = column(axiom, "symbol_order", "axiom", JsonReader<GrammarError>::any_size);
        while (order.next < order.values.size()) symbol_order.push_back(order.take(1, symbol_max));
    } else if (axiom.contains("symbol_order")) {
        r.fail("axiom.symbol_order", "is not part of version " + std::to_string(version));
    }
    Cursor axiom_symbol = column(axiom, "symbol", "axiom", nonterminal_at.size());
    Cursor frames = column(axiom, "frames", "axiom", 2 * nonterminal_at.size());
    for (const std::size_t at : nonterminal_at) {
        AxiomVertex& v = g.axiom_vertices[at];
        if (version >= 4) {
            if (symbol_order.empty()) r.fail("axiom.symbol_order", "is empty, but the axiom has nonterminals");
            v.symbol = static_cast<Symbol>(symbol_order[static_cast<std::size_t>(axiom_symbol.take(0, static_cast<std::int64_t>(symbol_order.size()) - 1))]);
        } else {
            v.symbol = static_cast<Symbol>(axiom_symbol.take(1, symbol_max));
        }
        v.frame.scale = from_steps(frames.take(1), axiom_scale_unit);
        v.frame.rotation_deg = from_steps(frames.take(), frame_degree_unit);
    }
    Cursor axiom_edges = column(axiom, "edges", "axiom", JsonReader<GrammarError>::any_size);
    if (axiom_edges.values.size() % 3) r.fail("axiom.edges", "must hold (step, span, class) triples");
    std::int64_t a = 0;
    for (std::size_t k = 0; k < axiom_edges.values.size() / 3; ++k) {
        a += axiom_edges.take();
        const std::int64_t b = a + axiom_edges.take();
        if (a < 0 || a > vertex_max || b < 0 || b > vertex_max) r.fail("axiom.edges", "edge " + std::to_string(k) + " joins a vertex out of range");
        g.axiom_edges.push_back({static_cast<std::int32_t>(a), static_cast<std::int32_t>(b), static_cast<HighwayClass>(axiom_edges.take(0, class_max))});
    }

    // Instances, in derivation order (see Packer::derivation_order).
    const bool lossless = enc.mode == "lossless";
    // Version 5 stores every instance's links by rank (neighbours, at least a count each) and
    // only the tolerances that are not 0; before, one tolerance per instance.
    const bool ranked_links = version >= 5;
    // Version 6 stores a link by rank, and a class change, as one number each (see Packer).
    const bool placed_links = version >= 6;
    Cursor tolerance = column(enc_doc, "tolerance", "encoding", JsonReader<GrammarError>::any_size);
    Cursor neighbours = column(enc_doc, "neighbours", "encoding", JsonReader<GrammarError>::any_size);
    if (!ranked_links && !neighbours.values.empty()) r.fail("encoding.neighbours", "is not part of version " + std::to_string(version));
    std::size_t axiom_nonterminals = 0;
    for (const AxiomVertex& v : g.axiom_vertices) axiom_nonterminals += v.symbol != 0;
    std::size_t instance_count = tolerance.values.size();
    if (ranked_links) {
        // As many instances as the derivation meets nonterminals; each takes one entry of
        // neighbours at least, which bounds a rule that places its own symbol.
        std::vector<std::vector<Symbol>> placed_by_rule(g.rules.size()); // the nonterminals each rule places
        for (std::size_t k = 0; k < g.rules.size(); ++k) {
            for (const RuleVertex& v : g.rules[k].vertices) {
                if (v.symbol) placed_by_rule[k].push_back(v.symbol);
            }
        }
        std::vector<Symbol> met;
        for (const AxiomVertex& v : g.axiom_vertices) {
            if (v.symbol) met.push_back(v.symbol);
        }
        for (std::size_t k = 0; k < met.size() && met.size() <= neighbours.values.size(); ++k) {
            const auto& placed = placed_by_rule[static_cast<std::size_t>(met[k] - 1)];
            met.insert(met.end(), placed.begin(), placed.end());
        }
        if (met.size() > neighbours.values.size()) r.fail("encoding.neighbours", "ends early (" + std::to_string(neighbours.values.size()) + " entries)");
        instance_count = met.size();
    }
    if (axiom_nonterminals > instance_count) r.fail("encoding.tolerance", "needs one entry per instance (" + std::to_string(axiom_nonterminals) + " nonterminals in the axiom)");
    // Corrections and shifts of the instances below the axiom's (those take its frames).
    Cursor correction = column(enc_doc, "correction", "encoding", 2 * (instance_count - axiom_nonterminals));
    Cursor shift = column(enc_doc, "shift", "encoding", 2 * (instance_count - axiom_nonterminals));
    Cursor residuals = column(enc_doc, "residuals", "encoding", JsonReader<GrammarError>::any_size);
    Cursor rule_points = column(enc_doc, "rule_points", "encoding", JsonReader<GrammarError>::any_size);
    Cursor links = column(enc_doc, "embedding", "encoding", JsonReader<GrammarError>::any_size);
    Cursor classes = column(enc_doc, "edge_classes", "encoding", JsonReader<GrammarError>::any_size);
    // Version 3 stores rule points and class changes only for the instances that have them,
    // and a link's rule vertex and class (by rank in link_classes) as one number.
    const bool sparse = version >= 3;
    Cursor link_classes = column(enc_doc, "link_classes", "encoding", JsonReader<GrammarError>::any_size);
    if (!sparse && !link_classes.values.empty()) r.fail("encoding.link_classes", "is not part of version 2");
    std::vector<HighwayClass> link_class;
    for (std::size_t c = 0; c < link_classes.values.size(); ++c) link_class.push_back(static_cast<HighwayClass>(link_classes.take(0, class_max)));
    Groups point_groups(rule_points, sparse), class_groups(classes, sparse);
    Groups link_groups(links, ranked_links); // version 5: own offsets only for the instances that have some
    std::int64_t tolerance_at = ranked_links && !tolerance.values.empty() ? tolerance.take(0, INT32_MAX) : -1;
    enc.instances.resize(instance_count);
    std::size_t next_id = 0;
    auto claim = [&](Symbol s, const std::string& where) {
        if (next_id >= instance_count) r.fail(where, "more nonterminals than instances (" + std::to_string(instance_count) + ")");
        enc.instances[next_id].symbol = s;
        return static_cast<std::int32_t>(next_id++);
    };
    bool any_nonterminal = false;
    for (const AxiomVertex& v : g.axiom_vertices) any_nonterminal |= v.symbol != 0;
    if (any_nonterminal) {
        for (const AxiomVertex& v : g.axiom_vertices) enc.axiom_instances.push_back(v.symbol ? claim(v.symbol, "axiom") : -1);
    }
    for (std::size_t k = 0; k < instance_count; ++k) {
        if (k >= next_id) r.fail("encoding", "instance " + std::to_string(k) + " rewrites no nonterminal");
        RuleInstance& inst = enc.instances[k];
        const Rule& rule = g.rules[inst.symbol - 1];
        const std::string where = "encoding.instances[" + std::to_string(k) + "]";
        if (k >= axiom_nonterminals) {
            inst.correction.scale = from_steps(correction.take(1 - static_cast<std::int64_t>(correction_scale_unit)) + static_cast<std::int64_t>(correction_scale_unit), correction_scale_unit);
            inst.correction.rotation_deg = from_steps(correction.take(), correction_degree_unit);
            inst.shift = {from_steps(shift.take(), quantum), from_steps(shift.take(), quantum)};
        }
        if (lossless) {
            for (std::size_t j = 0; j < rule.vertices.size(); ++j) {
                const double rx = from_steps(residuals.take(), quantum); // x before y
                inst.residuals.emplace_back(rx, from_steps(residuals.take(), quantum));
            }
        }
        std::int64_t stored_tolerance = 0;
        if (!ranked_links) {
            stored_tolerance = tolerance.take();
        } else if (tolerance_at == static_cast<std::int64_t>(k)) {
            stored_tolerance = tolerance.take();
            tolerance_at = tolerance.next < tolerance.values.size() ? tolerance_at + tolerance.take(1, INT32_MAX) : -1;
        }
        const auto tolerance_m = tolerance_of_code(stored_tolerance);
        if (!tolerance_m) r.fail(where + ".tolerance", "not a tolerance code");
        inst.tolerance_m = *tolerance_m;
        const auto instance = static_cast<std::int64_t>(k);
        const auto point_count = point_groups.count(instance);
        for (std::int64_t j = 0; j < point_count; ++j) inst.rule_points.push_back(static_cast<std::int32_t>(rule_points.take(0, INT32_MAX)));
        point_groups.done(instance);
        const auto link_count = ranked_links ? link_groups.count(instance) : links.take(0, INT32_MAX);
        if (link_count) {
            const double inverse = std::pow(10.0, static_cast<double>(links.take(-6, 12)));
            const auto k_vertices = static_cast<std::int64_t>(rule.vertices.size());
            if (sparse && link_class.empty()) r.fail("encoding.embedding", "has links, but encoding.link_classes is empty");
            for (std::int64_t j = 0; j < link_count; ++j) {
                RuleInstance::Link l;
                if (sparse) {
                    const std::int64_t code = links.take(0, k_vertices * static_cast<std::int64_t>(link_class.size()) - 1);
                    l.vertex = static_cast<std::int32_t>(code % k_vertices);
                    l.point.highway = link_class[static_cast<std::size_t>(code / k_vertices)];
                    l.point.offset = {from_steps(links.take(), inverse), from_steps(links.take(), inverse)};
                } else {
                    l.vertex = static_cast<std::int32_t>(links.take(0, k_vertices - 1));
                    l.point.offset = {from_steps(links.take(), inverse), from_steps(links.take(), inverse)};
                    l.point.highway = static_cast<HighwayClass>(links.take(0, class_max));
                }
                inst.embedding.push_back(l);
            }
        }
        if (ranked_links) {
            link_groups.done(instance);
            const auto k_vertices = static_cast<std::int64_t>(rule.vertices.size());
            const auto ranked_count = neighbours.take(0, INT32_MAX);
            if (ranked_count && link_class.empty()) r.fail("encoding.neighbours", "has links, but encoding.link_classes is empty");
            const std::int64_t codes = k_vertices * static_cast<std::int64_t>(link_class.size());
            for (std::int64_t j = 0; j < ranked_count; ++j) {
                RuleInstance::Neighbour l;
                // Version 6: code + codes × rank in one number; before, (code, rank).
                const std::int64_t combined = placed_links ? neighbours.take(0, codes * (RuleInstance::max_rank + 1) - 1) : 0;
                const std::int64_t link_code = placed_links ? combined % codes : neighbours.take(0, codes - 1);
                l.vertex = static_cast<std::int32_t>(link_code % k_vertices);
                l.highway = link_class[static_cast<std::size_t>(link_code / k_vertices)];
                l.rank = static_cast<std::int32_t>(placed_links ? combined / codes : neighbours.take(0, RuleInstance::max_rank));
                inst.neighbours.push_back(l);
            }
        }
        const auto class_count = class_groups.count(instance);
        const auto rule_edges = static_cast<std::int64_t>(rule.edges.size());
        for (std::int64_t j = 0; j < class_count; ++j) {
            if (placed_links) {
                // Version 6: edge + edges × the class's rank in link_classes.
                if (link_class.empty()) r.fail("encoding.edge_classes", "has class changes, but encoding.link_classes is empty");
                const std::int64_t code = classes.take(0, rule_edges * static_cast<std::int64_t>(link_class.size()) - 1);
                inst.edge_classes.emplace_back(static_cast<std::int32_t>(code % rule_edges), link_class[static_cast<std::size_t>(code / rule_edges)]);
                continue;
            }
            const auto edge = static_cast<std::int32_t>(classes.take(0, rule_edges - 1));
            inst.edge_classes.emplace_back(edge, static_cast<HighwayClass>(classes.take(0, class_max)));
        }
        class_groups.done(instance);
        bool has_nonterminal = false;
        for (const RuleVertex& v : rule.vertices) has_nonterminal |= v.symbol != 0;
        if (has_nonterminal) {
            for (const RuleVertex& v : rule.vertices) inst.children.push_back(v.symbol ? claim(v.symbol, where) : -1);
        }
    }
    if (next_id != instance_count) r.fail("encoding", std::to_string(instance_count - next_id) + " instances more than the nonterminals they rewrite");
    point_groups.finish();
    class_groups.finish();
    if (tolerance_at >= 0) r.fail("encoding.tolerance", "names instance " + std::to_string(tolerance_at) + ", past the last");
    if (ranked_links) link_groups.finish();
    for (const Cursor* c : {&axiom_edges, &correction, &shift, &residuals, &tolerance, &links, &neighbours}) c->finish();
    try {
        validate(g);
    } catch (const GrammarError& e) {
        throw GrammarError(name + ": " + e.what());
    }
    return g;
}

} // namespace

namespace {

// The document tree built from CBOR, with the bounds of the JSON parser (json_util.hpp).
class BoundedCborDom : public nlohmann::detail::json_sax_dom_parser<json> {
public:
    using Base = nlohmann::detail::json_sax_dom_parser<json>;
    BoundedCborDom(json& document, const std::string& name) : Base(document, false), name_(name) {}

    bool start_object(std::size_t n) { return deeper() && Base::start_object(n); }
    bool start_array(std::size_t n) { return deeper() && Base::start_array(n); }
    bool end_object() { --depth_; return Base::end_object(); }
    bool end_array() { --depth_; return Base::end_array(); }
    bool string(std::string& s) {
        if (s.size() > max_json_string_bytes) throw GrammarError(name_ + ": not valid input (a string longer than 1 MiB)");
        return Base::string(s);
    }
    bool parse_error(std::size_t position, const std::string&, const nlohmann::detail::exception&) {
        throw GrammarError(name_ + ": not valid CBOR (byte " + std::to_string(position) + ")");
    }

private:
    bool deeper() {
        if (++depth_ > max_json_depth) throw GrammarError(name_ + ": not valid input (nested more than " + std::to_string(max_json_depth) + " deep)");
        return true;
    }
    const std::string& name_;
    int depth_ = 0;
};

} // namespace

json parse_cbor(const std::string& bytes, const std::string& name) {
    json doc;
    BoundedCborDom dom(doc, name);
    try {
        if (!json::sax_parse(bytes, &dom, json::input_format_t::cbor)) throw GrammarError(name + ": not valid CBOR");
    } catch (const json::exception& e) {
        throw GrammarError(name + ": not valid CBOR (" + std::string(e.what()) + ")");
    }
    return doc;
}

bool looks_like_cbor(const std::string& bytes) {
    // A packed grammar is a CBOR map (major type 5); JSON text starts with '{' or blanks.
    return !bytes.empty() && (static_cast<unsigned char>(bytes[0]) & 0xe0) == 0xa0;
}

} // namespace ggg::io_detail
