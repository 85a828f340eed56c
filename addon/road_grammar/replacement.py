"""The piece of street network that Replace (roads.replace_isogroup, paper Fig. 1) puts in
place of a pattern's occurrences, and where it is kept.

``scene.road_replacement`` (ROADS_PG_replacement) holds the stored piece, saved in the
.blend: ``piece``, a JSON text

    {"version": 1, "source": "grid (selection)",
     "positions": [[x, y], ...],              # metres, in the frame of the road graph it came from
     "edges": [[i, j], ...],                  # indices into positions
     "highway": ["residential", ...]}         # the road class of each edge (ggg.highway_classes())

and what the panel shows of it (its counts and size), and the **Piece Object** picker. The
piece is drawn at any size and place: ggg.replace_isogroup centres it on the pattern and
scales it to the pattern's size, keeping its orientation in the graph's frame.

A piece comes from the vertices selected in a road graph (and the streets between them), or
from another mesh or curve object (all its vertices and edges, in world space brought into
the road graph's frame; its ``highway`` INT edge attribute, when it has one, gives the road
classes).
"""

import json

import bpy
import numpy as np
from bpy.props import FloatProperty, IntProperty, PointerProperty, StringProperty
from bpy.types import PropertyGroup

from . import importer, mesh_build, pattern_display, rule_display
from .analysis import MeshTopology

VERSION = 1
DEFAULT_CLASS = "residential"  # ggg.replace_isogroup's class of an edge without one
PIECE_TYPES = {'MESH', 'CURVE'}


class PieceError(Exception):
    """No piece, or one that cannot be used; the message says why."""


class Piece:
    """A replacement piece: positions (N, 2) float64 in metres, edges (M, 2) int64 and the
    road class name of each edge."""

    def __init__(self, positions, edges, highway, source=""):
        self.positions = np.asarray(positions, dtype=np.float64).reshape(-1, 2)
        self.edges = np.asarray(edges, dtype=np.int64).reshape(-1, 2)
        self.highway = [str(name) for name in highway]
        self.source = str(source)
        if len(self.highway) != len(self.edges):
            raise PieceError("The piece has {} road classes for {} streets".format(len(self.highway),
                                                                                   len(self.edges)))

    @property
    def vertex_count(self):
        return len(self.positions)

    @property
    def edge_count(self):
        return len(self.edges)

    def size(self):
        """(width, height) in metres of the piece's bounding box."""
        if len(self.positions) == 0:
            return 0.0, 0.0
        extent = self.positions.max(axis=0) - self.positions.min(axis=0)
        return float(extent[0]), float(extent[1])

    def problem(self):
        """Why the piece cannot replace a pattern (no vertices, no streets, not finite, no
        extent), else None. Indices out of range are left to the library, which says so."""
        if self.vertex_count == 0:
            return "The piece has no vertices"
        if self.edge_count == 0:
            return "The piece has no streets (edges): a piece needs streets to join the streets around it"
        if not np.all(np.isfinite(self.positions)):
            return "The piece has vertices that are not finite"
        if max(self.size()) <= 0.0:
            return "The piece's {} vertices are all at one place: it has no size".format(self.vertex_count)
        return None

    def highway_codes(self, ggg):
        """The class code of each edge for ggg.replace_isogroup; raises PieceError for a
        name the library does not know."""
        codes = {name: code for code, name in enumerate(ggg.highway_classes())}
        unknown = sorted({name for name in self.highway if name not in codes})
        if unknown:
            raise PieceError("The piece has road classes the library does not know: {}".format(", ".join(unknown)))
        return np.array([codes[name] for name in self.highway], dtype=np.int64)

    def to_json(self):
        return json.dumps({"version": VERSION, "source": self.source, "positions": self.positions.tolist(),
                           "edges": self.edges.tolist(), "highway": self.highway})

    @classmethod
    def from_json(cls, text):
        try:
            data = json.loads(text)
            positions = np.asarray(data["positions"], dtype=np.float64)
            edges = np.asarray(data["edges"], dtype=np.int64)
            highway = data.get("highway")
            if highway is None:
                highway = [DEFAULT_CLASS] * len(edges)
            if positions.size and (positions.ndim != 2 or positions.shape[1] != 2):
                raise ValueError("positions must be [x, y] pairs")
            if edges.size and (edges.ndim != 2 or edges.shape[1] != 2):
                raise ValueError("edges must be [i, j] pairs")
            if not isinstance(highway, list):
                raise ValueError("highway must be a list of class names")
            return cls(positions, edges, highway, data.get("source", ""))
        except (ValueError, TypeError, KeyError, AttributeError) as ex:
            raise PieceError("The stored piece cannot be read ({}: {}); store a piece again".format(
                type(ex).__name__, ex)) from ex


def _class_names(ggg, codes, count):
    """Class names of ``count`` edges from INT codes (None: the default class), clipped to
    the library's classes as a road graph's are (analysis.MeshTopology.graph)."""
    if codes is None:
        return [DEFAULT_CLASS] * count
    names = list(ggg.highway_classes())
    return [names[code] for code in np.clip(np.asarray(codes, dtype=np.int64), 0, len(names) - 1).tolist()]


def from_selection(ggg, graph_obj):
    """The vertices selected in the road graph ``graph_obj`` (Edit Mode: the edit mesh's
    selection; Object Mode: the stored one) and the streets between them, in the graph's
    metres. Raises PieceError."""
    topology = MeshTopology(graph_obj, with_classes=True)
    chosen = topology.selected_ids()
    if len(chosen) == 0:
        raise PieceError("Nothing is selected in {}: select the vertices of the piece in Edit Mode (the streets "
                         "between them come with them), or store another object as the piece".format(graph_obj.name))
    edges = np.asarray(topology.edges, dtype=np.int64).reshape(-1, 2)
    mask = np.zeros(topology.vertex_count, dtype=bool)
    mask[chosen] = True
    inside = np.flatnonzero(mask[edges[:, 0]] & mask[edges[:, 1]]) if len(edges) else np.zeros(0, dtype=np.int64)
    if len(inside) == 0:
        raise PieceError("No street joins the {} selected vertices of {}: a piece needs streets".format(
            len(chosen), graph_obj.name))
    index = np.full(topology.vertex_count, -1, dtype=np.int64)
    index[chosen] = np.arange(len(chosen))
    highway = None if topology.highway is None else topology.highway[inside]
    return Piece(topology.positions[chosen], index[edges[inside]], _class_names(ggg, highway, len(inside)),
                 "{} (selection)".format(graph_obj.name))


def from_object(ggg, piece_obj, graph_obj, depsgraph):
    """All the vertices and edges of the mesh or curve ``piece_obj`` (as evaluated, in world
    space) in the local frame of the road graph ``graph_obj`` (x, y; heights dropped).
    Raises PieceError."""
    if piece_obj is None:
        raise PieceError("No piece object")
    if piece_obj.type not in PIECE_TYPES:
        raise PieceError("{} is not a mesh or a curve (its type is {}): a piece is drawn as a mesh or a curve".format(
            piece_obj.name, piece_obj.type.lower()))
    if piece_obj == graph_obj:
        raise PieceError("{} is the road graph itself: select the vertices of the piece in Edit Mode instead, or "
                         "pick another object".format(piece_obj.name))
    evaluated = piece_obj.evaluated_get(depsgraph)
    mesh = evaluated.to_mesh()
    try:
        if mesh is None or len(mesh.vertices) == 0:
            raise PieceError("{} has no vertices".format(piece_obj.name))
        co = np.empty(len(mesh.vertices) * 3, dtype=np.float64)
        mesh.vertices.foreach_get("co", co)
        edges = mesh_build.edge_vertices(mesh)
        codes = None
        attribute = mesh.attributes.get("highway")
        if attribute is not None and attribute.domain == 'EDGE' and attribute.data_type == 'INT':
            codes = mesh_build.read_attribute(mesh, "highway", np.int64)
        matrix = np.array(graph_obj.matrix_world.inverted() @ evaluated.matrix_world, dtype=np.float64)
    finally:
        evaluated.to_mesh_clear()
    if len(edges) == 0:
        raise PieceError("{} has no edges: a piece needs streets (draw them as edges, e.g. a circle or a grid "
                         "without faces)".format(piece_obj.name))
    co = co.reshape(-1, 3)
    local = co @ matrix[:3, :3].T + matrix[:3, 3]
    return Piece(local[:, :2], edges, _class_names(ggg, codes, len(edges)), piece_obj.name)


# --- where the piece is kept --------------------------------------------------------------

def _piece_object_poll(_self, obj):
    """The Piece Object picker lists meshes and curves that are not a road graph's surface or
    display."""
    if obj.type not in PIECE_TYPES:
        return False
    if obj.get(importer.SURFACE_KEY) or obj.get(pattern_display.OBJECT_KEY) or obj.get(rule_display.OBJECT_KEY):
        return False
    return True


class ROADS_PG_replacement(PropertyGroup):
    """The stored replacement piece of Replace (Roads sidebar > Patterns > Replace)."""

    piece: StringProperty(name="Piece", description="The stored piece as JSON: positions (metres in the road "
                          "graph's frame), edges and their road classes")
    vertex_count: IntProperty(name="Vertices", description="Vertices of the stored piece")
    edge_count: IntProperty(name="Streets", description="Streets (edges) of the stored piece")
    width_m: FloatProperty(name="Width", description="Width of the stored piece as drawn", unit='LENGTH')
    height_m: FloatProperty(name="Height", description="Height (north-south extent) of the stored piece as drawn",
                            unit='LENGTH')
    source: StringProperty(name="Source", description="Where the stored piece came from")
    piece_object: PointerProperty(
        name="Piece Object", type=bpy.types.Object, poll=_piece_object_poll,
        description="Mesh or curve whose vertices and edges Store Object as Piece keeps as the piece")

    def has_piece(self):
        return bool(self.piece)


def keep(scene, piece):
    """Store ``piece`` in ``scene.road_replacement``, replacing the one there."""
    settings = scene.road_replacement
    width, height = piece.size()
    settings.piece = piece.to_json()
    settings.vertex_count = piece.vertex_count
    settings.edge_count = piece.edge_count
    settings.width_m, settings.height_m = width, height
    settings.source = piece.source


def stored(scene):
    """The Piece stored in ``scene``; raises PieceError when there is none or it cannot be
    read."""
    settings = scene.road_replacement
    if not settings.has_piece():
        raise PieceError("No piece is stored: select the vertices of a piece in Edit Mode and press Store Selection "
                         "as Piece (or store an object as the piece)")
    return Piece.from_json(settings.piece)


def register():
    bpy.types.Scene.road_replacement = PointerProperty(type=ROADS_PG_replacement)


def unregister():
    del bpy.types.Scene.road_replacement
