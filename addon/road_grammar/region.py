"""The region of Grow into Region (grammar_ops.ROADS_OT_grow_region): a polygon read from a
Blender object, in the road graph's frame.

A region object is a curve or a mesh, taken as it is evaluated (modifiers, and a curve's
resolution, applied), seen from above:

* a mesh with faces: the outline of its faces (the edges that only one face uses), e.g. a
  plane, a grid or an n-gon;
* a mesh without faces, or a curve (poly, Bezier or NURBS, made cyclic): its edges, which
  must form a closed loop, e.g. a Bezier circle or a cyclic poly line drawn by hand. A
  filled 2-D curve has faces and is read by its outline, like a mesh.

When there are several loops (a mesh with a hole, a curve of several splines), the one
that encloses the largest area is the region (growth takes one simple polygon). The
corners are brought from the object's local space to the world and into the road graph
object's local space (the frame of ggg.Graph positions: x, y in metres, z dropped).
"""

import numpy as np

from . import importer, mesh_build

REGION_TYPES = {'CURVE', 'MESH'}


class RegionError(Exception):
    """The object cannot be a region; the message says why."""


def is_candidate(obj):
    """A curve or a mesh that is not part of a road graph (the graph, its surface, its
    Patterns or Rules display): what the region picker lists."""
    if obj is None or obj.type not in REGION_TYPES:
        return False
    if importer.road_graph_object(obj) is not None:
        return False
    # (Imported here: rule_display imports grammar, which imports this module.)
    from . import pattern_display, rule_display

    return not (obj.get(pattern_display.OBJECT_KEY) or obj.get(rule_display.OBJECT_KEY))


def poll(_self, obj):
    """PointerProperty poll of the region picker."""
    return is_candidate(obj)


def polygon(obj, depsgraph, graph_obj):
    """The region of ``obj`` in ``graph_obj``'s local frame: (corners (N, 2) float64, not
    closed, and the number of closed loops the object has). Raises RegionError."""
    if obj is None:
        raise RegionError("No region object")
    if obj.type not in REGION_TYPES:
        raise RegionError("{} is a {}, not a curve or a mesh: a region is a closed curve or a mesh".format(
            obj.name, obj.type.lower()))
    if importer.road_graph_object(obj) is not None:
        raise RegionError("{} is part of a road graph: a region is another curve or mesh".format(obj.name))
    evaluated = obj.evaluated_get(depsgraph)
    mesh = evaluated.to_mesh()
    try:
        if mesh is None:
            raise RegionError("{} has no geometry".format(obj.name))
        co = np.empty(len(mesh.vertices) * 3, dtype=np.float64)
        mesh.vertices.foreach_get("co", co)
        co = co.reshape(-1, 3)
        edges = mesh_build.edge_vertices(mesh)
        if len(mesh.polygons):
            loop_edges = np.empty(len(mesh.loops), dtype=np.int64)
            mesh.loops.foreach_get("edge_index", loop_edges)
            uses = np.bincount(loop_edges, minlength=len(edges))
            outline = edges[uses == 1]
            if len(outline) == 0:
                raise RegionError("{} is a closed surface: it has no outline (use a plane, a face or a closed "
                                  "curve)".format(obj.name))
        else:
            outline = edges
        matrix = np.array(graph_obj.matrix_world.inverted() @ evaluated.matrix_world, dtype=np.float64)
    finally:
        evaluated.to_mesh_clear()
    if len(outline) == 0:
        raise RegionError("{} has no edges: a region is a closed curve, or a mesh with a face or a closed loop of "
                          "edges".format(obj.name))
    local = co @ matrix[:3, :3].T + matrix[:3, 3]
    loops = closed_loops(outline, obj.name)
    rings = [_clean(local[loop, :2]) for loop in loops]
    ring = max(rings, key=lambda r: abs(signed_area(r)))
    if len(ring) < 3:
        raise RegionError("{} has fewer than 3 corners: a region needs at least 3".format(obj.name))
    extent = float(np.ptp(ring, axis=0).max())
    # (Float32 coordinates: a plane seen edge-on keeps an area of about 1e-7 of its size squared.)
    if not abs(signed_area(ring)) > max(1e-6, 1e-6 * extent * extent):
        raise RegionError("{} has no area seen from above (in the XY plane of the road graph)".format(obj.name))
    return ring, len(loops)


def closed_loops(edges, name="the region"):
    """The closed loops of ``edges`` ((M, 2) vertex ids, every vertex on exactly two of
    them): a list of vertex id arrays in the order of the loop. Raises RegionError for open
    ends and branches."""
    edges = np.asarray(edges, dtype=np.int64).reshape(-1, 2)
    edges = edges[edges[:, 0] != edges[:, 1]]
    if len(edges) == 0:
        raise RegionError("{} has no edges".format(name))
    degree = np.bincount(edges.ravel())
    used = np.flatnonzero(degree)
    open_ends = int(np.count_nonzero(degree[used] == 1))
    if open_ends:
        raise RegionError("The outline of {} is not closed: it has {} open end{} (make the curve cyclic, Alt+C, or "
                          "close the loop of edges)".format(name, open_ends, "" if open_ends == 1 else "s"))
    if degree.max() > 2:
        raise RegionError("The outline of {} branches: a vertex is on {} of its edges; a region is one closed "
                          "loop".format(name, int(degree.max())))
    neighbours = {}
    for u, v in edges.tolist():
        neighbours.setdefault(u, []).append(v)
        neighbours.setdefault(v, []).append(u)
    seen = set()
    loops = []
    for start in used.tolist():
        if start in seen:
            continue
        loop, previous, current = [start], -1, start
        seen.add(start)
        while True:
            a, b = neighbours[current]
            following = b if a == previous else a
            if following == start or following in seen:
                break
            loop.append(following)
            seen.add(following)
            previous, current = current, following
        loops.append(np.array(loop, dtype=np.int64))
    return loops


def _clean(ring):
    """``ring`` without repeated consecutive corners (nor a last corner equal to the first)."""
    ring = np.asarray(ring, dtype=np.float64).reshape(-1, 2)
    if len(ring) == 0:
        return ring
    extent = float(np.ptp(ring, axis=0).max()) if len(ring) > 1 else 0.0
    step = np.linalg.norm(ring - np.roll(ring, 1, axis=0), axis=1)
    keep = step > 1e-9 * max(extent, 1.0)
    if not keep.any():
        return ring[:1]
    return ring[keep]


def signed_area(ring):
    """Shoelace area of a polygon (N, 2), positive when counter-clockwise."""
    ring = np.asarray(ring, dtype=np.float64).reshape(-1, 2)
    if len(ring) < 3:
        return 0.0
    x, y = ring[:, 0], ring[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


def contains(ring, points):
    """Whether each of ``points`` (K, 2) lies inside the polygon ``ring`` (even-odd rule,
    as the growth tests it)."""
    ring = np.asarray(ring, dtype=np.float64).reshape(-1, 2)
    points = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    inside = np.zeros(len(points), dtype=bool)
    a, b = ring, np.roll(ring, 1, axis=0)
    for (ax, ay), (bx, by) in zip(a, b):
        crosses = (ay > points[:, 1]) != (by > points[:, 1])
        with np.errstate(divide="ignore", invalid="ignore"):
            x = (bx - ax) * (points[:, 1] - ay) / (by - ay) + ax
        inside ^= crosses & (points[:, 0] < x)
    return inside
