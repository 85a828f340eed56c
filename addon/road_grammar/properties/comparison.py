"""The last comparison of a road graph with another (``object.road_compare``, set by
Compare): the ggg.compare dict as JSON, saved in the .blend."""

import bpy
from bpy.props import BoolProperty, StringProperty
from bpy.types import PropertyGroup

from ..core.comparison import read_stored


class ROADS_PG_compare(PropertyGroup):
    """The last Compare of this road graph (A) with another (B)."""

    result: StringProperty(name="Result", description="What ggg.compare returned, as JSON: the distances and the "
                           "summary of each network (a: this graph, b: the other)")
    other: StringProperty(name="Compared With", description="The road graph this one was compared with")
    topology: StringProperty(name="Topology", description="Checksum of this graph's vertices and edges when it was "
                             "compared")
    show_meanings: BoolProperty(name="Meanings", description="Say what each measure means to a planner",
                                default=False)

    def stored(self):
        """The ggg.compare dict kept here, or None."""
        return read_stored(self.result)


classes = (ROADS_PG_compare,)
pointers = ((bpy.types.Object, "road_compare", ROADS_PG_compare),)
