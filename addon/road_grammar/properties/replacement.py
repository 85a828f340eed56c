"""The stored replacement piece of Replace (``scene.road_replacement``, the piece of Store
as Piece)."""

import bpy
from bpy.props import FloatProperty, IntProperty, PointerProperty, StringProperty
from bpy.types import PropertyGroup

from ..core.names import PATTERNS_KEY, RULES_KEY, SURFACE_KEY
from ..data.replacement import PIECE_TYPES


def _piece_object_poll(_self, obj):
    """The Piece Object picker lists meshes and curves that are not a road graph's surface or
    display."""
    if obj.type not in PIECE_TYPES:
        return False
    if obj.get(SURFACE_KEY) or obj.get(PATTERNS_KEY) or obj.get(RULES_KEY):
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


classes = (ROADS_PG_replacement,)
pointers = ((bpy.types.Scene, "road_replacement", ROADS_PG_replacement),)
