#include "ggg/synthesis/city_layout.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <mutex>
#include <numbers>
#include <string>
#include <thread>

#include <clipper.hpp>

#include "ggg/error.hpp"
#include "ggg/graph/road_widths.hpp"
#include "ggg/graph/spatial_index.hpp"

namespace ggg {

namespace {

namespace bg = spatial::bg;
namespace bgi = spatial::bgi;
namespace cl = ClipperLib;

using spatial::Box;
using PieceEntry = std::pair<Box, std::size_t>;

// Clipper works on integers: millimetres, relative to the graph's bounding-box centre.
constexpr double kScale = 1000.0;

struct Frame {
    Vec2 centre = Vec2::Zero();
    cl::IntPoint to_int(const Vec2& p) const {
        return {static_cast<cl::cInt>(std::llround((p.x() - centre.x()) * kScale)),
                static_cast<cl::cInt>(std::llround((p.y() - centre.y()) * kScale))};
    }
    Vec2 to_metres(const cl::IntPoint& p) const {
        return {static_cast<double>(p.X) / kScale + centre.x(), static_cast<double>(p.Y) / kScale + centre.y()};
    }
    cl::Path path(const Vec2* begin, const Vec2* end) const {
        cl::Path out;
        out.reserve(static_cast<std::size_t>(end - begin));
        for (auto p = begin; p != end; ++p) out.push_back(to_int(*p));
        return out;
    }
};

// splitmix64: a seeded stream per block, so results do not depend on thread scheduling.
struct Random {
    std::uint64_t state;
    std::uint64_t next() {
        std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    double uniform(double low, double high) { return low + (high - low) * static_cast<double>(next() >> 11) * 0x1.0p-53; }
};

Box box_of(const Vec2* begin, const Vec2* end) {
    Box b{{begin->x(), begin->y()}, {begin->x(), begin->y()}};
    for (auto p = begin; p != end; ++p) bg::expand(b, spatial::point(*p));
    return b;
}

void ccw(std::vector<Vec2>& ring) {
    if (ring_area(ring.data(), ring.data() + ring.size()) < 0) std::reverse(ring.begin(), ring.end());
}

// Where each edge's and vertex's road pieces are.
struct PieceIndex {
    std::vector<std::size_t> edge_begin; // pieces of edge e: [edge_begin[e], edge_begin[e+1])
    std::vector<std::int64_t> vertex_disc; // piece of the disc at v, -1 for none
    std::vector<Box> boxes;                // bounding box of every piece
};

// The road pieces: segment rectangles, bevel triangles at bends, discs at vertices.
void road_pieces(const GeometricGraph& g, const std::vector<double>& half, int sides, CityLayout& out, PieceIndex& where) {
    const std::size_t m = g.edge_count();
    std::vector<double> vertex_radius(g.vertex_count(), 0.0);
    std::vector<EdgeId> vertex_edge(g.vertex_count(), -1);
    auto better = [&](EdgeId a, EdgeId b) { // a more important than b at a junction
        const int ra = highway_rank(g.edge_highway[static_cast<std::size_t>(a)]);
        const int rb = highway_rank(g.edge_highway[static_cast<std::size_t>(b)]);
        return ra < rb || (ra == rb && half[static_cast<std::size_t>(a)] > half[static_cast<std::size_t>(b)]);
    };
    std::vector<Vec2> line, ring;
    where.edge_begin.assign(m + 1, 0);
    where.vertex_disc.assign(g.vertex_count(), -1);
    for (std::size_t e = 0; e < m; ++e) {
        where.edge_begin[e] = out.roads.size();
        const double h = half[e];
        const auto id = static_cast<EdgeId>(e);
        for (VertexId v : g.edges[e]) {
            auto& r = vertex_radius[static_cast<std::size_t>(v)];
            r = std::max(r, h);
            auto& best = vertex_edge[static_cast<std::size_t>(v)];
            if (best < 0 || better(id, best)) best = id;
        }
        line.clear();
        if (g.geometry_size(id) >= 2) {
            line.assign(g.geometry_begin(id), g.geometry_begin(id) + g.geometry_size(id));
        } else {
            line = {g.positions[static_cast<std::size_t>(g.edges[e][0])], g.positions[static_cast<std::size_t>(g.edges[e][1])]};
        }
        // Drop repeated points: a zero-length segment has no direction.
        line.erase(std::unique(line.begin(), line.end(), [](const Vec2& a, const Vec2& b) { return (a - b).norm() < 1e-6; }),
                   line.end());
        Vec2 previous_normal = Vec2::Zero();
        for (std::size_t k = 0; k + 1 < line.size(); ++k) {
            const Vec2 d = (line[k + 1] - line[k]).normalized();
            const Vec2 normal{-d.y() * h, d.x() * h};
            out.roads.add({line[k] - normal, line[k + 1] - normal, line[k + 1] + normal, line[k] + normal}, id);
            out.road_piece.push_back(RoadPiece::segment);
            if (k > 0) {
                // The outer side of the bend is the one the road turns away from; fill it so
                // that every point within h of the bend point is road (a mitre up to 120
                // degrees of turn, a polygon around the circle beyond), as the kerb inset
                // and the clearance of the buildings assume.
                const double turn = previous_normal.x() * normal.y() - previous_normal.y() * normal.x();
                if (std::abs(turn) > 1e-9 * h * h) {
                    const double side = turn > 0 ? -1.0 : 1.0;
                    const Vec2 a = side * previous_normal, b = side * normal;
                    const Vec2 bisector = (a + b).normalized();
                    const double cos_half = bisector.dot(a) / h;
                    ring.clear();
                    if (cos_half > 0.5) {
                        ring = {line[k], line[k] + a, line[k] + bisector * (h / cos_half), line[k] + b};
                    } else {
                        const double r = h / std::cos(std::numbers::pi / 8);
                        for (int j = 0; j < 8; ++j) {
                            const double angle = 2.0 * std::numbers::pi * (j + 0.5) / 8;
                            ring.push_back(line[k] + Vec2{r * std::cos(angle), r * std::sin(angle)});
                        }
                    }
                    ccw(ring);
                    out.roads.add(ring, id);
                    out.road_piece.push_back(RoadPiece::bend);
                }
            }
            previous_normal = normal;
        }
    }
    where.edge_begin[m] = out.roads.size();
    // Discs circumscribe the circle, so that they cover every rectangle's end.
    const double grow = 1.0 / std::cos(std::numbers::pi / sides);
    for (std::size_t v = 0; v < g.vertex_count(); ++v) {
        if (vertex_edge[v] < 0) continue;
        const double r = vertex_radius[v] * grow;
        ring.clear();
        for (int k = 0; k < sides; ++k) {
            const double a = 2.0 * std::numbers::pi * (k + 0.5) / sides;
            ring.push_back(g.positions[v] + Vec2{r * std::cos(a), r * std::sin(a)});
        }
        where.vertex_disc[v] = static_cast<std::int64_t>(out.roads.size());
        out.roads.add(ring, vertex_edge[v]);
        out.road_piece.push_back(RoadPiece::junction);
    }
}

// Polygons with holes -> simple polygons without holes, by cutting each polygon that has
// holes with a vertical line through its first hole until none is left.
void add_without_holes(const cl::PolyTree& tree, const Frame& frame, std::int32_t owner, PolygonSet& out, int depth = 0);

void add_outer_node(const cl::PolyNode& node, const Frame& frame, std::int32_t owner, PolygonSet& out, int depth) {
    if (node.Contour.size() < 3) return;
    // Clipper can leave a hole without a contour (a degenerate one): only real holes count.
    const cl::PolyNode* first_hole = nullptr;
    for (const cl::PolyNode* hole : node.Childs) {
        if (hole->Contour.size() >= 3) {
            first_hole = hole;
            break;
        }
    }
    if (!first_hole || depth > 64) {
        std::vector<Vec2> ring;
        ring.reserve(node.Contour.size());
        for (const auto& p : node.Contour) ring.push_back(frame.to_metres(p));
        ccw(ring);
        out.add(ring, owner);
    } else {
        cl::Paths polygon{node.Contour};
        for (const cl::PolyNode* hole : node.Childs) {
            if (hole->Contour.size() >= 3) polygon.push_back(hole->Contour);
        }
        cl::cInt left = node.Contour[0].X, right = left, bottom = node.Contour[0].Y, top = bottom;
        for (const auto& p : node.Contour) {
            left = std::min(left, p.X);
            right = std::max(right, p.X);
            bottom = std::min(bottom, p.Y);
            top = std::max(top, p.Y);
        }
        cl::cInt hole_left = first_hole->Contour[0].X, hole_right = hole_left;
        for (const auto& p : first_hole->Contour) {
            hole_left = std::min(hole_left, p.X);
            hole_right = std::max(hole_right, p.X);
        }
        const cl::cInt cut = hole_left + (hole_right - hole_left) / 2;
        for (int half = 0; half < 2; ++half) {
            const cl::cInt x0 = half == 0 ? left - 1 : cut, x1 = half == 0 ? cut : right + 1;
            const cl::Path strip{{x0, bottom - 1}, {x1, bottom - 1}, {x1, top + 1}, {x0, top + 1}};
            cl::Clipper clipper;
            clipper.AddPaths(polygon, cl::ptSubject, true);
            clipper.AddPath(strip, cl::ptClip, true);
            cl::PolyTree piece;
            clipper.Execute(cl::ctIntersection, piece, cl::pftNonZero, cl::pftNonZero);
            add_without_holes(piece, frame, owner, out, depth + 1);
        }
    }
}

void add_without_holes(const cl::PolyTree& tree, const Frame& frame, std::int32_t owner, PolygonSet& out, int depth) {
    // Outer contours are the tree's top level and the children of holes (islands).
    std::vector<const cl::PolyNode*> todo(tree.Childs.begin(), tree.Childs.end());
    while (!todo.empty()) {
        const cl::PolyNode* node = todo.back();
        todo.pop_back();
        if (node->IsHole()) continue;
        add_outer_node(*node, frame, owner, out, depth);
        for (const cl::PolyNode* hole : node->Childs)
            for (const cl::PolyNode* island : hole->Childs) todo.push_back(island);
    }
}

double paths_area(const cl::Paths& paths) {
    double a = 0;
    for (const auto& p : paths) a += cl::Area(p);
    return a / (kScale * kScale);
}

// Thin cutters across the building band, one per lot boundary along every ring of the yard.
cl::Paths lot_cutters(const cl::Paths& yard, const Frame& frame, double reach, const CityLayoutOptions& o, Random& random) {
    cl::Paths cutters;
    for (const cl::Path& ring : yard) {
        const std::size_t n = ring.size();
        if (n < 3) continue;
        std::vector<Vec2> pts(n);
        for (std::size_t i = 0; i < n; ++i) pts[i] = frame.to_metres(ring[i]);
        double perimeter = 0;
        for (std::size_t i = 0; i < n; ++i) perimeter += (pts[(i + 1) % n] - pts[i]).norm();
        // Inside is on the left of every ring Clipper returns (outer CCW, holes CW).
        double s = random.uniform(0.0, o.lot_max_m);
        std::size_t i = 0;
        double along = 0; // arc length at pts[i]
        while (s < perimeter) {
            while (i < n) {
                const double len = (pts[(i + 1) % n] - pts[i]).norm();
                if (along + len >= s) break;
                along += len;
                ++i;
            }
            if (i >= n) break;
            const Vec2 a = pts[i], b = pts[(i + 1) % n];
            const double len = (b - a).norm();
            if (len > 1e-9) {
                const Vec2 d = (b - a) / len;
                const Vec2 p = a + d * (s - along);
                const Vec2 inward{-d.y(), d.x()};
                const Vec2 w = d * (0.5 * o.gap_m);
                const Vec2 from = p - inward * 1.0, to = p + inward * reach;
                cl::Path cutter{frame.to_int(from - w), frame.to_int(from + w), frame.to_int(to + w), frame.to_int(to - w)};
                if (!cl::Orientation(cutter)) cl::ReversePath(cutter);
                cutters.push_back(std::move(cutter));
            }
            s += random.uniform(o.lot_min_m, o.lot_max_m);
        }
    }
    return cutters;
}

using SegmentEntry = std::pair<Box, std::pair<EdgeId, std::uint32_t>>;
using spatial::VertexEntry;

// Edges that cross another edge without a shared vertex (bridges, tunnels): their pieces are
// cut out of every block they pass over.
std::vector<char> crossing_edges(const GeometricGraph& g) {
    auto line = [&](EdgeId e) -> std::pair<const Vec2*, std::size_t> {
        if (g.geometry_size(e) >= 2) return {g.geometry_begin(e), g.geometry_size(e)};
        return {nullptr, 0};
    };
    auto point = [&](EdgeId e, std::uint32_t k) {
        const auto [pts, n] = line(e);
        if (n) return pts[k];
        return g.positions[static_cast<std::size_t>(g.edges[static_cast<std::size_t>(e)][k])];
    };
    std::vector<SegmentEntry> entries;
    for (std::size_t e = 0; e < g.edge_count(); ++e) {
        const auto id = static_cast<EdgeId>(e);
        const std::size_t n = std::max<std::size_t>(line(id).second, 2);
        for (std::uint32_t k = 0; k + 1 < n; ++k) {
            const Vec2 a = point(id, k), b = point(id, k + 1);
            entries.push_back({spatial::around(a, b), {id, k}});
        }
    }
    const spatial::RTree<SegmentEntry> tree(entries.begin(), entries.end());
    std::vector<char> crossing(g.edge_count(), 0);
    std::vector<SegmentEntry> hits;
    for (const auto& [box, id] : entries) {
        hits.clear();
        tree.query(bgi::intersects(box), std::back_inserter(hits));
        const Vec2 a = point(id.first, id.second), b = point(id.first, id.second + 1);
        for (const auto& [other_box, other] : hits) {
            if (other.first <= id.first) continue;
            const Vec2 c = point(other.first, other.second), d = point(other.first, other.second + 1);
            const Vec2 r = b - a, q = d - c;
            const double denominator = r.x() * q.y() - r.y() * q.x();
            if (std::abs(denominator) < 1e-12) continue;
            const Vec2 ac = c - a;
            const double t = (ac.x() * q.y() - ac.y() * q.x()) / denominator;
            const double u = (ac.x() * r.y() - ac.y() * r.x()) / denominator;
            constexpr double inside = 1e-6;
            if (t > inside && t < 1 - inside && u > inside && u < 1 - inside) {
                crossing[static_cast<std::size_t>(id.first)] = crossing[static_cast<std::size_t>(other.first)] = 1;
            }
        }
    }
    return crossing;
}

bool inside_rings(const Vec2& p, const PlanarFaces& faces, std::size_t first, std::size_t last) {
    bool inside = false;
    for (std::size_t r = first; r < last; ++r) {
        const Vec2* pts = faces.points.data() + faces.ring_offsets[r];
        const auto n = static_cast<std::size_t>(faces.ring_offsets[r + 1] - faces.ring_offsets[r]);
        for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
            if ((pts[i].y() > p.y()) != (pts[j].y() > p.y()) &&
                p.x() < (pts[j].x() - pts[i].x()) * (p.y() - pts[i].y()) / (pts[j].y() - pts[i].y()) + pts[i].x()) {
                inside = !inside;
            }
        }
    }
    return inside;
}

// What every face's work reads.
struct Shared {
    const GeometricGraph& g;
    const PlanarFaces& faces;
    const std::vector<std::size_t>& first_ring;
    const PolygonSet& roads;
    const PieceIndex& where;
    const Adjacency& adjacency;
    const spatial::RTree<VertexEntry>& vertices;
    const spatial::RTree<PieceEntry>& crossing_pieces;
    const std::vector<RoadPiece>& piece_kind;
    const std::vector<cl::Paths>& outlines; // union of each edge's segment and bend pieces
    const Frame& frame;
    const CityLayoutOptions& options;
};

// The road pieces that can reach into face f: those of every edge at a vertex of its
// boundary, of every edge at a vertex inside it (nested components) and of crossing edges.
void face_pieces(const Shared& s, std::size_t f, const Box& bounds, std::vector<std::int32_t>& stamp, std::vector<std::size_t>& out) {
    out.clear();
    const auto mark = static_cast<std::int32_t>(f) + 1;
    auto add_vertex = [&](VertexId v) {
        const auto vi = static_cast<std::size_t>(v);
        if (stamp[vi] == mark) return;
        stamp[vi] = mark;
        if (s.where.vertex_disc[vi] >= 0) out.push_back(static_cast<std::size_t>(s.where.vertex_disc[vi]));
        for (auto k = s.adjacency.offsets[vi]; k < s.adjacency.offsets[vi + 1]; ++k) {
            const auto e = static_cast<std::size_t>(s.adjacency.edge_ids[static_cast<std::size_t>(k)]);
            // Only the part of a road that comes near the face: a long road leaving the
            // block adds just its first pieces.
            for (std::size_t p = s.where.edge_begin[e]; p < s.where.edge_begin[e + 1]; ++p) {
                if (bg::intersects(s.where.boxes[p], bounds)) out.push_back(p);
            }
        }
    };
    for (auto k = s.faces.face_edge_offsets[f]; k < s.faces.face_edge_offsets[f + 1]; ++k) {
        const auto& edge = s.g.edges[static_cast<std::size_t>(s.faces.face_edges[static_cast<std::size_t>(k)])];
        add_vertex(edge[0]);
        add_vertex(edge[1]);
    }
    std::vector<VertexEntry> candidates;
    s.vertices.query(bgi::intersects(bounds), std::back_inserter(candidates));
    for (const auto& [point, v] : candidates) {
        if (stamp[static_cast<std::size_t>(v)] == mark) continue;
        if (inside_rings(s.g.positions[static_cast<std::size_t>(v)], s.faces, s.first_ring[f], s.first_ring[f + 1])) add_vertex(v);
    }
    std::vector<PieceEntry> crossing;
    s.crossing_pieces.query(bgi::intersects(bounds), std::back_inserter(crossing));
    for (const auto& entry : crossing) out.push_back(entry.second);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
}

struct FaceResult {
    PolygonSet blocks, yards, buildings;
    std::vector<double> depth;
    bool empty = false;
};

void build_face(const Shared& s, std::size_t f, std::vector<std::int32_t>& stamp, std::vector<std::int32_t>& edge_stamp,
                std::vector<std::size_t>& pieces_in, FaceResult& out) {
    const auto face = static_cast<std::int32_t>(f);
    const PlanarFaces& faces = s.faces;
    const auto& first_ring = s.first_ring;
    const PolygonSet& roads = s.roads;
    const Frame& frame = s.frame;
    const CityLayoutOptions& o = s.options;
    cl::Paths subject;
    Box bounds;
    bool first = true;
    for (std::size_t r = first_ring[f]; r < first_ring[f + 1]; ++r) {
        const Vec2* begin = faces.points.data() + faces.ring_offsets[r];
        const Vec2* end = faces.points.data() + faces.ring_offsets[r + 1];
        subject.push_back(frame.path(begin, end));
        const Box b = box_of(begin, end);
        if (first) bounds = b;
        else bg::expand(bounds, b);
        first = false;
    }
    if (subject.empty()) return;
    cl::Clipper clipper;
    clipper.AddPaths(subject, cl::ptSubject, true);
    face_pieces(s, f, bounds, stamp, pieces_in);
    // An edge goes in as its outline (one polygon instead of overlapping rectangles: far
    // fewer intersections for Clipper's sweep), a junction as its disc.
    for (std::size_t piece : pieces_in) {
        if (s.piece_kind[piece] == RoadPiece::junction) {
            clipper.AddPath(frame.path(roads.points.data() + roads.offsets[piece], roads.points.data() + roads.offsets[piece + 1]),
                            cl::ptClip, true);
            continue;
        }
        const auto e = static_cast<std::size_t>(roads.owner[piece]);
        if (edge_stamp[e] == face + 1) continue;
        edge_stamp[e] = face + 1;
        clipper.AddPaths(s.outlines[e], cl::ptClip, true);
    }
    cl::PolyTree kerb_tree;
    clipper.Execute(cl::ctDifference, kerb_tree, cl::pftNonZero, cl::pftNonZero);
    cl::Paths kerb;
    cl::PolyTreeToPaths(kerb_tree, kerb);
    if (paths_area(kerb) < 1.0) {
        out.empty = true;
        return;
    }
    add_without_holes(kerb_tree, frame, face, out.blocks);

    cl::ClipperOffset inset(2.0, 0.25 * kScale);
    inset.AddPaths(kerb, cl::jtMiter, cl::etClosedPolygon);
    cl::PolyTree yard_tree;
    inset.Execute(yard_tree, -o.sidewalk_m * kScale);
    cl::Paths yard;
    cl::PolyTreeToPaths(yard_tree, yard);
    const double yard_area = paths_area(yard);
    if (yard_area < o.min_building_area_m2) return;
    add_without_holes(yard_tree, frame, face, out.yards);
    if (faces.face_area[f] > o.max_block_area_m2) return; // fields and forests, not city blocks
    if (yard_area < o.min_yard_area_m2) return;           // traffic islands, roundabouts

    Random random{o.seed * 0x2545F4914F6CDD1Dull + f};
    const double depth = random.uniform(o.depth_min_m, o.depth_max_m);
    cl::ClipperOffset deeper(2.0, 0.25 * kScale);
    deeper.AddPaths(yard, cl::jtMiter, cl::etClosedPolygon);
    cl::Paths court;
    deeper.Execute(court, -depth * kScale);
    // Cutters reach well past the band, so that they also part the deeper corner lots.
    cl::Paths cutters = lot_cutters(yard, frame, depth * 2.5 + 5.0, o, random);
    cl::Clipper lots;
    lots.AddPaths(yard, cl::ptSubject, true);
    lots.AddPaths(court, cl::ptClip, true);
    lots.AddPaths(cutters, cl::ptClip, true);
    cl::PolyTree lot_tree;
    lots.Execute(cl::ctDifference, lot_tree, cl::pftNonZero, cl::pftNonZero);
    // Points closer than 0.3 m to the line of their neighbours add nothing to a building.
    for (cl::PolyNode* node = lot_tree.GetFirst(); node != nullptr; node = node->GetNext()) {
        cl::CleanPolygon(node->Contour, 0.3 * kScale);
    }
    PolygonSet pieces;
    add_without_holes(lot_tree, frame, face, pieces);
    for (std::size_t k = 0; k < pieces.size(); ++k) {
        const Vec2* begin = pieces.points.data() + pieces.offsets[k];
        const Vec2* end = pieces.points.data() + pieces.offsets[k + 1];
        const double area = ring_area(begin, end);
        double perimeter = 0;
        for (auto p = begin; p != end; ++p) perimeter += ((p + 1 == end ? *begin : p[1]) - *p).norm();
        // Slivers (where a cutter grazed a corner) are no buildings.
        if (area < o.min_building_area_m2 || 4.0 * std::numbers::pi * area < 0.12 * perimeter * perimeter) continue;
        out.buildings.add(std::vector<Vec2>(begin, end), face);
        out.depth.push_back(depth);
    }
}

void append(PolygonSet& to, const PolygonSet& from) {
    const std::int64_t base = to.offsets.back();
    to.points.insert(to.points.end(), from.points.begin(), from.points.end());
    for (std::size_t k = 1; k < from.offsets.size(); ++k) to.offsets.push_back(base + from.offsets[k]);
    to.owner.insert(to.owner.end(), from.owner.begin(), from.owner.end());
}

} // namespace

void PolygonSet::add(const std::vector<Vec2>& ring, std::int32_t owner_id) {
    points.insert(points.end(), ring.begin(), ring.end());
    offsets.push_back(static_cast<std::int64_t>(points.size()));
    owner.push_back(owner_id);
}

namespace {

// Floors grow towards the middle of the network and in small blocks (a dense core, low-rise
// suburbs), vary from lot to lot, and one lot in a hundred of the densest blocks is a tower.
void building_heights(const GeometricGraph& g, const CityLayoutOptions& o, CityLayout& out) {
    const std::size_t count = out.buildings.size();
    out.building_height_m.resize(count);
    out.building_tint.resize(count);
    if (count == 0) return;
    std::vector<double> xs, ys;
    for (const Vec2& p : g.positions) {
        xs.push_back(p.x());
        ys.push_back(p.y());
    }
    auto middle = [](std::vector<double>& v) {
        std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
        return v[v.size() / 2];
    };
    const auto [x_low, x_high] = std::minmax_element(xs.begin(), xs.end());
    const auto [y_low, y_high] = std::minmax_element(ys.begin(), ys.end());
    const double radius = std::max(1.0, 0.5 * std::hypot(*x_high - *x_low, *y_high - *y_low));
    const Vec2 centre(middle(xs), middle(ys));
    Random random{o.seed * 0x2545F4914F6CDD1Dull + 0x5851F42D4C957F2Dull};
    auto base_floors = [](double area_m2) { // 4 floors in blocks under 0.3 ha, down to 1.5 over 25 ha
        const double x = std::log10(std::max(area_m2, 1.0));
        const std::array<double, 4> at{3.5, 4.2, 4.8, 5.4}, floors{4.0, 3.0, 2.0, 1.5};
        if (x <= at.front()) return floors.front();
        for (std::size_t i = 1; i < at.size(); ++i) {
            if (x <= at[i]) return floors[i - 1] + (floors[i] - floors[i - 1]) * (x - at[i - 1]) / (at[i] - at[i - 1]);
        }
        return floors.back();
    };
    for (std::size_t b = 0; b < count; ++b) {
        const Vec2 first = out.buildings.points[static_cast<std::size_t>(out.buildings.offsets[b])];
        const double area = out.faces.face_area[static_cast<std::size_t>(out.buildings.owner[b])];
        const double base = base_floors(area);
        const double distance = (first - centre).norm() / radius;
        const double near_middle = std::clamp(1.0 - 1.5 * distance, 0.0, 1.0);
        const double central = 1.0 + 0.6 * near_middle * near_middle;
        // Log-normal noise (sigma 0.25), from two uniforms (Box-Muller).
        const double u1 = 1.0 - random.uniform(0.0, 1.0), u2 = random.uniform(0.0, 1.0);
        double floors = base * central * std::exp(0.25 * std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2));
        const bool tower = random.uniform(0.0, 1.0) < 0.01 && base * central >= 5.0;
        if (tower) floors *= random.uniform(1.8, 3.0);
        floors = std::clamp(std::rint(floors), 1.0, 60.0);
        out.building_height_m[b] = floors * o.floor_height_m + random.uniform(0.3, 1.2);
        out.building_tint[b] = random.uniform(0.0, 1.0);
    }
}

} // namespace

CityLayout city_layout(const GeometricGraph& g, const CityLayoutOptions& options, const ProgressCallback& progress) {
    const std::size_t m = g.edge_count();
    std::vector<double> half = options.half_widths;
    if (half.empty()) {
        half = road_widths(g);
        for (double& h : half) h *= 0.5;
    }
    if (half.size() != m) throw UsageError("half_widths has " + std::to_string(half.size()) + " values for " + std::to_string(m) + " edges");
    for (double h : half) {
        if (!(h > 0.0 && h < 500.0)) throw InputError("half_widths must be in (0, 500) metres");
    }
    const CityLayoutOptions& o = options;
    if (!(o.sidewalk_m >= 0 && o.sidewalk_m < 100) || !(o.lot_min_m > 1 && o.lot_max_m >= o.lot_min_m) ||
        !(o.depth_min_m > 1 && o.depth_max_m >= o.depth_min_m) || !(o.gap_m >= 0.01) || o.disc_sides < 6 || o.disc_sides > 128 ||
        !(o.max_block_area_m2 > 0) || !(o.min_yard_area_m2 >= 0) || !(o.floor_height_m >= 1 && o.floor_height_m <= 10)) {
        throw UsageError("city layout options out of range (sidewalk >= 0, lots and depths > 1 m with min <= max, gap >= 0.01 m, "
                         "6..128 disc sides, max block area > 0, floors 1 to 10 m high)");
    }
    for (const Vec2& p : g.positions) {
        if (!p.allFinite() || std::abs(p.x()) > 1e8 || std::abs(p.y()) > 1e8) throw InputError("vertex positions must be finite and within 100,000 km");
    }

    CityLayout out;
    report(progress, 0.0, "faces");
    out.faces = planar_faces(g);
    report(progress, 0.1, "road surfaces");
    PieceIndex where;
    road_pieces(g, half, o.disc_sides, out, where);
    const Adjacency adjacency(g);
    where.boxes.reserve(out.roads.size());
    for (std::size_t k = 0; k < out.roads.size(); ++k) {
        where.boxes.push_back(box_of(out.roads.points.data() + out.roads.offsets[k], out.roads.points.data() + out.roads.offsets[k + 1]));
    }

    Frame frame;
    if (!g.positions.empty()) {
        const Box b = box_of(g.positions.data(), g.positions.data() + g.positions.size());
        frame.centre = {0.5 * (b.min_corner().get<0>() + b.max_corner().get<0>()), 0.5 * (b.min_corner().get<1>() + b.max_corner().get<1>())};
    }
    const std::vector<char> crossing = crossing_edges(g);
    std::vector<PieceEntry> entries;
    for (std::size_t e = 0; e < g.edge_count(); ++e) {
        if (!crossing[e]) continue;
        for (std::size_t k = where.edge_begin[e]; k < where.edge_begin[e + 1]; ++k) {
                entries.emplace_back(where.boxes[k], k);
        }
    }
    const spatial::RTree<PieceEntry> crossing_pieces(entries.begin(), entries.end());
    std::vector<VertexEntry> vertex_entries;
    for (std::size_t v = 0; v < g.vertex_count(); ++v) {
        vertex_entries.emplace_back(spatial::point(g.positions[v]), static_cast<VertexId>(v));
    }
    const spatial::RTree<VertexEntry> vertex_tree(vertex_entries.begin(), vertex_entries.end());
    out.crossing_edges = static_cast<std::size_t>(std::count(crossing.begin(), crossing.end(), 1));

    // Faces are independent: split them over threads, collect in face order.
    const std::size_t faces = out.faces.face_count();
    // Rings of a face are contiguous, in face order.
    std::vector<std::size_t> first_ring(faces + 1, out.faces.ring_count());
    for (std::size_t r = out.faces.ring_count(); r-- > 0;) first_ring[static_cast<std::size_t>(out.faces.ring_face[r])] = r;
    for (std::size_t f = faces; f-- > 0;) first_ring[f] = std::min(first_ring[f], first_ring[f + 1]);
    std::vector<FaceResult> results(faces);
    const unsigned threads = std::max(1u, std::min(o.threads ? o.threads : std::thread::hardware_concurrency(), 16u));
    std::vector<cl::Paths> outlines(g.edge_count());
    {
        std::atomic<std::size_t> next_edge{0};
        auto outline_work = [&] {
            for (std::size_t e; (e = next_edge.fetch_add(1)) < g.edge_count();) {
                cl::Clipper clipper;
                for (std::size_t k = where.edge_begin[e]; k < where.edge_begin[e + 1]; ++k) {
                    clipper.AddPath(frame.path(out.roads.points.data() + out.roads.offsets[k],
                                               out.roads.points.data() + out.roads.offsets[k + 1]),
                                    cl::ptSubject, true);
                }
                clipper.Execute(cl::ctUnion, outlines[e], cl::pftNonZero, cl::pftNonZero);
            }
        };
        std::vector<std::thread> pool;
        for (unsigned t = 1; t < threads; ++t) pool.emplace_back(outline_work);
        outline_work();
        for (auto& t : pool) t.join();
    }
    report(progress, 0.2, "blocks and buildings");
    const Shared shared{g, out.faces, first_ring, out.roads, where, adjacency, vertex_tree, crossing_pieces, out.road_piece, outlines, frame, o};
    std::atomic<std::size_t> next{0};
    std::atomic<bool> stop{false};
    std::exception_ptr failure;
    std::mutex failure_mutex;
    auto work = [&](bool reporting) {
        std::vector<std::int32_t> stamp(g.vertex_count(), 0), edge_stamp(g.edge_count(), 0);
        std::vector<std::size_t> pieces;
        try {
            for (std::size_t f; !stop && (f = next.fetch_add(1)) < faces;) {
                build_face(shared, f, stamp, edge_stamp, pieces, results[f]);
                if (reporting && f % 256 == 0) report(progress, 0.2 + 0.75 * static_cast<double>(f) / static_cast<double>(faces), "blocks and buildings");
            }
        } catch (...) {
            stop = true;
            std::lock_guard lock(failure_mutex);
            if (!failure) failure = std::current_exception();
        }
    };
    std::vector<std::thread> pool;
    for (unsigned t = 1; t < threads; ++t) pool.emplace_back(work, false);
    work(true);
    for (auto& t : pool) t.join();
    if (failure) {
        try {
            std::rethrow_exception(failure);
        } catch (const cl::clipperException& ex) {
            throw InputError(std::string("polygon clipping failed: ") + ex.what());
        }
    }
    for (std::size_t f = 0; f < faces; ++f) {
        append(out.blocks, results[f].blocks);
        append(out.yards, results[f].yards);
        append(out.buildings, results[f].buildings);
        out.building_depth.insert(out.building_depth.end(), results[f].depth.begin(), results[f].depth.end());
        out.empty_blocks += results[f].empty;
    }
    building_heights(g, o, out);
    report(progress, 1.0, "done");
    return out;
}

} // namespace ggg
