"""The scene's grammar: a Text datablock holding a grammar file (ggg-grammar JSON, see
docs/file-formats.md), so that it is saved inside the .blend, and the scene settings of
the grammar operators (scene.road_grammar), Grow into Region's region object among them.

The text is parsed by the native module (ggg.parse_grammar) when it is used; the last
parse is cached by content, so the sidebar and the rule menus do not parse on every redraw,
and an edit of the text in the Text Editor is seen at once.
"""

import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, PointerProperty
from bpy.types import PropertyGroup

from . import native
from .region import poll as _region_poll

# Custom property of a grammar Text: the file it was loaded from.
SOURCE_KEY = "road_grammar_source"
# Which grammar a nonterminal placed by Place Rule comes from: the point attribute
# RULE_GRAMMAR of the graph mesh is k > 0 for the grammar Text named
# object[RULE_GRAMMARS_KEY][k - 1], 0 for a vertex without a note (a street vertex, or a
# nonterminal of an axiom, a derivation or an imported file: the grammar of its object).
RULE_GRAMMAR = "rule_grammar"
RULE_GRAMMARS_KEY = "rule_grammars"

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


class GrammarUnavailable(Exception):
    """No grammar can be used: none is loaded, or its text does not parse. The message
    says which."""


# Text name -> (content, ggg.Grammar or the error), for the last few texts parsed (the
# scene's grammar, the one Place Rule uses, the two of Stitch Cities).
_cache = {}
_CACHED_TEXTS = 8


def parse_text(text):
    """The ggg.Grammar of a Text datablock; raises ggg.GrammarError (or NativeModuleError)."""
    ggg = native.load()
    content = text.as_string()
    cached = _cache.get(text.name_full)
    if cached is not None and cached[0] == content:
        result = cached[1]
    else:
        try:
            result = ggg.parse_grammar(content, text.name_full)
        except ggg.Error as ex:
            result = ex
        _cache.pop(text.name_full, None)
        while len(_cache) >= _CACHED_TEXTS:
            _cache.pop(next(iter(_cache)))
        _cache[text.name_full] = (content, result)
    if isinstance(result, Exception):
        raise result
    return result


def of_text(text):
    """(Text, ggg.Grammar) of a grammar Text; raises GrammarUnavailable or
    native.NativeModuleError."""
    ggg = native.load()
    try:
        return text, parse_text(text)
    except ggg.Error as ex:
        raise GrammarUnavailable("The grammar text '{}' is not a valid grammar: {}".format(text.name, ex)) from ex


def named(name):
    """(Text, ggg.Grammar) of the Text ``name``; raises GrammarUnavailable (no such text,
    not a grammar) or native.NativeModuleError."""
    text = bpy.data.texts.get(name)
    if text is None:
        raise GrammarUnavailable("No text named '{}' holds a grammar".format(name))
    return of_text(text)


def looks_like_grammar(text):
    """Whether a Text looks like a grammar file (its beginning names the format), without
    parsing it: what the grammar pickers list."""
    if text is None or text.name.startswith("."):
        return False
    if text.get(SOURCE_KEY) is not None or text.get("road_grammar_learned_from") is not None:
        return True
    head = "".join(line.body for line in text.lines[:4])[:400]
    return '"ggg-grammar"' in head


def learned_text(obj):
    """The grammar Text learned from the road graph ``obj`` (its Learn result), else None."""
    result = getattr(obj, "road_learning", None)
    return result.text if result is not None else None


def active_text(context):
    settings = getattr(context.scene, "road_grammar", None)
    return settings.text if settings is not None else None


def active(context):
    """(Text, ggg.Grammar) of the scene's active grammar; raises GrammarUnavailable or
    native.NativeModuleError."""
    text = active_text(context)
    if text is None:
        raise GrammarUnavailable("No grammar in this scene: load one (Roads sidebar > Grammar > Load)")
    return of_text(text)


def chosen_text(owner, context):
    """The grammar Text a rule menu lists: the one its owner names (Place Rule's
    ``grammar``, the panel's ``place_grammar``), else the scene's."""
    name = getattr(owner, "grammar", None)
    if isinstance(name, str) and name:
        return bpy.data.texts.get(name)
    picked = getattr(owner, "place_grammar", None)
    if isinstance(picked, bpy.types.Text):
        return picked
    return active_text(context)


def try_active(context):
    """(Text or None, grammar or None, message or None), for drawing: never raises."""
    try:
        text, parsed = active(context)
        return text, parsed, None
    except (GrammarUnavailable, native.NativeModuleError) as ex:
        return active_text(context), None, str(ex)


def rule_of(parsed, identifier):
    """The rule dict whose symbol name (or number) is ``identifier``, else None."""
    for rule in parsed.rules:
        if rule["name"] == identifier or str(rule["symbol"]) == identifier:
            return rule
    return None


def describe_rule(rule):
    return "{} -> {} vertices, {} edges, {} nonterminals, {} embedding points".format(
        rule["name"], rule["vertices"], rule["edges"], rule["nonterminals"], rule["embedding_points"])


# Blender needs the strings of dynamic enum items to stay alive while it shows them.
_rule_items = []


def rule_items(_self, context):
    """Enum items of the active grammar's rules: (symbol name, "name (k)", description)."""
    items = []
    parsed = None
    if context is not None:
        text = chosen_text(_self, context)
        try:
            parsed = of_text(text)[1] if text is not None else None
        except (GrammarUnavailable, native.NativeModuleError):
            parsed = None
    if parsed is not None:
        # Values by position, so that the default (0) is the first rule of any grammar.
        for index, rule in enumerate(parsed.rules):
            items.append((rule["name"], "{} ({})".format(rule["name"], rule["symbol"]), describe_rule(rule), index))
    if not items:
        items.append(('NONE', "No Rules", "Load a grammar first", 0))
    _rule_items[:] = items
    return _rule_items


TOLERANCE_ITEMS = (
    ('RELATIVE', "Relative", "Tolerance as a fraction of the scale of the vertex being rewritten"),
    ('METRES', "Metres", "Tolerance as a distance in metres"),
)


# The settings of Place Rule and Grow, declared once here for both the scene
# (ROADS_PG_grammar below) and the operators (grammar_ops), which take the scene's values
# when invoked. Each call makes a new property; the arguments are the labels and
# descriptions in which the two differ.

def rule_property(description):
    return EnumProperty(
        name="Rule",
        description=description,
        items=rule_items,
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
    return looks_like_grammar(text)


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
    stitch_share: share_property()


def register():
    bpy.types.Scene.road_grammar = PointerProperty(type=ROADS_PG_grammar)


def unregister():
    del bpy.types.Scene.road_grammar
