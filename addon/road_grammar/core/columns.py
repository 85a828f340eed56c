"""A road graph as the columns of ``ggg.Graph.from_arrays``, and two of them joined side by
side (Stitch Cities). (The surgery around a growth, the part of a graph on some of its
vertices and the graph with what grew on it put back, is the library's:
``ggg.induced_subgraph`` and ``ggg.with_grown``.)

``GraphColumns`` holds what a road graph object's mesh (and its surface's polylines) says
about the graph; ``data.graph_edit.MeshGraph`` reads it from the object. Besides the graph's
own columns it carries what only Blender holds (other attributes, selection and hiding),
so that it can follow the vertices and edges it belongs to.
"""

import numpy as np

from .names import FRAME_A, FRAME_B, NAME, SYMBOL
from .polylines import complete_polylines

# Point attributes that the graph carries itself (not copied from the old mesh).
GRAPH_POINT_ATTRIBUTES = (SYMBOL, FRAME_A, FRAME_B)
# Edge attributes that the graph carries itself.
GRAPH_EDGE_ATTRIBUTES = ("highway", "rank", "width", "lanes", "oneway", NAME)
# Edge columns whose values the library takes only in a range: (dtype, accepted(values),
# untagged). A value set by hand outside it goes in untagged and comes back on its edge.
RANGED_COLUMNS = {
    "width": (np.float64, lambda w: np.isfinite(w) & (w > 0.0), np.nan),
    "lanes": (np.int64, lambda n: (n >= 0) & (n <= 50), 0),
    "oneway": (np.int64, lambda d: (d >= -1) & (d <= 1), 0),
}
# Untagged values of the ranged columns, for a graph that lacks one of them.
UNTAGGED = {name: (dtype, untagged) for name, (dtype, _accepted, untagged) in RANGED_COLUMNS.items()}


class GraphColumns:
    """The columns of a road graph, as ggg.Graph.from_arrays wants them: ``positions`` (N, 2),
    ``edges`` (M, 2), ``symbols`` (N,), ``frames`` (N, 4: a, b, x, y) with ``frame_missing``
    (a vertex without a frame of its own), ``highway`` (M,) or None, the ranged ``columns``
    {"width", "lanes", "oneway"} with the values the library ``refused`` ({name: (mask,
    the original values)}), ``names`` (M str) or None, ``geometry`` (offsets, points) or
    None, and what only Blender holds: ``edge_attributes`` and ``point_attributes``
    {name: (kind, values)}, ``vertex_flags`` and ``edge_flags`` {"select", "hide"}; and
    ``more_rewrites`` (Graph.more_rewrites) or None."""

    more_rewrites = None

    @property
    def nonterminal_count(self):
        return int(np.count_nonzero(self.symbols))

    def graph(self, ggg):
        """The ggg.Graph of these columns (raises ggg.Error for a graph it refuses)."""
        highway = None
        if self.highway is not None:
            highway = np.clip(self.highway, 0, len(ggg.highway_classes()) - 1)
        return ggg.Graph.from_arrays(
            self.positions, self.edges, origin_latlon=self.origin_latlon,
            vertex_symbols=self.symbols, vertex_frames=self.frames,
            edge_highway=highway, edge_width=self.columns.get("width"), edge_lanes=self.columns.get("lanes"),
            edge_oneway=self.columns.get("oneway"), edge_names=self.names, edge_geometry=self.geometry,
            more_rewrites=self.more_rewrites)


def stacked(first, second, n_first, n_second, dtype, fill):
    """``first`` and ``second`` one after the other; a missing one (None) as ``fill``."""
    if first is None and second is None:
        return None
    parts = [np.full(n, fill, dtype=dtype) if values is None else np.asarray(values, dtype=dtype)
             for values, n in ((first, n_first), (second, n_second))]
    return np.concatenate(parts)


def stacked_attributes(first, second, n_first, n_second):
    """{name: (kind, values)} of two meshes' user attributes one after the other; an
    attribute of one only is zero on the other's elements, and one whose type differs
    between them takes the first's type."""
    joined = {}
    for name in list(first) + [name for name in second if name not in first]:
        kind, values = first.get(name, second.get(name))
        dtype = np.asarray(values).dtype
        a = first[name][1] if name in first else None
        b = second[name][1] if name in second else None
        joined[name] = (kind, stacked(a, b, n_first, n_second, dtype, 0))
    return joined


def joined(ggg, first, second, matrix):
    """GraphColumns of ``first``'s vertices and edges followed by ``second``'s (both
    GraphColumns), ``second``'s brought into ``first``'s frame by the 4x4 ``matrix`` (seen from
    above: its x, y rows; the frames of its nonterminals turned and scaled by its linear
    part). Every column and attribute follows its vertex or edge; one that only one of them
    has is untagged (or zero) on the other's."""
    matrix = np.asarray(matrix, dtype=np.float64)
    linear, shift = matrix[:2, :2], matrix[:2, 3]
    n1, n2 = len(first.positions), len(second.positions)
    e1, e2 = len(first.edges), len(second.edges)
    out = GraphColumns()
    moved = second.positions @ linear.T + shift
    out.positions = np.concatenate((first.positions, moved))
    out.edges = np.concatenate((first.edges, second.edges + n1)).reshape(-1, 2)
    out.symbols = np.concatenate((first.symbols, second.symbols))
    out.frame_missing = np.concatenate((first.frame_missing, second.frame_missing))
    ab = second.frames[:, :2] @ linear.T
    out.frames = np.column_stack((np.concatenate((first.frames[:, :2], ab)), out.positions))
    parts = []
    for part, offset, turn in ((first, 0, None), (second, n1, linear)):
        if part.more_rewrites is not None:
            vertices, symbols, frames = (np.asarray(column) for column in part.more_rewrites)
            frames = np.asarray(frames, dtype=np.float64).reshape(-1, 4)
            vertices = vertices.astype(np.int64) + offset
            ab_more = frames[:, :2] if turn is None else frames[:, :2] @ turn.T
            parts.append((vertices, symbols, np.column_stack((ab_more, out.positions[vertices]))))
    out.more_rewrites = None if not parts else tuple(np.concatenate(column) for column in zip(*parts))
    road = ggg.highway_classes().index("road") if "road" in ggg.highway_classes() else 0
    out.highway = stacked(first.highway, second.highway, e1, e2, np.int64, road)
    out.columns, out.refused = {}, {}
    for name, (dtype, untagged) in UNTAGGED.items():
        values = stacked(first.columns.get(name), second.columns.get(name), e1, e2, dtype, untagged)
        if values is not None:
            out.columns[name] = values
        if name in first.refused or name in second.refused:
            masks, originals = [], []
            for part, count in ((first, e1), (second, e2)):
                refused, original = part.refused.get(name, (np.zeros(count, dtype=bool), None))
                masks.append(refused)
                originals.append(np.full(count, untagged, dtype=dtype) if original is None else original)
            out.refused[name] = (np.concatenate(masks), np.concatenate(originals).astype(dtype))
    if first.names is None and second.names is None:
        out.names = None
    else:
        out.names = list(first.names or [""] * e1) + list(second.names or [""] * e2)
    offsets, points = [], []
    for part, shape in ((first, None), (second, (linear, shift))):
        geometry = part.geometry
        if geometry is None:
            geometry = complete_polylines(np.zeros(len(part.edges) + 1, dtype=np.int64), np.zeros((0, 2)),
                                          part.positions, part.edges)
        part_offsets, part_points = (np.asarray(geometry[0], dtype=np.int64),
                                     np.asarray(geometry[1], dtype=np.float64).reshape(-1, 2))
        if shape is not None:
            part_points = part_points @ shape[0].T + shape[1]
        offsets.append(part_offsets if not offsets else part_offsets[1:] + len(points[0]))
        points.append(part_points)
    out.geometry = (np.concatenate(offsets), np.concatenate(points))
    out.edge_attributes = stacked_attributes(first.edge_attributes, second.edge_attributes, e1, e2)
    out.point_attributes = stacked_attributes(first.point_attributes, second.point_attributes, n1, n2)
    out.vertex_flags = {name: stacked(first.vertex_flags.get(name), second.vertex_flags.get(name), n1, n2, bool,
                                      False) for name in first.vertex_flags}
    out.edge_flags = {name: stacked(first.edge_flags.get(name), second.edge_flags.get(name), e1, e2, bool, False)
                      for name in first.edge_flags}
    out.origin_latlon = first.origin_latlon
    return out


def more_rewrite_slots(vertex_count, more_rewrites):
    """The rewrites pending at vertices besides their own (``Graph.more_rewrites``: vertices,
    symbols, frames) as per-vertex slots: [(symbols (N,), a (N,), b (N,)), ...] for slots 2,
    3, ...; a vertex with fewer has symbol 0 in the rest."""
    vertices, symbols, frames = (np.asarray(column) for column in more_rewrites)
    frames = frames.reshape(-1, 4)
    slots = []
    taken = np.zeros(vertex_count, dtype=np.int64)  # slots already filled per vertex
    for vertex, symbol, frame in zip(vertices.astype(np.int64), symbols, frames):
        k = taken[vertex]
        if k == len(slots):
            slots.append((np.zeros(vertex_count, dtype=np.int64), np.ones(vertex_count), np.zeros(vertex_count)))
        slots[k][0][vertex], slots[k][1][vertex], slots[k][2][vertex] = symbol, frame[0], frame[1]
        taken[vertex] += 1
    return slots


def more_rewrites_from_slots(slots, positions, symbols):
    """``Graph.more_rewrites`` (vertices, symbols, frames) of per-vertex slots as
    ``more_rewrite_slots`` makes them, at the vertices' ``positions``; None when there are none.
    A slot at a terminal vertex (``symbols`` 0) or with a frame of no scale is left out."""
    vertices, kinds, frames = [], [], []
    for slot_symbols, a, b in slots:
        usable = (slot_symbols > 0) & (np.asarray(symbols) > 0) & np.isfinite(a) & np.isfinite(b) & (np.hypot(a, b) > 0)
        where = np.flatnonzero(usable)
        vertices.append(where)
        kinds.append(slot_symbols[where])
        frames.append(np.column_stack((a[where], b[where], positions[where])))
    if not vertices or not sum(len(v) for v in vertices):
        return None
    vertices = np.concatenate(vertices)
    order = np.argsort(vertices, kind="stable")
    return (vertices[order], np.concatenate(kinds)[order], np.concatenate(frames).reshape(-1, 4)[order])
