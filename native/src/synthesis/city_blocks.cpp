// Each face's block, yard and buildings (city_stages.hpp).
#include "city_stages.hpp"

#include <algorithm>
#include <numbers>

#include "ggg/random.hpp"

namespace ggg::city_detail {

namespace {

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

} // namespace

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

} // namespace ggg::city_detail
