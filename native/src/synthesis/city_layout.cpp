#include "ggg/synthesis/city_layout.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <mutex>
#include <string>
#include <thread>

#include "ggg/error.hpp"
#include "ggg/graph/road_widths.hpp"
#include "city_stages.hpp"

namespace ggg {

namespace {

using namespace city_detail; // the stages, Frame, PieceIndex, Shared, cl, bgi, Box

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
