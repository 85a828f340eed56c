"""The region of Grow into Region (operators.region.ROADS_OT_grow_region): a polygon read from a
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

from ..core.names import PATTERNS_KEY, RULES_KEY
from ..core.polygons import RegionError, clean, closed_loops, signed_area
from . import mesh, roads

REGION_TYPES = {'CURVE', 'MESH'}


def is_candidate(obj):
    """A curve or a mesh that is not part of a road graph (the graph, its surface, its
    Patterns or Rules display): what the region picker lists."""
    if obj is None or obj.type not in REGION_TYPES:
        return False
    if roads.road_graph_object(obj) is not None:
        return False
    return not (obj.get(PATTERNS_KEY) or obj.get(RULES_KEY))


def polygon(obj, depsgraph, graph_obj):
    """The region of ``obj`` in ``graph_obj``'s local frame: (corners (N, 2) float64, not
    closed, and the number of closed loops the object has). Raises RegionError."""
    if obj is None:
        raise RegionError("No region object")
    if obj.type not in REGION_TYPES:
        raise RegionError("{} is a {}, not a curve or a mesh: a region is a closed curve or a mesh".format(
            obj.name, obj.type.lower()))
    if roads.road_graph_object(obj) is not None:
        raise RegionError("{} is part of a road graph: a region is another curve or mesh".format(obj.name))
    evaluated = obj.evaluated_get(depsgraph)
    shape = evaluated.to_mesh()
    try:
        if shape is None:
            raise RegionError("{} has no geometry".format(obj.name))
        co = np.empty(len(shape.vertices) * 3, dtype=np.float64)
        shape.vertices.foreach_get("co", co)
        co = co.reshape(-1, 3)
        edges = mesh.edge_vertices(shape)
        if len(shape.polygons):
            loop_edges = np.empty(len(shape.loops), dtype=np.int64)
            shape.loops.foreach_get("edge_index", loop_edges)
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
    rings = [clean(local[loop, :2]) for loop in loops]
    ring = max(rings, key=lambda r: abs(signed_area(r)))
    if len(ring) < 3:
        raise RegionError("{} has fewer than 3 corners: a region needs at least 3".format(obj.name))
    extent = float(np.ptp(ring, axis=0).max())
    # (Float32 coordinates: a plane seen edge-on keeps an area of about 1e-7 of its size squared.)
    if not abs(signed_area(ring)) > max(1e-6, 1e-6 * extent * extent):
        raise RegionError("{} has no area seen from above (in the XY plane of the road graph)".format(obj.name))
    return ring, len(loops)
