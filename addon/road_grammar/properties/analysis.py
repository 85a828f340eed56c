"""The analyzer's properties (paper 5):

* ``scene.road_analysis`` (ROADS_PG_analysis_settings): the parameters of Analyze and
  Find Similar, shown in the Patterns panel;
* ``object.road_analysis`` (ROADS_PG_analysis) on a road graph object: the result of its
  last Analyze, saved in the .blend (data.analysis writes and reads it).
"""

import bpy
from bpy.props import (BoolProperty, CollectionProperty, EnumProperty, FloatProperty, FloatVectorProperty,
                       IntProperty, StringProperty)
from bpy.types import PropertyGroup

from ..core.analysis import DEFAULT_MAX_STORED, SCALE_ITEMS, StaleAnalysis
from ..core.palette import PALETTE_SIZE, slot_color_srgb
from ..core.updates import updates_suspended
from ..display import patterns


def _item_color(item):
    return slot_color_srgb(item.color_slot)


class ROADS_PG_isogroup(PropertyGroup):
    """One isogroup of an analysis: a street pattern and where it occurs."""

    # name (from PropertyGroup): "order k", what the list's filter matches.
    rank: IntProperty(name="Rank",
                      description="Place in the list: 1 = the largest gain (with a seed: the seed's own group)")
    order: IntProperty(name="Order", description="Vertices of the pattern")
    edge_count: IntProperty(name="Edges", description="Edges of the pattern")
    frequency: IntProperty(name="Occurrences", description="Places where the pattern occurs (they may overlap)")
    non_overlapping_count: IntProperty(name="Non-Overlapping",
                                       description="The largest number of occurrences that share no vertex")
    gain: FloatProperty(name="Gain", description="Description-length gain of encoding the non-overlapping occurrences")
    score: FloatProperty(name="Score", description="Frequency x convex-hull area added by the last vertex (paper 5.1)")
    size_m: FloatProperty(name="Size", description="Mean RMS radius of the occurrences", unit='LENGTH')
    aspect: FloatProperty(name="Aspect", description="Aspect ratio of the pattern (1 = as wide as long)")
    leaves: IntProperty(name="Leaves", description="Pattern vertices with one street")
    irregularity_deg: FloatProperty(name="Irregularity",
                                    description="Mean deviation of the pattern's street angles from multiples of "
                                    "90 degrees")
    parent: IntProperty(name="Parent", description="Rank of the isogroup this one grew from (0: none, or not stored)")
    selection_exact: BoolProperty(name="Exact", description="The non-overlapping set is a proven maximum")
    selection_method: StringProperty(name="Method", description="How the non-overlapping set was chosen")
    color_slot: IntProperty(name="Colour Slot", description="Colour of the isogroup in the overview (0: not coloured)")
    color: FloatVectorProperty(name="Colour", description="Colour of the isogroup in the overview",
                               subtype='COLOR_GAMMA', size=3, get=_item_color)
    occurrence_start: IntProperty(options={'HIDDEN'})
    non_overlapping_start: IntProperty(options={'HIDDEN'})
    edge_start: IntProperty(options={'HIDDEN'})


def _active_index_changed(self, context):
    # Choosing an isogroup in the list highlights it (select + colour); the update is
    # skipped while the add-on itself sets the index.
    if updates_suspended() or self.active_index < 0:
        return
    obj = self.id_data
    try:
        patterns.show_isogroup(obj, self.active_index, select=True)
    except (StaleAnalysis, KeyError, ValueError):
        pass  # the panel says why (out of date); an update cannot report


class ROADS_PG_analysis(PropertyGroup):
    """The result of the last Analyze of a road graph object (kept in the .blend)."""

    isogroups: CollectionProperty(type=ROADS_PG_isogroup)
    active_index: IntProperty(name="Isogroup", description="Isogroup shown in the viewport (select + colour)",
                              default=-1, min=-1, update=_active_index_changed)
    detected: IntProperty(name="Detected", description="Isogroups found before the constraints")
    listed: IntProperty(name="Listed", description="Isogroups that passed the constraints")
    stopped_by_budget: BoolProperty(name="Stopped by Budget")
    seeded: BoolProperty(name="Seeded", description="The analysis grew from the selected vertices")
    seconds: FloatProperty(name="Time", description="Duration of the analysis in seconds")
    max_order: IntProperty(name="Largest Order", description="Largest order of an isogroup found")
    parameters: StringProperty(name="Parameters", description="The parameters of the analysis")
    options: StringProperty(name="Options", description="The arguments of ggg.analyze as JSON (to run the same "
                            "analysis again)")
    topology: StringProperty(name="Topology", description="Checksum of the mesh the vertex ids refer to")

    def has_result(self):
        return bool(self.topology)


def settings_properties():
    """The parameters of Analyze, new property objects on each call: the scene's settings
    (ROADS_PG_analysis_settings) and the operator (operators.analysis.ROADS_OT_analyze) declare
    the same ones, and the operator takes the scene's values when invoked."""
    return {
        "angle_cells": IntProperty(
            name="Angle Cells", description="Angle cells of the polar grid a new vertex is binned in (paper 5.1); "
            "finer grids find fewer, closer copies", default=12, min=1, soft_max=72),
        "distance_cells": IntProperty(
            name="Distance Cells", description="Distance cells of the polar grid", default=10, min=1, soft_max=60),
        "cut": FloatProperty(
            name="Frequency Cut", description="Share of the least frequent patterns that are not grown further "
            "(about 0.8 once the patterns are well formed)", default=0.8, min=0.0, max=0.99, precision=2),
        "full": BoolProperty(
            name="Full", description="Grow every pattern (no frequency cut): the paper's ground truth, slow on "
            "large graphs", default=False),
        "max_order": IntProperty(
            name="Max Order", description="Largest pattern in vertices (0 = until nothing repeats)", default=8,
            min=0, soft_max=20),
        "min_count": IntProperty(
            name="Min Count", description="Fewest occurrences for a pattern to count as repeated", default=2, min=2,
            soft_max=100),
        "scale": EnumProperty(
            name="Scale", description="How the sizes of two occurrences may differ", items=SCALE_ITEMS,
            default='SIMILARITY'),
        "tolerance": FloatProperty(
            name="Tolerance", description="Largest vertex displacement of a match, relative to the seed's size "
            "(Find Similar, and Analyze with a seed)", default=0.2, min=0.0, soft_max=0.5, precision=3),
        "min_aspect": FloatProperty(
            name="Min Aspect", description="List only patterns at least this close to square (0 = any; 1 = as "
            "wide as long)", default=0.0, min=0.0, max=1.0, precision=2),
        "min_leaves": IntProperty(
            name="Min Leaves", description="List only patterns with at least this many dead-end vertices",
            default=0, min=0, soft_max=10),
        "min_irregularity": FloatProperty(
            name="Min Irregularity", description="List only patterns whose street angles deviate at least this "
            "much from a right-angled grid (degrees)", default=0.0, min=0.0, max=45.0, precision=1),
        "use_seed": BoolProperty(
            name="Selection as Seed", description="Grow the analysis from the vertices selected in Edit Mode (its "
            "own isogroup comes first)", default=False),
        "max_stored": IntProperty(
            name="Keep", description="Isogroups kept in the list and in the .blend (the best ones)",
            default=DEFAULT_MAX_STORED, min=1, soft_max=2000),
        "overview_count": IntProperty(
            name="Colours", description="Isogroups coloured in the overview, each in its own colour (the best ones)",
            default=PALETTE_SIZE, min=1, max=PALETTE_SIZE),
    }


class ROADS_PG_analysis_settings(PropertyGroup):
    """The parameters of Analyze and Find Similar (Roads sidebar > Patterns)."""

    __annotations__ = {
        **settings_properties(),
        "show_constraints": BoolProperty(name="Constraints", description="Show the selection constraints",
                                         default=False),
    }


classes = (ROADS_PG_isogroup, ROADS_PG_analysis, ROADS_PG_analysis_settings)
pointers = ((bpy.types.Scene, "road_analysis", ROADS_PG_analysis_settings),
            (bpy.types.Object, "road_analysis", ROADS_PG_analysis))
