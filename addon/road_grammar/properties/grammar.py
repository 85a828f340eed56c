"""The scene's grammar and the scene settings of the grammar operators
(``scene.road_grammar``), Grow into Region's region object among them; the grammar itself
is a Text (data.texts).

The settings of Place Rule, Grow, Grow into Region and Stitch Cities are declared once
here, by the ``*_property`` functions, for both the scene (ROADS_PG_grammar) and the
operators (operators.grammar, operators.region, operators.stitch), which take the scene's
values when invoked.
"""

import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, PointerProperty
from bpy.types import PropertyGroup

from ..data import region, texts

DEFAULT_SCALE = 100.0
DEFAULT_STEPS = 1
DEFAULT_MAX_VERTICES = 1_000_000
DEFAULT_TOLERANCE = 0.05
DEFAULT_TOLERANCE_M = 1.0
# Grow into Region (ggg.grow_region's defaults).
DEFAULT_REGION_SEED = 1
DEFAULT_MAX_PLACEMENTS = 200
DEFAULT_REGION_MAX_VERTICES = 200_000
DEFAULT_PATIENCE = 150


TOLERANCE_ITEMS = (
    ('RELATIVE', "Relative", "Tolerance as a fraction of the scale of the vertex being rewritten"),
    ('METRES', "Metres", "Tolerance as a distance in metres"),
)


# Each call makes a new property; the arguments are the labels and descriptions in which
# the scene's and the operator's differ.

def rule_property(description):
    return EnumProperty(
        name="Rule",
        description=description,
        items=texts.rule_items,
    )


def scale_property(description):
    return FloatProperty(
        name="Scale",
        description=description,
        default=DEFAULT_SCALE,
        min=1e-3,
        soft_min=1.0,
        soft_max=5000.0,
        unit='LENGTH',
        subtype='DISTANCE',
    )


def steps_property():
    return IntProperty(
        name="Steps",
        description="Derivation steps: each rewrites every nonterminal at once",
        default=DEFAULT_STEPS,
        min=1,
        soft_max=10,
    )


def max_vertices_property():
    return IntProperty(
        name="Max Vertices",
        description="Vertex budget: a step that would make the graph larger is not applied",
        default=DEFAULT_MAX_VERTICES,
        min=1,
    )


def tolerance_unit_property(name):
    return EnumProperty(
        name=name,
        description="How the embedding tolerance is given",
        items=TOLERANCE_ITEMS,
        default='RELATIVE',
    )


def tolerance_property():
    return FloatProperty(
        name="Tolerance",
        description="Embedding points connect to (and placed vertices merge with) vertices this "
        "close, as a fraction of the rewritten vertex's scale",
        default=DEFAULT_TOLERANCE,
        min=0.0,
        soft_max=0.5,
        precision=3,
    )


def tolerance_m_property(name):
    return FloatProperty(
        name=name,
        description="Embedding points connect to (and placed vertices merge with) vertices this "
        "close, in metres",
        default=DEFAULT_TOLERANCE_M,
        min=0.0,
        soft_max=100.0,
        unit='LENGTH',
        subtype='DISTANCE',
    )


def strict_property(description):
    return BoolProperty(
        name="Strict Embedding",
        description=description,
        default=False,
    )


def seed_property():
    return IntProperty(
        name="Seed",
        description="Seed of the random choices (which street, rule and side next): the same seed gives the same "
        "streets",
        default=DEFAULT_REGION_SEED,
        min=0,
    )


def max_placements_property():
    return IntProperty(
        name="Max Rules",
        description="Most rules placed in the region (the placed rules of the graph count too)",
        default=DEFAULT_MAX_PLACEMENTS,
        min=1,
        soft_max=5000,
    )


def region_max_vertices_property():
    return IntProperty(
        name="Max Vertices",
        description="Vertex budget of the whole graph, its own vertices included: growth stops when it is reached",
        default=DEFAULT_REGION_MAX_VERTICES,
        min=1,
    )


def patience_property():
    return IntProperty(
        name="Patience",
        description="Tries in a row that place nothing after which the region counts as full",
        default=DEFAULT_PATIENCE,
        min=1,
        soft_max=2000,
    )


def use_placed_property():
    return BoolProperty(
        name="Use Placed Rules",
        description="Grow the rules placed in the graph (its nonterminals, Place Rule) first; each one that fits "
        "becomes streets, the others stay as they are. Off: they stay as they are, and growth leaves them out",
        default=True,
    )


def roundabouts_property():
    return BoolProperty(
        name="Roundabouts",
        description="Make grown junctions roundabouts as often as the road graph's junctions near the region are "
        "ones (rings of one-way streets driven one way round). Off: every grown junction stays a junction",
        default=True,
    )


DEFAULT_STITCH_SHARE = 0.5


def share_property():
    return FloatProperty(
        name="Share of the Active City",
        description="Share of the rules that the active city's grammar places: its growth stops after this share of "
        "the rules that would fill the region alone, and the other city's grammar fills the rest (1: the other "
        "city's grammar only fills what is left)",
        default=DEFAULT_STITCH_SHARE, min=0.0, max=1.0, subtype='FACTOR',
    )


def _text_poll(_self, text):
    return not text.name.startswith(".")


def _grammar_text_poll(_self, text):
    return texts.looks_like_grammar(text)


def _region_poll(_self, obj):
    return region.is_candidate(obj)


def place_grammar_property():
    return PointerProperty(
        name="Grammar",
        type=bpy.types.Text,
        description="Grammar whose rule Place Rule places (empty: the scene's grammar); each learned road graph "
        "keeps its own",
        poll=_grammar_text_poll,
    )


class ROADS_PG_grammar(PropertyGroup):
    """The scene's grammar and the settings of the grammar operators (Roads sidebar)."""

    text: PointerProperty(
        name="Grammar",
        type=bpy.types.Text,
        description="Text holding the active grammar (a ggg-grammar JSON file, kept in the .blend)",
        poll=_text_poll,
    )
    place_grammar: place_grammar_property()
    rule: rule_property("Rule whose nonterminal Place Rule puts at the 3D cursor")
    scale: scale_property("Metres for one unit of the rule: the scale of the placed nonterminal's frame")
    steps: steps_property()
    max_vertices: max_vertices_property()
    tolerance_unit: tolerance_unit_property("Tolerance")
    tolerance: tolerance_property()
    tolerance_m: tolerance_m_property("Tolerance")
    strict: strict_property("Rewrite a nonterminal only when every embedding point finds a vertex to connect "
                            "to (off: relaxed embedding, paper 3.3)")
    region: PointerProperty(
        name="Region",
        type=bpy.types.Object,
        description="Curve or mesh whose outline (seen from above) Grow into Region fills with streets",
        poll=_region_poll,
    )
    region_seed: seed_property()
    region_max_placements: max_placements_property()
    region_max_vertices: region_max_vertices_property()
    region_patience: patience_property()
    region_use_placed: use_placed_property()
    region_roundabouts: roundabouts_property()
    stitch_share: share_property()


classes = (ROADS_PG_grammar,)
pointers = ((bpy.types.Scene, "road_grammar", ROADS_PG_grammar),)
