"""A road graph object <-> ggg.Graph, for the grammar operators.

``MeshGraph`` reads the object's mesh, and the edge polylines of its surface, into the
columns of ggg.Graph.from_arrays; ``Replacement`` puts a derived graph back into the same
mesh datablock and rebuilds the surface from the graph's own columns, as an import does
(display.road_objects.rewrite writes it, with the Rule Frames modifier when it has
nonterminals). Everything is computed before the first change, so an error leaves the
object as it was.
(Cutting a ggg.Graph down to some of its vertices, adding what ggg.grow_region grew and
joining two graphs' columns: core.columns.)

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

from ..core.columns import (GRAPH_EDGE_ATTRIBUTES, GRAPH_POINT_ATTRIBUTES, RANGED_COLUMNS, GraphColumns,
                            more_rewrites_from_slots)
from ..core.names import (FRAME_A, FRAME_B, NAME, RULE_GRAMMAR, RULE_GRAMMARS_KEY, SURFACE_EDGE, SYMBOL,
                          is_more_rewrite_name, more_rewrite_names)
from ..core.polylines import complete_polylines, segment_polylines
from ..core.topology import carried, kept_edges
from . import mesh as mesh_data
from . import roads


class MeshGraph(GraphColumns):
    """The columns of a road graph object's mesh (and its surface's polylines), as
    ggg.Graph.from_arrays wants them (core.columns.GraphColumns)."""

    def __init__(self, obj):
        mesh = obj.data
        self.positions = mesh_data.positions_xy(mesh)
        self.edges = mesh_data.edge_vertices(mesh)
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
        self.more_rewrites = more_rewrites_from_slots(_slots(mesh), self.positions, self.symbols)
        self.highway = _values(mesh, "highway", 'EDGE', np.int64)
        # Ranged columns: (values for the library, the mesh's values where it refuses them).
        self.columns, self.refused = {}, {}
        for name, (dtype, accepted, untagged) in RANGED_COLUMNS.items():
            values = _values(mesh, name, 'EDGE', dtype)
            if values is None:
                continue
            refused = ~accepted(values)
            self.columns[name] = np.where(refused, untagged, values)
            if refused.any():
                self.refused[name] = (refused, values)
        self.names = mesh_data.read_strings(mesh, NAME, 'EDGE')
        self.geometry = surface_polylines(obj, self.positions, self.edges)
        self.edge_attributes = {name: value for name, value in mesh_data.user_attributes(mesh, 'EDGE').items()
                                if name not in GRAPH_EDGE_ATTRIBUTES}
        self.point_attributes = {name: value for name, value in mesh_data.user_attributes(mesh, 'POINT').items()
                                 if name not in GRAPH_POINT_ATTRIBUTES and not is_more_rewrite_name(name)}
        self.vertex_flags = mesh_data.read_flags(mesh.vertices)
        self.edge_flags = mesh_data.read_flags(mesh.edges)
        lat = float(obj.get("origin_lat", 0.0))
        lon = float(obj.get("origin_lon", 0.0))
        self.origin_latlon = (lat, lon)


def _values(mesh, name, domain, dtype):
    """The values of the INT or FLOAT attribute ``name`` on ``domain``, else None."""
    attribute = mesh.attributes.get(name)
    if attribute is None or attribute.domain != domain or attribute.data_type not in ('INT', 'FLOAT'):
        return None
    return mesh_data.read_attribute(mesh, name, dtype)


def _slots(mesh):
    """The slots of further rewrites the mesh has (core.names.more_rewrite_names), in order,
    as (symbols, a, b); the first slot missing ends them."""
    slots = []
    for slot in range(2, 2 + len(mesh.vertices) + 1):
        columns = [_values(mesh, name, 'POINT', dtype)
                   for name, dtype in zip(more_rewrite_names(slot), (np.int64, np.float64, np.float64))]
        if any(column is None for column in columns):
            break
        slots.append(tuple(columns))
    return slots


def surface_polylines(graph_obj, positions, edges):
    """(offsets, points) of each graph edge's polyline in the surface (from the segments'
    `graph_edge` attribute), as Graph.edge_geometry() gives them: an edge without one is
    straight, and every polyline ends on its edge's vertices (which an edit may have
    moved). None without a surface."""
    surface_obj = roads.surface_object(graph_obj)
    if surface_obj is None or surface_obj.type != 'MESH':
        return None
    mesh = surface_obj.data
    attribute = mesh.attributes.get(SURFACE_EDGE)
    edge_count = len(edges)
    if attribute is None or attribute.domain != 'EDGE' or attribute.data_type != 'INT':
        offsets, points = np.zeros(edge_count + 1, dtype=np.int64), np.zeros((0, 2))
    else:
        owner = mesh_data.read_attribute(mesh, SURFACE_EDGE, np.int64)
        offsets, points = segment_polylines(mesh_data.positions_xy(mesh), mesh_data.edge_vertices(mesh), owner,
                                            edge_count)
    offsets, points = complete_polylines(offsets, points, positions, edges)
    points = np.array(points, dtype=np.float64, copy=True)
    if edge_count:
        points[offsets[:-1]] = positions[edges[:, 0]]
        points[offsets[1:] - 1] = positions[edges[:, 1]]
    return offsets, points


class Replacement:
    """The new contents of a road graph object (and its surface) from a derived graph,
    computed without touching Blender data; ``new_surface_mesh`` and ``apply`` write them
    (display.road_objects.rewrite calls both).

    ``old`` is the MeshGraph the derivation started from, ``result`` and ``report`` what
    ggg.derive returned (of the report, only ``source_vertex`` is read: Grow into Region
    passes its own, see core.columns.appended), ``widths`` the road width of each edge of ``result``."""

    def __init__(self, graph_obj, old, result, report, widths):
        self.graph_obj = graph_obj
        self.positions = np.asarray(result.positions, dtype=np.float64)
        self.edges = np.asarray(result.edges, dtype=np.int64)
        vertex_source = np.asarray(report["source_vertex"], dtype=np.int64)
        edge_source = kept_edges(old.edges, vertex_source, self.edges)

        # The graph's own columns, as an import writes them.
        edge_attributes = roads.graph_edge_attributes(result, widths)
        for name, (refused, values) in old.refused.items():
            # Values the library does not take, set by hand, stay on their kept edges.
            back = carried(refused, edge_source)
            column = np.array(edge_attributes[name][1], dtype=values.dtype, copy=True)
            column[back] = values[edge_source[back]]
            edge_attributes[name] = (edge_attributes[name][0], column)
        # What only Blender holds.
        for name, (kind, values) in old.edge_attributes.items():
            edge_attributes[name] = (kind, carried(values, edge_source))
        self.edge_attributes = edge_attributes
        point_attributes = roads.vertex_attributes(result.vertex_symbols, result.vertex_frames, result.more_rewrites)
        for name, (kind, values) in old.point_attributes.items():
            point_attributes[name] = (kind, carried(values, vertex_source))
        self.point_attributes = point_attributes
        self.vertex_flags = {name: carried(values, vertex_source) for name, values in old.vertex_flags.items()}
        self.edge_flags = {name: carried(values, edge_source) for name, values in old.edge_flags.items()}

        # The arrows of the nonterminals (a graph grown into a region may have none).
        self.with_frames = bool(np.any(np.asarray(result.vertex_symbols)))
        self.surface_obj = roads.surface_object(graph_obj)
        self.offsets, self.points = result.edge_geometry()
        self.total_length_m = float(result.total_length_m)

    def new_surface_mesh(self, created):
        """The mesh of the rebuilt surface (remembered in ``created``, a roads.Created), else
        None when the object has no surface. Nothing else changes."""
        if self.surface_obj is None:
            return None
        points, segments, attributes = roads.surface_geometry(
            self.positions, self.edges, self.offsets, self.points, self.edge_attributes)
        return created.add(mesh_data.new_edge_mesh(self.surface_obj.data.name, points, segments, attributes))

    def apply(self, surface_mesh):
        """Write the new graph into the object's mesh and give its surface ``surface_mesh``
        (from ``new_surface_mesh``, made before anything changes, as is what draws the
        nonterminals when ``with_frames``)."""
        mesh = self.graph_obj.data
        mesh_data.fill_edge_mesh(mesh, self.positions, self.edges, self.edge_attributes, self.point_attributes)
        mesh_data.write_flags(mesh.vertices, self.vertex_flags)
        mesh_data.write_flags(mesh.edges, self.edge_flags)
        self.graph_obj["total_length_m"] = self.total_length_m
        if surface_mesh is not None:
            old_mesh = self.surface_obj.data
            name = old_mesh.name
            self.surface_obj.data = surface_mesh
            if old_mesh.users == 0:
                bpy.data.meshes.remove(old_mesh)
                surface_mesh.name = name


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
            mesh_data.set_attribute(mesh, name, kind, 'POINT', np.full(n, default))
    mesh.vertices.add(1)
    mesh.vertices[n].co = (position[0], position[1], 0.0)
    mesh.attributes[SYMBOL].data[n].value = int(symbol)
    mesh.attributes[FRAME_A].data[n].value = float(frame_ab[0])
    mesh.attributes[FRAME_B].data[n].value = float(frame_ab[1])
    mesh.update()
    return n


def note_grammar(graph_obj, vertex, text_name):
    """Record on the nonterminal ``vertex`` of the graph mesh that it comes from the grammar
    Text ``text_name`` (the point attribute RULE_GRAMMAR: k > 0 for the k-th name of
    the object's list RULE_GRAMMARS_KEY)."""
    names = list(graph_obj.get(RULE_GRAMMARS_KEY, []))
    if text_name not in names:
        names.append(text_name)
        graph_obj[RULE_GRAMMARS_KEY] = names
    mesh = graph_obj.data
    attribute = mesh.attributes.get(RULE_GRAMMAR)
    if attribute is not None and (attribute.domain != 'POINT' or attribute.data_type != 'INT'):
        mesh.attributes.remove(attribute)
        attribute = None
    if attribute is None:
        mesh_data.set_attribute(mesh, RULE_GRAMMAR, 'INT', 'POINT', np.zeros(len(mesh.vertices)))
    mesh.attributes[RULE_GRAMMAR].data[vertex].value = names.index(text_name) + 1


def noted_grammars(graph_obj, old, default):
    """For each vertex of the MeshGraph ``old`` of ``graph_obj``, the name of the grammar
    Text its nonterminal comes from: the note of Place Rule, else ``default``."""
    names = list(graph_obj.get(RULE_GRAMMARS_KEY, []))
    noted = old.point_attributes.get(RULE_GRAMMAR)
    result = [default] * len(old.positions)
    if noted is not None:
        for vertex, k in enumerate(np.asarray(noted[1], dtype=np.int64).tolist()):
            if 1 <= k <= len(names):
                result[vertex] = names[k - 1]
    return result
