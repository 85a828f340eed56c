"""A road graph object <-> ggg.Graph, for the grammar operators.

``read`` turns the object's mesh into a ggg.Graph (positions, edges, highway codes, the
nonterminals' symbols and frames); ``replace`` puts a derived graph back into the same
mesh datablock and rebuilds the surface. Everything is computed before the first change,
so an error leaves the object as it was.

A derived graph keeps every vertex and edge of its input that was not rewritten, with
positions copied exactly. ggg.derive does not say which output vertex was which input
vertex, so ``replace`` finds the kept ones by their exact position; a kept edge keeps its
edge attributes (width, lanes, oneway, user attributes) and its polyline in the surface.
New edges get the default width of their class (add-on preferences) and a straight surface.
"""

import contextlib

import bpy
import numpy as np

from . import importer, mesh_build, preferences
from .importer import FRAME_A, FRAME_B, SURFACE_EDGE, SYMBOL

# Point attributes that the graph carries itself (not copied from the old mesh).
_GRAPH_POINT_ATTRIBUTES = (SYMBOL, FRAME_A, FRAME_B)
# Edge attributes that the graph carries itself.
_GRAPH_EDGE_ATTRIBUTES = ("highway", "rank")


class MeshGraph:
    """The arrays of a road graph object's mesh, as ggg.Graph.from_arrays wants them."""

    def __init__(self, obj):
        mesh = obj.data
        self.positions = mesh_build.positions_xy(mesh)
        self.edges = mesh_build.edge_vertices(mesh)
        n = len(self.positions)
        self.symbols = _point_values(mesh, SYMBOL, np.int64, 0, n)
        self.symbols = np.where(self.symbols < 0, 0, self.symbols)
        a = _point_values(mesh, FRAME_A, np.float64, 1.0, n)
        b = _point_values(mesh, FRAME_B, np.float64, 0.0, n)
        # A frame without scale (e.g. a vertex added by hand) becomes the unit frame.
        degenerate = ~(np.isfinite(a) & np.isfinite(b)) | (np.hypot(a, b) == 0.0)
        a, b = np.where(degenerate, 1.0, a), np.where(degenerate, 0.0, b)
        self.frames = np.column_stack((a, b, self.positions))
        self.highway = None
        if "highway" in mesh.attributes and mesh.attributes["highway"].domain == 'EDGE':
            self.highway = mesh_build.read_attribute(mesh, "highway", np.int64)
        self.edge_attributes = mesh_build.user_attributes(mesh, 'EDGE')
        self.point_attributes = {name: value for name, value in mesh_build.user_attributes(mesh, 'POINT').items()
                                 if name not in _GRAPH_POINT_ATTRIBUTES}
        lat = float(obj.get("origin_lat", 0.0))
        lon = float(obj.get("origin_lon", 0.0))
        self.origin_latlon = (lat, lon)

    @property
    def nonterminal_count(self):
        return int(np.count_nonzero(self.symbols))

    def graph(self, ggg):
        """The ggg.Graph of these arrays (raises ggg.Error for a graph it refuses)."""
        highway = None
        if self.highway is not None:
            classes = len(ggg.highway_classes())
            highway = np.clip(self.highway, 0, classes - 1)
        return ggg.Graph.from_arrays(self.positions, self.edges, origin_latlon=self.origin_latlon,
                                     vertex_symbols=self.symbols, vertex_frames=self.frames,
                                     edge_highway=highway)


def _point_values(mesh, name, dtype, default, count):
    attribute = mesh.attributes.get(name)
    if attribute is None or attribute.domain != 'POINT' or attribute.data_type not in ('INT', 'FLOAT'):
        return np.full(count, default, dtype=dtype)
    return mesh_build.read_attribute(mesh, name, dtype)


def _position_keys(positions):
    return np.ascontiguousarray(positions, dtype=np.float64).view(np.dtype((np.void, 16))).ravel()


def kept_vertices(old_positions, old_stable, new_positions):
    """For each new vertex, the old vertex at exactly the same position, else -1.

    Only old vertices in ``old_stable`` (bool mask: those the derivation cannot have
    erased) with a position no other such vertex shares are matched, each to the first
    new vertex there (kept vertices come before placed ones in a derived graph)."""
    result = np.full(len(new_positions), -1, dtype=np.int64)
    candidates = np.flatnonzero(old_stable)
    if len(candidates) == 0 or len(new_positions) == 0:
        return result
    keys = _position_keys(old_positions[candidates])
    order = np.argsort(keys, kind="stable")
    keys, candidates = keys[order], candidates[order]
    unique = np.ones(len(keys), dtype=bool)
    same = keys[1:] == keys[:-1]
    unique[1:] &= ~same
    unique[:-1] &= ~same
    keys, candidates = keys[unique], candidates[unique]
    if len(keys) == 0:
        return result
    new_keys = _position_keys(new_positions)
    where = np.clip(np.searchsorted(keys, new_keys), 0, len(keys) - 1)
    hit = keys[where] == new_keys
    hits = np.flatnonzero(hit)
    matched = candidates[where[hits]]
    # The first new vertex per old vertex only.
    _, first = np.unique(matched, return_index=True)
    result[hits[first]] = matched[first]
    return result


def kept_edges(old_edges, vertex_map, new_edges):
    """For each new edge, (old edge index or -1, True where it runs the other way)."""
    new_edges = np.asarray(new_edges, dtype=np.int64).reshape(-1, 2)
    result = np.full(len(new_edges), -1, dtype=np.int64)
    flipped = np.zeros(len(new_edges), dtype=bool)
    if len(old_edges) == 0 or len(new_edges) == 0:
        return result, flipped
    n_old = int(old_edges.max()) + 1
    old_lo, old_hi = old_edges.min(axis=1), old_edges.max(axis=1)
    old_keys = old_lo * n_old + old_hi
    order = np.argsort(old_keys, kind="stable")
    sorted_keys = old_keys[order]
    u, v = vertex_map[new_edges[:, 0]], vertex_map[new_edges[:, 1]]
    both = (u >= 0) & (v >= 0) & (u < n_old) & (v < n_old)
    lo, hi = np.minimum(u, v), np.maximum(u, v)
    keys = np.where(both, lo * n_old + hi, -1)
    where = np.clip(np.searchsorted(sorted_keys, keys), 0, len(sorted_keys) - 1)
    hit = both & (sorted_keys[where] == keys)
    result[hit] = order[where[hit]]
    flipped[hit] = old_edges[result[hit], 0] != u[hit]
    return result, flipped


def old_polylines(graph_obj, edge_count):
    """(offsets, points) of the old surface's polyline per graph edge (empty: straight),
    from the surface segments' `graph_edge` attribute; None without a surface."""
    surface_obj = importer.surface_object(graph_obj)
    if surface_obj is None or surface_obj.type != 'MESH':
        return None
    mesh = surface_obj.data
    attribute = mesh.attributes.get(SURFACE_EDGE)
    if attribute is None or attribute.domain != 'EDGE':
        return np.zeros(edge_count + 1, dtype=np.int64), np.zeros((0, 2))
    owner = mesh_build.read_attribute(mesh, SURFACE_EDGE, np.int64)
    return mesh_build.segment_polylines(mesh_build.positions_xy(mesh), mesh_build.edge_vertices(mesh), owner,
                                        edge_count)


def new_polylines(old_lines, edge_map, flipped, positions, edges):
    """(offsets, points) for the new edges: a kept edge keeps its old polyline (reversed
    when it runs the other way, ends on its vertices), a new edge is straight."""
    m = len(edges)
    counts = np.zeros(m, dtype=np.int64)
    if old_lines is None:
        return np.zeros(m + 1, dtype=np.int64), np.zeros((0, 2))
    old_offsets, old_points = old_lines
    kept = edge_map >= 0
    old_counts = np.diff(old_offsets)
    counts[kept] = old_counts[edge_map[kept]]
    offsets = np.zeros(m + 1, dtype=np.int64)
    np.cumsum(counts, out=offsets[1:])
    points = np.empty((offsets[-1], 2), dtype=np.float64)
    ramp = mesh_build._ramp(counts)
    owners = np.repeat(np.arange(m), counts)
    within = np.where(flipped[owners], counts[owners] - 1 - ramp, ramp)
    if len(owners):
        points[:] = old_points[old_offsets[edge_map[owners]] + within]
    # The ends are the vertices (which an edit may have moved).
    has = counts >= 2
    points[offsets[:-1][has]] = positions[edges[has, 0]]
    points[offsets[1:][has] - 1] = positions[edges[has, 1]]
    return offsets, points


def _polyline_length(offsets, points, positions, edges):
    pts, segments, _ = mesh_build.polyline_segments(offsets, points, positions, edges)
    if len(segments) == 0:
        return 0.0
    return float(np.linalg.norm(pts[segments[:, 1]] - pts[segments[:, 0]], axis=1).sum())


class Replacement:
    """The new contents of a road graph object (and its surface), computed without
    touching Blender data; ``apply`` writes them."""

    def __init__(self, context, graph_obj, old, result, ggg, grammar_symbols=()):
        self.graph_obj = graph_obj
        positions = np.asarray(result.positions, dtype=np.float64)
        edges = np.asarray(result.edges, dtype=np.int64)
        highway = np.asarray(result.edge_highway, dtype=np.int64)
        self.positions, self.edges = positions, edges

        # What was kept: terminals and nonterminals that have no rule are never erased.
        stable = ~np.isin(old.symbols, np.asarray(list(grammar_symbols), dtype=np.int64))
        vertex_map = kept_vertices(old.positions, stable, positions)
        edge_map, flipped = kept_edges(old.edges, vertex_map, edges)
        kept = edge_map >= 0
        self.kept_edges = int(np.count_nonzero(kept))

        prefs = preferences.get(context)
        class_widths = np.asarray(preferences.class_width_table(prefs, ggg), dtype=np.float64)
        ranks = np.asarray(ggg.highway_ranks(), dtype=np.int64)
        safe_highway = np.clip(highway, 0, len(class_widths) - 1)

        # Edge attributes: kept edges keep theirs, new edges get their class's defaults.
        edge_attributes = {
            "highway": ('INT', highway),
            "rank": ('INT', ranks[np.clip(highway, 0, len(ranks) - 1)]),
        }
        defaults = {
            "width": ('FLOAT', class_widths[safe_highway]),
            "lanes": ('INT', np.zeros(len(edges), dtype=np.int64)),
            "oneway": ('INT', np.zeros(len(edges), dtype=np.int64)),
        }
        for name, (kind, values) in old.edge_attributes.items():
            if name in _GRAPH_EDGE_ATTRIBUTES:
                continue
            default_kind, default_values = defaults.get(name, (kind, None))
            if default_values is None or default_kind != kind:
                default_values = np.zeros(len(edges), dtype=values.dtype)
            new_values = np.array(default_values, dtype=values.dtype, copy=True)
            new_values[kept] = values[edge_map[kept]]
            if name == "oneway":
                new_values[kept & flipped] = -new_values[kept & flipped]
            edge_attributes[name] = (kind, new_values)
        for name, value in defaults.items():
            edge_attributes.setdefault(name, value)
        self.edge_attributes = edge_attributes

        # Point attributes: the graph's nonterminals and frames; user attributes carried.
        point_attributes = importer.vertex_attributes(result.vertex_symbols, result.vertex_frames)
        kept_points = vertex_map >= 0
        for name, (kind, values) in old.point_attributes.items():
            new_values = np.zeros(len(positions), dtype=values.dtype)
            new_values[kept_points] = values[vertex_map[kept_points]]
            point_attributes[name] = (kind, new_values)
        self.point_attributes = point_attributes

        # The surface: kept polylines, straight new edges.
        old_lines = old_polylines(graph_obj, len(old.edges))
        self.offsets, self.points = new_polylines(old_lines, edge_map, flipped, positions, edges)
        self.total_length_m = _polyline_length(self.offsets, self.points, positions, edges)
        self.surface_obj = importer.surface_object(graph_obj)

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
            importer.add_frames_modifier(self.graph_obj, created)
        except BaseException:
            created.remove_all()
            raise
        mesh_build.fill_edge_mesh(self.graph_obj.data, self.positions, self.edges, self.edge_attributes,
                                  self.point_attributes)
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
