"""The piece of street network that Replace (roads.replace_isogroup, paper Fig. 1) puts in
place of a pattern's occurrences (core.piece), and where it is kept.

``scene.road_replacement`` (properties.replacement.ROADS_PG_replacement) holds the stored
piece, saved in the .blend: ``piece``, its JSON text, and what the panel shows of it (its
counts and size), and the **Piece Object** picker.

A piece comes from the vertices selected in a road graph (and the streets between them), or
from another mesh or curve object (all its vertices and edges, in world space brought into
the road graph's frame; its ``highway`` INT edge attribute, when it has one, gives the road
classes).
"""

import numpy as np

from ..core.piece import Piece, PieceError, class_names
from . import mesh as mesh_data
from .analysis import MeshTopology

PIECE_TYPES = {'MESH', 'CURVE'}


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
    return Piece(topology.positions[chosen], index[edges[inside]], class_names(ggg, highway, len(inside)),
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
        edges = mesh_data.edge_vertices(mesh)
        codes = None
        attribute = mesh.attributes.get("highway")
        if attribute is not None and attribute.domain == 'EDGE' and attribute.data_type == 'INT':
            codes = mesh_data.read_attribute(mesh, "highway", np.int64)
        matrix = np.array(graph_obj.matrix_world.inverted() @ evaluated.matrix_world, dtype=np.float64)
    finally:
        evaluated.to_mesh_clear()
    if len(edges) == 0:
        raise PieceError("{} has no edges: a piece needs streets (draw them as edges, e.g. a circle or a grid "
                         "without faces)".format(piece_obj.name))
    co = co.reshape(-1, 3)
    local = co @ matrix[:3, :3].T + matrix[:3, 3]
    return Piece(local[:, :2], edges, class_names(ggg, codes, len(edges)), piece_obj.name)


# --- where the piece is kept --------------------------------------------------------------

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
