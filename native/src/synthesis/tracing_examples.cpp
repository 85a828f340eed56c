// The first stage of tracing: the city's junctions learned as examples, each seen from each of
// its streets (what leaves it, at which turns, how long, how bent, of which class), and what
// they say of the city: its typical street, its share of right angles, its common class
// (tracing_stages.hpp).
#include "tracing_stages.hpp"

#include <algorithm>
#include <array>
#include <numeric>

#include "ggg/graph/plane_geometry.hpp"

namespace ggg::growth_detail::tracing {

void Tracer::learn_examples(const GeometricGraph& city, double radius) {
    const std::size_t n = city.vertex_count();
    if (city.edge_count() == 0) return;
    const std::vector<std::vector<EdgeId>> at = streets_at(city);
    // The city's streets from junction to junction (or dead end), through the vertices where
    // only two of its edges meet: many maps split a street wherever one of its tags changes,
    // and the spacing of junctions, not of those splits, is what tracing keeps to.
    std::vector<double> lengths;
    std::vector<char> seen(city.edge_count(), 0);
    for (std::size_t first = 0; first < city.edge_count(); ++first) {
        if (seen[first]) continue;
        seen[first] = 1;
        const auto [a, b] = city.edges[first];
        const Vec2 pa = city.positions[static_cast<std::size_t>(a)], pb = city.positions[static_cast<std::size_t>(b)];
        const bool near = !std::isfinite(radius) || distance_to_ring(region_, pa) <= radius;
        double length = (pb - pa).norm();
        for (const VertexId start : {a, b}) {
            VertexId v = start;
            auto previous = static_cast<EdgeId>(first);
            while (at[static_cast<std::size_t>(v)].size() == 2) {
                const auto& two = at[static_cast<std::size_t>(v)];
                const EdgeId next = two[0] == previous ? two[1] : two[0];
                if (seen[static_cast<std::size_t>(next)]) break;
                seen[static_cast<std::size_t>(next)] = 1;
                const auto [c, d] = city.edges[static_cast<std::size_t>(next)];
                const VertexId w = c == v ? d : c;
                length += (city.positions[static_cast<std::size_t>(w)] - city.positions[static_cast<std::size_t>(v)]).norm();
                previous = next;
                v = w;
            }
        }
        if (near) lengths.push_back(length);
    }
    // ... and its edges as the map has them.
    {
        std::vector<double> pieces;
        for (std::size_t e = 0; e < city.edge_count(); ++e) {
            const auto [a, b] = city.edges[e];
            const Vec2 pa = city.positions[static_cast<std::size_t>(a)], pb = city.positions[static_cast<std::size_t>(b)];
            if (std::isfinite(radius) && distance_to_ring(region_, pa) > radius) continue;
            pieces.push_back((pb - pa).norm());
        }
        if (!pieces.empty()) {
            std::nth_element(pieces.begin(), pieces.begin() + static_cast<long>(pieces.size() / 2), pieces.end());
            typical_edge_ = std::max(1.0, pieces[pieces.size() / 2]);
        }
    }
    if (lengths.empty()) return;
    std::nth_element(lengths.begin(), lengths.begin() + static_cast<long>(lengths.size() / 2), lengths.end());
    typical_ = std::max(1.0, lengths[lengths.size() / 2]);
    std::nth_element(lengths.begin(), lengths.begin() + static_cast<long>(9 * lengths.size() / 10), lengths.end());
    long_ = lengths[9 * lengths.size() / 10];
    std::nth_element(lengths.begin(), lengths.begin() + static_cast<long>(lengths.size() / 20), lengths.end());
    shortest_ = lengths[lengths.size() / 20];
    short_share_ = static_cast<double>(std::count_if(lengths.begin(), lengths.end(), [&](double l) { return l < crowd_ * typical_; })) /
                   static_cast<double>(lengths.size());
    // The city's own edges are not examples: its dead ends there are where its map was cut
    // (the extract's border, or this very region when it was cut out of the city).
    const Eigen::AlignedBox2d extent = bounds(city.positions.begin(), city.positions.end());
    auto at_a_border = [&](const Vec2& p) {
        const double margin = typical_;
        if ((p - extent.min()).minCoeff() < margin || (extent.max() - p).minCoeff() < margin) return true;
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
    // Offset crossings: two T-junctions a few metres apart on one street, their side streets
    // leaving to either side, where another city would have one crossing. Counted against the
    // city's crossings (four streets), with how far apart they are.
    std::size_t crossings = 0;
    for (std::size_t c = 0; c < n; ++c) {
        if (at[c].size() != 4 || at_a_border(city.positions[c])) continue;
        if (std::isfinite(radius) && distance_to_ring(region_, city.positions[c]) > radius) continue;
        ++crossings;
    }
    offsets_.clear();
    for (std::size_t e = 0; e < city.edge_count(); ++e) {
        const auto [a, b] = city.edges[e];
        if (a == b || at[static_cast<std::size_t>(a)].size() != 3 || at[static_cast<std::size_t>(b)].size() != 3) continue;
        const Vec2 pa = city.positions[static_cast<std::size_t>(a)];
        if (at_a_border(pa) || (std::isfinite(radius) && distance_to_ring(region_, pa) > radius)) continue;
        const double length = city.edge_length(static_cast<EdgeId>(e));
        if (length >= crowd_ * typical_ || length < 1e-3) continue;
        if (offset_sides(city, at, static_cast<EdgeId>(e))) offsets_.push_back(length);
    }
    offset_share_ = offsets_.empty() ? 0.0 : static_cast<double>(offsets_.size()) / static_cast<double>(offsets_.size() + crossings);
    // Junction islands: at a T-junction, a short street from the side street to the street it
    // meets, cutting the sharper corner between them (a street that forks where it meets
    // another, a slip road), which closes a small triangle. How often the city's T's have one
    // depends on that corner (forks at a slant do, the square T's of a grid seldom) and on
    // the street met (Helsinki's are where its side streets meet main roads).
    std::array<std::array<std::size_t, island_bins>, 2> t_counts{}, island_counts{};
    for (auto& kind : islands_) {
        for (auto& bin : kind) bin.clear();
    }
    auto adjacent_in_city = [&](VertexId x, VertexId y) {
        return std::any_of(at[static_cast<std::size_t>(x)].begin(), at[static_cast<std::size_t>(x)].end(), [&](EdgeId f) {
            const auto [p, q] = city.edges[static_cast<std::size_t>(f)];
            return (p == x && q == y) || (p == y && q == x);
        });
    };
    for (std::size_t c = 0; c < n; ++c) {
        if (at[c].size() != 3 || at_a_border(city.positions[c])) continue;
        if (std::isfinite(radius) && distance_to_ring(region_, city.positions[c]) > radius) continue;
        const auto v = static_cast<VertexId>(c);
        const Vec2 pc = city.positions[c];
        std::array<Vec2, 3> out;
        for (std::size_t k = 0; k < 3; ++k) out[k] = (leaving(city, at[c][k], v) - pc).normalized();
        const std::optional<TShape> t = t_shape(out);
        if (!t) continue;
        const std::size_t kind = main_class(city.edge_highway[static_cast<std::size_t>(at[c][t->near])]) ? 1 : 0;
        const std::size_t bin = island_bin(t->corner);
        ++t_counts[kind][bin];
        auto far_end = [&](EdgeId e) {
            const auto [p, q] = city.edges[static_cast<std::size_t>(e)];
            return p == v ? q : p;
        };
        const VertexId x = far_end(at[c][t->side]), y = far_end(at[c][t->near]);
        if (x == y || at[static_cast<std::size_t>(x)].size() < 3 || at[static_cast<std::size_t>(y)].size() < 3 || !adjacent_in_city(x, y)) continue;
        const Vec2 px = city.positions[static_cast<std::size_t>(x)], py = city.positions[static_cast<std::size_t>(y)];
        const double area = 0.5 * std::abs(cross(px - pc, py - pc));
        if (area < 1.0 || (s_.usual_block_m2 > 0 && area >= s_.usual_block_m2)) continue;
        ++island_counts[kind][bin];
        islands_[kind][bin].push_back({(px - pc).norm(), (py - pc).norm()});
    }
    // A bin with too few T's to say takes the rate of all the T's on streets of its kind, or of
    // all the city's T's where that kind has too few too.
    auto rate = [](std::size_t islands, std::size_t ts) { return static_cast<double>(islands) / static_cast<double>(std::max<std::size_t>(ts, 1)); };
    auto sum = [](const std::array<std::size_t, island_bins>& a) { return std::accumulate(a.begin(), a.end(), std::size_t{0}); };
    const std::size_t all_t = sum(t_counts[0]) + sum(t_counts[1]), all_islands = sum(island_counts[0]) + sum(island_counts[1]);
    for (std::size_t kind = 0; kind < 2; ++kind) {
        const double of_kind = sum(t_counts[kind]) >= 10 ? rate(sum(island_counts[kind]), sum(t_counts[kind])) : rate(all_islands, all_t);
        for (std::size_t bin = 0; bin < island_bins; ++bin) {
            island_rate_[kind][bin] = t_counts[kind][bin] >= 10 ? rate(island_counts[kind][bin], t_counts[kind][bin]) : of_kind;
        }
    }
    pick_common_class(class_counts);
    if (angles > 0) right_share_ = static_cast<double>(right) / static_cast<double>(angles);
}

namespace {

// The cells of a typical street's size around the region (within `radius` of it, over the
// city's extent) and clear of it: cells the region's border runs through are partly the
// region's (empty) ground. Empty where there are none or too many to look at.
struct BandCells {
    Vec2 lo = Vec2::Zero();
    double cell = 0.0;
    long columns = 0, rows = 0;
    std::vector<char> in_band; // per cell, row by row
    Vec2 centre(long i, long j) const { return lo + Vec2((static_cast<double>(i) + 0.5) * cell, (static_cast<double>(j) + 0.5) * cell); }
    long cell_of(const Vec2& p) const {
        const auto i = static_cast<long>(std::floor((p.x() - lo.x()) / cell)), j = static_cast<long>(std::floor((p.y() - lo.y()) / cell));
        return i < 0 || j < 0 || i >= columns || j >= rows ? -1 : j * columns + i;
    }
};

BandCells band_cells(const GeometricGraph& city, const std::vector<Vec2>& region, double cell, double radius) {
    BandCells band;
    Eigen::AlignedBox2d ground = bounds(city.positions.begin(), city.positions.end());
    if (std::isfinite(radius)) {
        const Eigen::AlignedBox2d near = bounds(region.begin(), region.end());
        ground = ground.intersection(Eigen::AlignedBox2d(near.min() - Vec2(radius, radius), near.max() + Vec2(radius, radius)));
    }
    if (ground.isEmpty()) return band;
    const Vec2 lo = ground.min(), hi = ground.max();
    const auto columns = static_cast<long>(std::ceil((hi.x() - lo.x()) / cell)) + 1;
    const auto rows = static_cast<long>(std::ceil((hi.y() - lo.y()) / cell)) + 1;
    if (columns <= 0 || rows <= 0 || columns * rows > 4'000'000) return band;
    band.lo = lo;
    band.cell = cell;
    band.columns = columns;
    band.rows = rows;
    band.in_band.assign(static_cast<std::size_t>(columns * rows), 0);
    for (long j = 0; j < rows; ++j) {
        for (long i = 0; i < columns; ++i) {
            const Vec2 centre = band.centre(i, j);
            band.in_band[static_cast<std::size_t>(j * columns + i)] =
                !inside(region, centre) && distance_to_ring(region, centre) >= 0.75 * cell &&
                !(std::isfinite(radius) && distance_to_ring(region, centre) > radius);
        }
    }
    return band;
}

} // namespace

void Tracer::measure_density(const GeometricGraph& city, double radius) {
    // Cells of a typical street's size, around the region (within `radius`) and outside it,
    // that have a street vertex in them or next to them: the ground the city covers. Ground
    // its map does not cover (beyond the extract, or across a gap between two cities) would
    // make the city look sparser than it is; its own squares and parks, up to three cells
    // across, count.
    const double cell = typical_;
    const BandCells band = band_cells(city, region_, cell, radius);
    if (band.in_band.empty()) return;
    const long columns = band.columns, rows = band.rows;
    auto cell_of = [&](const Vec2& p) { return band.cell_of(p); };
    std::vector<char> has_vertex(static_cast<std::size_t>(columns * rows), 0);
    for (const Vec2& p : city.positions) {
        if (const long c = cell_of(p); c >= 0) has_vertex[static_cast<std::size_t>(c)] = 1;
    }
    std::vector<char> counted(has_vertex.size(), 0);
    std::size_t cells = 0;
    for (long j = 0; j < rows; ++j) {
        for (long i = 0; i < columns; ++i) {
            if (!band.in_band[static_cast<std::size_t>(j * columns + i)]) continue;
            bool covered = false;
            for (long dj = -1; dj <= 1 && !covered; ++dj) {
                for (long di = -1; di <= 1 && !covered; ++di) {
                    const long a = i + di, b = j + dj;
                    covered = a >= 0 && b >= 0 && a < columns && b < rows && has_vertex[static_cast<std::size_t>(b * columns + a)];
                }
            }
            if (covered) counted[static_cast<std::size_t>(j * columns + i)] = 1, ++cells;
        }
    }
    double length = 0.0;
    std::vector<int> degree(city.vertex_count(), 0);
    for (const auto& [a, b] : city.edges) ++degree[static_cast<std::size_t>(a)], ++degree[static_cast<std::size_t>(b)];
    std::size_t junctions = 0;
    for (std::size_t v = 0; v < city.vertex_count(); ++v) {
        if (const long c = cell_of(city.positions[v]); degree[v] >= 3 && c >= 0 && counted[static_cast<std::size_t>(c)]) ++junctions;
    }
    for (std::size_t e = 0; e < city.edge_count(); ++e) {
        const Vec2* p = city.geometry_begin(static_cast<EdgeId>(e));
        for (std::size_t k = 0; k + 1 < city.geometry_size(static_cast<EdgeId>(e)); ++k) {
            if (const long c = cell_of(0.5 * (p[k] + p[k + 1])); c >= 0 && counted[static_cast<std::size_t>(c)]) length += (p[k + 1] - p[k]).norm();
        }
    }
    // Too little ground to say (a few cells): no cap.
    density_ = cells >= 16 ? length / (static_cast<double>(cells) * cell * cell) : 0.0;
    junction_density_ = cells >= 16 ? static_cast<double>(junctions) / (static_cast<double>(cells) * cell * cell) : 0.0;
    density_cells_ = cells;
}

void Tracer::measure_empty_ground(const GeometricGraph& city, double radius) {
    // How much of the ground around the region is far from every street (its parks, its
    // hillsides, water): the region may have as much of it, and no more (open_empty_ground).
    // The cells of measure_density, all of them.
    const double cell = typical_;
    const BandCells band = band_cells(city, region_, cell, radius);
    if (band.in_band.empty()) return;
    const Vec2 lo = band.lo, hi = band.lo + cell * Vec2(static_cast<double>(band.columns), static_cast<double>(band.rows));
    std::vector<spatial::EdgeEntry> entries;
    const spatial::Box reach({lo.x() - 4.0 * cell, lo.y() - 4.0 * cell}, {hi.x() + 4.0 * cell, hi.y() + 4.0 * cell});
    for (std::size_t e = 0; e < city.edge_count(); ++e) {
        const spatial::Box box = spatial::edge_box(city, static_cast<EdgeId>(e));
        if (spatial::bg::intersects(box, reach)) entries.push_back({box, static_cast<EdgeId>(e)});
    }
    const spatial::RTree<spatial::EdgeEntry> streets(entries.begin(), entries.end());
    std::size_t all = 0, far = 0;
    for (long j = 0; j < band.rows; ++j) {
        for (long i = 0; i < band.columns; ++i) {
            if (!band.in_band[static_cast<std::size_t>(j * band.columns + i)]) continue;
            const Vec2 centre = band.centre(i, j);
            double d = 4.0 * cell;
            for (auto it = streets.qbegin(spatial::bgi::intersects(spatial::around(centre, d))); it != streets.qend(); ++it) {
                const Vec2* q = city.geometry_begin(it->second);
                for (std::size_t k = 0; k + 1 < city.geometry_size(it->second); ++k) d = std::min(d, distance_to_segment(centre, q[k], q[k + 1]));
            }
            ++all;
            if (d > empty_reach * cell) ++far;
        }
    }
    empty_share_ = all >= 16 ? static_cast<double>(far) / static_cast<double>(all) : 1.0;
}

void Tracer::pick_common_class(const std::vector<std::size_t>& class_counts) {
    const auto most = std::max_element(class_counts.begin(), class_counts.end());
    if (*most > 0) common_class_ = static_cast<HighwayClass>(most - class_counts.begin());
}

const Example& Tracer::example_for(bool main) {
    const auto& pool = (main && !main_examples_.empty()) || other_examples_.empty() ? main_examples_ : other_examples_;
    std::uniform_int_distribution<std::size_t> pick(0, pool.size() - 1);
    return pool[pick(rng_)];
}

} // namespace ggg::growth_detail::tracing
