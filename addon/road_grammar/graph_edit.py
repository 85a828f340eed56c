"""A road graph object <-> ggg.Graph, for the grammar operators.

``MeshGraph`` reads the object's mesh, and the edge polylines of its surface, into the
columns of ggg.Graph.from_arrays; ``Replacement`` puts a derived graph back into the same
mesh datablock and rebuilds the surface from the graph's own columns, as an import does.
Everything is computed before the first change, so an error leaves the object as it was.
``induced_subgraph`` and ``appended`` cut a ggg.Graph down to some of its vertices and add
what ggg.grow_region grew (Grow into Region grows the streets without the nonterminals).

ggg.derive keeps every vertex and edge that is not rewritten with all its columns (width,
lanes, oneway, name, polyline). New edges come without a width tag and get the usual
rule (lanes x lane width, else the class default of the preferences) and a straight
surface. What only Blender holds (other FLOAT, INT and BOOLEAN attributes, selection and
hiding) follows the derivation's ``source_vertex``: for a vertex directly, for an edge
through the two vertices it joins.
"""

import contextlib

import bpy
import numpy as np

from . import importer, mesh_build
from .importer import FRAME_A, FRAME_B, NAME, SURFACE_EDGE, SYMBOL

# Point attributes that the graph carries itself (not copied from the old mesh).
_GRAPH_POINT_ATTRIBUTES = (SYMBOL, FRAME_A, FRAME_B)
# Edge attributes that the graph carries itself.
_GRAPH_EDGE_ATTRIBUTES = ("highway", "rank", "width", "lanes", "oneway", NAME)
# Edge columns whose values the library takes only in a range: (dtype, accepted(values),
# untagged). A value set by hand outside it goes in untagged and comes back on its edge.
_RANGED_COLUMNS = {
    "width": (np.float64, lambda w: np.isfinite(w) & (w > 0.0), np.nan),
    "lanes": (np.int64, lambda n: (n >= 0) & (n <= 50), 0),
    "oneway": (np.int64, lambda d: (d >= -1) & (d <= 1), 0),
}


class MeshGraph:
    """The columns of a road graph object's mesh (and its surface's polylines), as
    ggg.Graph.from_arrays wants them."""

    def __init__(self, obj):
        mesh = obj.data
        self.positions = mesh_build.positions_xy(mesh)
        self.edges = mesh_build.edge_vertices(mesh)
        n = len(self.positions)
        self.symbols = _values(mesh, SYMBOL, 'POINT', np.int64)
        self.symbols = np.zeros(n, dtype=np.int64) if self.symbols is None else np.maximum(self.symbols, 0)
        a = _values(mesh, FRAME_A, 'POINT', np.float64)
        b = _values(mesh, FRAME_B, 'POINT', np.float64)
        without_frames = a is None or b is None
        a = np.ones(n) if a is None else a
        b = np.zeros(n) if b is None else b
        # A frame without scale (e.g. a vertex added by hand) becomes the unit frame.
        degenerate = ~(np.isfinite(a) & np.isfinite(b)) | (np.hypot(a, b) == 0.0)
        # (Grow into Region gives such a vertex's rule its learned size instead.)
        self.frame_missing = degenerate | without_frames
        a, b = np.where(degenerate, 1.0, a), np.where(degenerate, 0.0, b)
        self.frames = np.column_stack((a, b, self.positions))
        self.highway = _values(mesh, "highway", 'EDGE', np.int64)
        # Ranged columns: (values for the library, the mesh's values where it refuses them).
        self.columns, self.refused = {}, {}
        for name, (dtype, accepted, untagged) in _RANGED_COLUMNS.items():
            values = _values(mesh, name, 'EDGE', dtype)
            if values is None:
                continue
            refused = ~accepted(values)
            self.columns[name] = np.where(refused, untagged, values)
            if refused.any():
                self.refused[name] = (refused, values)
        self.names = mesh_build.read_strings(mesh, NAME, 'EDGE')
        self.geometry = surface_polylines(obj, self.positions, self.edges)
        self.edge_attributes = {name: value for name, value in mesh_build.user_attributes(mesh, 'EDGE').items()
                                if name not in _GRAPH_EDGE_ATTRIBUTES}
        self.point_attributes = {name: value for name, value in mesh_build.user_attributes(mesh, 'POINT').items()
                                 if name not in _GRAPH_POINT_ATTRIBUTES}
        self.vertex_flags = mesh_build.read_flags(mesh.vertices)
        self.edge_flags = mesh_build.read_flags(mesh.edges)
        lat = float(obj.get("origin_lat", 0.0))
        lon = float(obj.get("origin_lon", 0.0))
        self.origin_latlon = (lat, lon)

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
            edge_oneway=self.columns.get("oneway"), edge_names=self.names, edge_geometry=self.geometry)


def _polylines(offsets, points, edge_ids):
    """(offsets, points) of the polylines of the edges ``edge_ids`` only, in that order."""
    offsets = np.asarray(offsets, dtype=np.int64)
    points = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    edge_ids = np.asarray(edge_ids, dtype=np.int64)
    starts = offsets[edge_ids]
    counts = offsets[edge_ids + 1] - starts
    new_offsets = np.zeros(len(edge_ids) + 1, dtype=np.int64)
    np.cumsum(counts, out=new_offsets[1:])
    index = np.repeat(starts, counts) + mesh_build._ramp(counts)
    return new_offsets, points[index]


def _assembled(ggg, graph, vertex_ids, edge_ids, edges, more=None):
    """A ggg.Graph of the vertices ``vertex_ids`` and edges ``edge_ids`` of ``graph`` with
    all their columns (``edges``: those edges renumbered), followed by ``more`` =
    (grown, first vertex, first edge, edges): the vertices and edges of the ggg.Graph
    ``grown`` from those ids on (``edges``: renumbered)."""
    parts = [(graph, np.asarray(vertex_ids, dtype=np.int64), np.asarray(edge_ids, dtype=np.int64), edges)]
    if more is not None:
        grown, first_vertex, first_edge, grown_edges = more
        parts.append((grown, np.arange(first_vertex, grown.vertex_count, dtype=np.int64),
                      np.arange(first_edge, grown.edge_count, dtype=np.int64), grown_edges))
    columns = {name: [] for name in ("positions", "symbols", "frames", "edges", "highway", "width", "lanes", "oneway",
                                     "names", "offsets", "points")}
    point_count = 0
    for part, vertices, part_edges, renumbered in parts:
        columns["positions"].append(np.asarray(part.positions, dtype=np.float64).reshape(-1, 2)[vertices])
        columns["symbols"].append(np.asarray(part.vertex_symbols, dtype=np.int64)[vertices])
        columns["frames"].append(np.asarray(part.vertex_frames, dtype=np.float64).reshape(-1, 4)[vertices])
        columns["edges"].append(np.asarray(renumbered, dtype=np.int64).reshape(-1, 2))
        columns["highway"].append(np.asarray(part.edge_highway, dtype=np.int64)[part_edges])
        columns["width"].append(np.asarray(part.edge_width, dtype=np.float64)[part_edges])
        columns["lanes"].append(np.asarray(part.edge_lanes, dtype=np.int64)[part_edges])
        columns["oneway"].append(np.asarray(part.edge_oneway, dtype=np.int64)[part_edges])
        names = part.edge_names
        columns["names"].extend(names[i] for i in part_edges.tolist())
        offsets, points = _polylines(*part.edge_geometry(), part_edges)
        columns["offsets"].append(offsets[1:] + point_count if columns["offsets"] else offsets + point_count)
        columns["points"].append(points)
        point_count += len(points)
    joined = {name: np.concatenate(values) for name, values in columns.items() if name != "names"}
    return ggg.Graph.from_arrays(
        joined["positions"], joined["edges"], origin_latlon=tuple(graph.origin_latlon),
        vertex_symbols=joined["symbols"], vertex_frames=joined["frames"], edge_highway=joined["highway"],
        edge_width=joined["width"], edge_lanes=joined["lanes"], edge_oneway=joined["oneway"],
        edge_names=columns["names"], edge_geometry=(joined["offsets"], joined["points"]))


def induced_subgraph(ggg, graph, keep):
    """The part of the ggg.Graph ``graph`` on the vertices where ``keep`` is True and the
    edges between them, with all their columns, in ``graph``'s order: (subgraph, its
    vertices' ids in ``graph``, its edges' ids in ``graph``)."""
    keep = np.asarray(keep, dtype=bool)
    vertex_ids = np.flatnonzero(keep)
    edges = np.asarray(graph.edges, dtype=np.int64).reshape(-1, 2)
    edge_ids = np.flatnonzero(keep[edges[:, 0]] & keep[edges[:, 1]]) if len(edges) else np.zeros(0, np.int64)
    index = np.full(len(keep), -1, dtype=np.int64)
    index[vertex_ids] = np.arange(len(vertex_ids))
    return _assembled(ggg, graph, vertex_ids, edge_ids, index[edges[edge_ids]]), vertex_ids, edge_ids


def appended(ggg, graph, keep, grown, base_ids, base_edge_count):
    """``graph`` cut down to the vertices where ``keep`` is True (and the edges between
    them), followed by what ggg.grow_region added in ``grown``: the result of growing the
    subgraph of ``graph`` on the vertices ``base_ids`` (all kept), whose first
    ``base_edge_count`` edges were that subgraph's own.

    Returns (graph, source_vertex): for each vertex of the result, its id in ``graph``, -1
    for a grown one (what Replacement wants as the report's ``source_vertex``)."""
    keep = np.asarray(keep, dtype=bool)
    base_ids = np.asarray(base_ids, dtype=np.int64)
    kept_ids = np.flatnonzero(keep)
    index = np.full(len(keep), -1, dtype=np.int64)
    index[kept_ids] = np.arange(len(kept_ids))
    edges = np.asarray(graph.edges, dtype=np.int64).reshape(-1, 2)
    edge_ids = np.flatnonzero(keep[edges[:, 0]] & keep[edges[:, 1]]) if len(edges) else np.zeros(0, np.int64)
    grown_count = grown.vertex_count - len(base_ids)
    # A vertex of ``grown``: one of the base (``base_ids``), else a new one after the kept.
    grown_index = np.concatenate((index[base_ids], len(kept_ids) + np.arange(grown_count, dtype=np.int64)))
    grown_edges = np.asarray(grown.edges, dtype=np.int64).reshape(-1, 2)[base_edge_count:]
    result = _assembled(ggg, graph, kept_ids, edge_ids, index[edges[edge_ids]],
                        (grown, len(base_ids), base_edge_count, grown_index[grown_edges]))
    source = np.concatenate((kept_ids, np.full(grown_count, -1, dtype=np.int64)))
    return result, source


def _values(mesh, name, domain, dtype):
    """The values of the INT or FLOAT attribute ``name`` on ``domain``, else None."""
    attribute = mesh.attributes.get(name)
    if attribute is None or attribute.domain != domain or attribute.data_type not in ('INT', 'FLOAT'):
        return None
    return mesh_build.read_attribute(mesh, name, dtype)


def surface_polylines(graph_obj, positions, edges):
    """(offsets, points) of each graph edge's polyline in the surface (from the segments'
    `graph_edge` attribute), as Graph.edge_geometry() gives them: an edge without one is
    straight, and every polyline ends on its edge's vertices (which an edit may have
    moved). None without a surface."""
    surface_obj = importer.surface_object(graph_obj)
    if surface_obj is None or surface_obj.type != 'MESH':
        return None
    mesh = surface_obj.data
    attribute = mesh.attributes.get(SURFACE_EDGE)
    edge_count = len(edges)
    if attribute is None or attribute.domain != 'EDGE' or attribute.data_type != 'INT':
        offsets, points = np.zeros(edge_count + 1, dtype=np.int64), np.zeros((0, 2))
    else:
        owner = mesh_build.read_attribute(mesh, SURFACE_EDGE, np.int64)
        offsets, points = mesh_build.segment_polylines(mesh_build.positions_xy(mesh), mesh_build.edge_vertices(mesh),
                                                       owner, edge_count)
    offsets, points = mesh_build.complete_polylines(offsets, points, positions, edges)
    points = np.array(points, dtype=np.float64, copy=True)
    if edge_count:
        points[offsets[:-1]] = positions[edges[:, 0]]
        points[offsets[1:] - 1] = positions[edges[:, 1]]
    return offsets, points


def kept_edges(old_edges, source_vertex, new_edges):
    """For each edge of a derived graph, the edge of its input graph it is, else -1.

    ``source_vertex`` is the derivation's report entry (for each new vertex, the input vertex
    it is, -1 for a placed one). An edge is kept with both its vertices, in its direction,
    and a derivation never adds a second edge between two vertices: a new edge between two
    kept vertices that an input edge joins is that input edge (the first of them, as the
    derivation keeps only that one)."""
    old_edges = np.asarray(old_edges, dtype=np.int64).reshape(-1, 2)
    new_edges = np.asarray(new_edges, dtype=np.int64).reshape(-1, 2)
    source_vertex = np.asarray(source_vertex, dtype=np.int64)
    result = np.full(len(new_edges), -1, dtype=np.int64)
    if len(old_edges) == 0 or len(new_edges) == 0:
        return result
    n_old = int(old_edges.max()) + 1
    old_keys = old_edges.min(axis=1) * n_old + old_edges.max(axis=1)
    order = np.argsort(old_keys, kind="stable")
    sorted_keys = old_keys[order]
    u, v = source_vertex[new_edges[:, 0]], source_vertex[new_edges[:, 1]]
    both = (u >= 0) & (v >= 0) & (u < n_old) & (v < n_old)
    keys = np.where(both, np.minimum(u, v) * n_old + np.maximum(u, v), -1)
    where = np.clip(np.searchsorted(sorted_keys, keys), 0, len(sorted_keys) - 1)
    hit = both & (sorted_keys[where] == keys)
    result[hit] = order[where[hit]]
    return result


def _carried(values, source):
    """``values`` of the old elements for the new ones (``source``: old index or -1; zero
    for -1)."""
    out = np.zeros(len(source), dtype=values.dtype)
    kept = source >= 0
    out[kept] = values[source[kept]]
    return out


class Replacement:
    """The new contents of a road graph object (and its surface) from a derived graph,
    computed without touching Blender data; ``apply`` writes them.

    ``old`` is the MeshGraph the derivation started from, ``result`` and ``report`` what
    ggg.derive returned (of the report, only ``source_vertex`` is read: Grow into Region
    passes its own, see ``appended``), ``widths`` the road width of each edge of ``result``."""

    def __init__(self, graph_obj, old, result, report, widths):
        self.graph_obj = graph_obj
        self.positions = np.asarray(result.positions, dtype=np.float64)
        self.edges = np.asarray(result.edges, dtype=np.int64)
        vertex_source = np.asarray(report["source_vertex"], dtype=np.int64)
        edge_source = kept_edges(old.edges, vertex_source, self.edges)

        # The graph's own columns, as an import writes them.
        edge_attributes = importer.graph_edge_attributes(result, widths)
        for name, (refused, values) in old.refused.items():
            # Values the library does not take, set by hand, stay on their kept edges.
            back = _carried(refused, edge_source)
            column = np.array(edge_attributes[name][1], dtype=values.dtype, copy=True)
            column[back] = values[edge_source[back]]
            edge_attributes[name] = (edge_attributes[name][0], column)
        # What only Blender holds.
        for name, (kind, values) in old.edge_attributes.items():
            edge_attributes[name] = (kind, _carried(values, edge_source))
        self.edge_attributes = edge_attributes
        point_attributes = importer.vertex_attributes(result.vertex_symbols, result.vertex_frames)
        for name, (kind, values) in old.point_attributes.items():
            point_attributes[name] = (kind, _carried(values, vertex_source))
        self.point_attributes = point_attributes
        self.vertex_flags = {name: _carried(values, vertex_source) for name, values in old.vertex_flags.items()}
        self.edge_flags = {name: _carried(values, edge_source) for name, values in old.edge_flags.items()}

        # The arrows of the nonterminals (a graph grown into a region may have none).
        self.with_frames = bool(np.any(np.asarray(result.vertex_symbols)))
        self.surface_obj = importer.surface_object(graph_obj)
        self.offsets, self.points = result.edge_geometry()
        self.total_length_m = float(result.total_length_m)

    def apply(self, context):
        """Write the new graph into the object's mesh and rebuild its surface."""
        created = importer.Created()
        try:
            new_surface_mesh = None
            if self.surface_obj is not None:
                points, segments, attributes = importer.surface_geometry(
                    self.positions, self.edges, self.offsets, self.points, self.edge_attributes)
                new_surface_mesh = created.add(mesh_build.new_edge_mesh(
                    self.surface_obj.data.name, points, segments, attributes))
            if self.with_frames:
                importer.add_frames_modifier(self.graph_obj, created)
        except BaseException:
            created.remove_all()
            raise
        mesh = self.graph_obj.data
        mesh_build.fill_edge_mesh(mesh, self.positions, self.edges, self.edge_attributes, self.point_attributes)
        mesh_build.write_flags(mesh.vertices, self.vertex_flags)
        mesh_build.write_flags(mesh.edges, self.edge_flags)
        self.graph_obj["total_length_m"] = self.total_length_m
        if new_surface_mesh is not None:
            old_mesh = self.surface_obj.data
            name = old_mesh.name
            self.surface_obj.data = new_surface_mesh
            if old_mesh.users == 0:
                bpy.data.meshes.remove(old_mesh)
                new_surface_mesh.name = name


@contextlib.contextmanager
def object_mode(context, obj):
    """Leave Edit Mode for the duration (so that the mesh data of ``obj`` is current and
    can be replaced), then go back to it."""
    editing = obj.mode == 'EDIT' and context.mode == 'EDIT_MESH'
    if editing:
        bpy.ops.object.mode_set(mode='OBJECT')
    try:
        yield
    finally:
        if editing:
            bpy.ops.object.mode_set(mode='EDIT')


def add_nonterminal(graph_obj, position, symbol, frame_ab):
    """Append one nonterminal vertex at ``position`` (object-local x, y) to the graph mesh."""
    mesh = graph_obj.data
    n = len(mesh.vertices)
    for name, kind, default in ((SYMBOL, 'INT', 0), (FRAME_A, 'FLOAT', 1.0), (FRAME_B, 'FLOAT', 0.0)):
        attribute = mesh.attributes.get(name)
        if attribute is not None and (attribute.domain != 'POINT' or attribute.data_type != kind):
            mesh.attributes.remove(attribute)
            attribute = None
        if attribute is None:
            mesh_build.set_attribute(mesh, name, kind, 'POINT', np.full(n, default))
    mesh.vertices.add(1)
    mesh.vertices[n].co = (position[0], position[1], 0.0)
    mesh.attributes[SYMBOL].data[n].value = int(symbol)
    mesh.attributes[FRAME_A].data[n].value = float(frame_ab[0])
    mesh.attributes[FRAME_B].data[n].value = float(frame_ab[1])
    mesh.update()
    return n


# --- joining two road graphs (Stitch Cities) ------------------------------------------------

# Untagged values of the ranged columns, for a graph that lacks one of them.
_UNTAGGED = {name: (dtype, untagged) for name, (dtype, _accepted, untagged) in _RANGED_COLUMNS.items()}


def _stacked(first, second, n_first, n_second, dtype, fill):
    """``first`` and ``second`` one after the other; a missing one (None) as ``fill``."""
    if first is None and second is None:
        return None
    parts = [np.full(n, fill, dtype=dtype) if values is None else np.asarray(values, dtype=dtype)
             for values, n in ((first, n_first), (second, n_second))]
    return np.concatenate(parts)


def _stacked_attributes(first, second, n_first, n_second):
    """{name: (kind, values)} of two meshes' user attributes one after the other; an
    attribute of one only is zero on the other's elements, and one whose type differs
    between them takes the first's type."""
    joined = {}
    for name in list(first) + [name for name in second if name not in first]:
        kind, values = first.get(name, second.get(name))
        dtype = np.asarray(values).dtype
        a = first[name][1] if name in first else None
        b = second[name][1] if name in second else None
        joined[name] = (kind, _stacked(a, b, n_first, n_second, dtype, 0))
    return joined


def joined(ggg, first, second, matrix):
    """A MeshGraph of ``first``'s vertices and edges followed by ``second``'s (both
    MeshGraphs), ``second``'s brought into ``first``'s frame by the 4x4 ``matrix`` (seen from
    above: its x, y rows; the frames of its nonterminals turned and scaled by its linear
    part). Every column and attribute follows its vertex or edge; one that only one of them
    has is untagged (or zero) on the other's."""
    matrix = np.asarray(matrix, dtype=np.float64)
    linear, shift = matrix[:2, :2], matrix[:2, 3]
    n1, n2 = len(first.positions), len(second.positions)
    e1, e2 = len(first.edges), len(second.edges)
    out = MeshGraph.__new__(MeshGraph)
    moved = second.positions @ linear.T + shift
    out.positions = np.concatenate((first.positions, moved))
    out.edges = np.concatenate((first.edges, second.edges + n1)).reshape(-1, 2)
    out.symbols = np.concatenate((first.symbols, second.symbols))
    out.frame_missing = np.concatenate((first.frame_missing, second.frame_missing))
    ab = second.frames[:, :2] @ linear.T
    out.frames = np.column_stack((np.concatenate((first.frames[:, :2], ab)), out.positions))
    road = ggg.highway_classes().index("road") if "road" in ggg.highway_classes() else 0
    out.highway = _stacked(first.highway, second.highway, e1, e2, np.int64, road)
    out.columns, out.refused = {}, {}
    for name, (dtype, untagged) in _UNTAGGED.items():
        values = _stacked(first.columns.get(name), second.columns.get(name), e1, e2, dtype, untagged)
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
            geometry = mesh_build.complete_polylines(np.zeros(len(part.edges) + 1, dtype=np.int64), np.zeros((0, 2)),
                                                     part.positions, part.edges)
        part_offsets, part_points = (np.asarray(geometry[0], dtype=np.int64),
                                     np.asarray(geometry[1], dtype=np.float64).reshape(-1, 2))
        if shape is not None:
            part_points = part_points @ shape[0].T + shape[1]
        offsets.append(part_offsets if not offsets else part_offsets[1:] + len(points[0]))
        points.append(part_points)
    out.geometry = (np.concatenate(offsets), np.concatenate(points))
    out.edge_attributes = _stacked_attributes(first.edge_attributes, second.edge_attributes, e1, e2)
    out.point_attributes = _stacked_attributes(first.point_attributes, second.point_attributes, n1, n2)
    out.vertex_flags = {name: _stacked(first.vertex_flags.get(name), second.vertex_flags.get(name), n1, n2, bool,
                                       False) for name in first.vertex_flags}
    out.edge_flags = {name: _stacked(first.edge_flags.get(name), second.edge_flags.get(name), e1, e2, bool, False)
                      for name in first.edge_flags}
    out.origin_latlon = first.origin_latlon
    return out


def note_grammar(graph_obj, vertex, text_name):
    """Record on the nonterminal ``vertex`` of the graph mesh that it comes from the grammar
    Text ``text_name`` (the point attribute grammar.RULE_GRAMMAR: k > 0 for the k-th name of
    the object's list grammar.RULE_GRAMMARS_KEY)."""
    from . import grammar

    names = list(graph_obj.get(grammar.RULE_GRAMMARS_KEY, []))
    if text_name not in names:
        names.append(text_name)
        graph_obj[grammar.RULE_GRAMMARS_KEY] = names
    mesh = graph_obj.data
    attribute = mesh.attributes.get(grammar.RULE_GRAMMAR)
    if attribute is not None and (attribute.domain != 'POINT' or attribute.data_type != 'INT'):
        mesh.attributes.remove(attribute)
        attribute = None
    if attribute is None:
        mesh_build.set_attribute(mesh, grammar.RULE_GRAMMAR, 'INT', 'POINT', np.zeros(len(mesh.vertices)))
    mesh.attributes[grammar.RULE_GRAMMAR].data[vertex].value = names.index(text_name) + 1


def noted_grammars(graph_obj, old, default):
    """For each vertex of the MeshGraph ``old`` of ``graph_obj``, the name of the grammar
    Text its nonterminal comes from: the note of Place Rule, else ``default``."""
    from . import grammar

    names = list(graph_obj.get(grammar.RULE_GRAMMARS_KEY, []))
    noted = old.point_attributes.get(grammar.RULE_GRAMMAR)
    result = [default] * len(old.positions)
    if noted is not None:
        for vertex, k in enumerate(np.asarray(noted[1], dtype=np.int64).tolist()):
            if 1 <= k <= len(names):
                result[vertex] = names[k - 1]
    return result
