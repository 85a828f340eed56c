"""Grammar learning's properties (inverse procedural modelling, paper 6): settings, the
stored result and the level shown.

* ``scene.road_learning`` (ROADS_PG_learning_settings): the parameters of Learn, shown in
  the Learn panel.
* ``object.road_learning`` (ROADS_PG_learning) on a road graph object: the result of its
  last Learn, saved in the .blend: the Text that holds the learned grammar (a ggg-grammar
  JSON file; Learn also makes it the scene's grammar, ``scene.road_grammar.text``, so the
  Grammar panel's operators use it), the learning statistics as JSON (``stats``, as
  ``ggg.learn`` returns them), the rules for the list (name, level, uses, size), the chosen
  rule and the level shown.

The level (0 = the decoded streets ... ``levels`` = the axiom) and the chosen rule are
shown by display.rules: setting either (the panel's slider, the list) rebuilds the rules
object of the graph from the grammar text (display.rules.show_learned).
"""

import json

import bpy
from bpy.props import (BoolProperty, CollectionProperty, EnumProperty, FloatProperty, FloatVectorProperty,
                       IntProperty, PointerProperty, StringProperty)
from bpy.types import PropertyGroup

from ..core.palette import rule_color_srgb
from ..core.updates import updates_suspended
from ..display import rules
# ID property of ROADS_PG_learning that holds the level (the property has a getter and a
# setter, which keep it within 0 .. levels).
_LEVEL_KEY = "level_shown"

MODE_ITEMS = (
    ('PAPER', "Paper", "Rules and the placement of their instances only (paper 6): the decoded streets keep "
     "every edge, the positions move by up to the shape tolerance"),
    ('LOSSLESS', "Lossless", "Also store each vertex's residual, so that the grammar decodes to exactly the same "
     "streets, to OpenStreetMap's own precision (positions within 1 cm)"),
)


def settings_properties(options=frozenset({'ANIMATABLE'})):
    """The parameters of Learn, new property objects on each call: the scene's settings
    (ROADS_PG_learning_settings) and the operator (operators.learning.ROADS_OT_learn) declare the
    same ones, and the operator takes the scene's values when invoked. The operator's are
    ``options={'SKIP_SAVE'}``, so that a value its caller does not give is the panel's, not
    the last run's."""
    options = set(options)
    return {
        "angle_cells": IntProperty(
            name="Angle Cells", description="Angle cells of the polar grid a new vertex is binned in when finding "
            "the patterns (paper 5.1)", default=12, min=1, max=360, soft_max=72, options=options),
        "distance_cells": IntProperty(
            name="Distance Cells", description="Distance cells of the polar grid", default=10, min=1, soft_max=60,
            options=options),
        "cut": FloatProperty(
            name="Frequency Cut", description="Share of the least frequent patterns that are not grown further",
            default=0.8, min=0.0, max=0.99, precision=2, options=options),
        "max_order": IntProperty(
            name="Max Order", description="Largest pattern that can become a rule, in vertices", default=6, min=2,
            soft_max=20, options=options),
        "levels": IntProperty(
            name="Levels", description="Most levels of the hierarchy: each level encodes the repeated patterns of "
            "the graph encoded so far (0 = until nothing repeats)", default=64, min=0, soft_max=100,
            options=options),
        "complete": BoolProperty(
            name="Complete", description="Encode level after level until the axiom is a single vertex (paper Fig. "
            "13): smaller repeating patterns keep the encoding going where nothing pays, and what never repeats "
            "becomes a rule used once. Larger than the default grammar; shows the whole hierarchy",
            default=False, options=options),
        "mode": EnumProperty(
            name="Mode", description="What the grammar keeps of the graph", items=MODE_ITEMS, default='PAPER',
            options=options),
        "min_aspect": FloatProperty(
            name="Min Aspect", description="Only patterns at least this close to square become rules (0 = any; 1 = "
            "as wide as long)", default=0.0, min=0.0, max=1.0, precision=2, options=options),
        "min_leaves": IntProperty(
            name="Min Leaves", description="Only patterns with at least this many dead-end vertices become rules",
            default=0, min=0, soft_max=10, options=options),
        "min_irregularity": FloatProperty(
            name="Min Irregularity", description="Only patterns whose street angles deviate at least this much from "
            "a right-angled grid become rules (degrees)", default=0.0, min=0.0, max=45.0, precision=1,
            options=options),
        "use_seed": BoolProperty(
            name="Selection as First Rule", description="The piece selected in Edit Mode becomes the first rule, with "
            "all its copies, before the automatic passes (paper Fig. 18a, user selected)", default=False,
            options=options),
    }


class ROADS_PG_learning_settings(PropertyGroup):
    """The parameters of Learn (Roads sidebar > Learn)."""

    __annotations__ = {
        **settings_properties(),
        "show_constraints": BoolProperty(name="Constraints", description="Show the constraints on the rules",
                                         default=False),
    }


# --- the stored result ------------------------------------------------------------------

def _rule_color(item):
    return rule_color_srgb(item.color_slot)


class ROADS_PG_learned_rule(PropertyGroup):
    """One rule of a learned grammar, for the list."""

    # name (from PropertyGroup): the rule's symbol name (R1, R2, ...).
    symbol: IntProperty(name="Symbol", description="Number of the rule's symbol")
    level: IntProperty(name="Level", description="Level of the hierarchy the rule belongs to (1: it places "
                       "street vertices only)")
    uses: IntProperty(name="Uses", description="Instances of the rule in the encoding of the road graph")
    vertex_count: IntProperty(name="Vertices", description="Vertices of the rule's right-hand side S")
    edge_count: IntProperty(name="Edges", description="Edges of S")
    nonterminals: IntProperty(name="Nonterminals", description="Nonterminal vertices of S")
    embedding_points: IntProperty(name="Embedding Points", description="Where S connects to the rest of the graph")
    color_slot: IntProperty(name="Colour Slot", description="Colour of the rule in the display")
    color: FloatVectorProperty(name="Colour", description="Colour of the rule in the display", subtype='COLOR_GAMMA',
                               size=3, get=_rule_color)


def _show_changed(self, _context):
    # The slider and the list show what they say; skipped while the add-on sets them.
    if updates_suspended():
        return
    rules.show_learned(self.id_data)


def _get_level(self):
    return int(self.get(_LEVEL_KEY, 0))


def _set_level(self, value):
    self[_LEVEL_KEY] = max(0, min(int(value), self.levels))


class ROADS_PG_learning(PropertyGroup):
    """The result of the last Learn of a road graph object (kept in the .blend)."""

    text: PointerProperty(name="Grammar", type=bpy.types.Text,
                          description="Text holding the grammar learned from this road graph")
    stats: StringProperty(name="Statistics", description="What ggg.learn reported, as JSON")
    parameters: StringProperty(name="Parameters", description="The parameters of the learning")
    mode: StringProperty(name="Mode", description="paper or lossless")
    levels: IntProperty(name="Levels", description="Levels of the learned hierarchy")
    seconds: FloatProperty(name="Time", description="Duration of the learning in seconds")
    topology: StringProperty(name="Topology", description="Checksum of the mesh the grammar was learned from")
    rules: CollectionProperty(type=ROADS_PG_learned_rule)
    active_rule: IntProperty(name="Rule", description="Rule whose instances are highlighted (-1: all rules in "
                             "their colours)", default=-1, min=-1, update=_show_changed)
    level: IntProperty(name="Level", description="Level of the hierarchy shown: 0 = the decoded streets, the "
                       "highest = the axiom; each street is coloured by the rule whose instance holds it there",
                       min=0, get=_get_level, set=_set_level, update=_show_changed)

    def has_result(self):
        return bool(self.stats)

    def stats_dict(self):
        try:
            return json.loads(self.stats) if self.stats else {}
        except ValueError:
            return {}

    def highlighted_symbol(self):
        """The symbol of the chosen rule, 0 for none."""
        if 0 <= self.active_rule < len(self.rules):
            return self.rules[self.active_rule].symbol
        return 0


classes = (ROADS_PG_learned_rule, ROADS_PG_learning, ROADS_PG_learning_settings)
pointers = ((bpy.types.Scene, "road_learning", ROADS_PG_learning_settings),
            (bpy.types.Object, "road_learning", ROADS_PG_learning))
