"""Showing how a learned grammar encodes its road graph (paper Fig. 13): the graph encoded
to one level of the hierarchy, coloured by rule.

A child object of the road graph, "<graph> Rules", holds the streets the grammar decodes
to (``ggg.decode``) and, as loose vertices after them, the nonterminal vertices of the
graph encoded to the level shown (``ggg.encoded_graph``). Its mesh attributes:

* edges: ``rule``, the symbol of the rule whose instance holds the street at that level (both
  of its ends stand for the same nonterminal vertex of the level's graph; 0: none, the
  street joins two instances or lies outside them), ``rule_slot``, its colour (0 the
  neutral grey, 1..PALETTE_SIZE the colours of the palette (core.palette): rule k of the
  grammar has colour (k - 1) mod PALETTE_SIZE + 1), and ``width`` (the class's default
  width);
* points: ``marker_rule`` (the symbol of the nonterminal a vertex marks, 0 for a street
  vertex) and ``marker_slot`` (its colour, DIMMED_SLOT for a rule that is not the chosen
  one, 0 for a street vertex).

Its Geometry Nodes modifier ("Road Rules") draws every street as a flat ribbon a little
above the road surfaces in its colour (the neutral ones lowest) and every nonterminal as a
disc in its rule's colour on a white disc, above them; the materials of the colours are
display.patterns', so the list, the isogroups and this display share them. The mesh is
kept in the .blend, so the display survives saving; a level is computed again from the
grammar text whenever it is shown (the last results are cached in memory by the text's
content).
"""

import bpy
import numpy as np

from ..core import native
from ..core.levels import DisplayError, LevelView
from ..core.names import RULES_KEY
from ..core.palette import DIMMED_SLOT, NEUTRAL_SLOT, NO_COLOR, PALETTE_SIZE, to_linear
from ..core.widths import class_default_widths
from ..data import mesh as mesh_data
from ..data import texts
from ..data import preferences
from . import patterns
from .nodes import find_socket, new_node, new_socket

OBJECT_KEY = RULES_KEY  # marks the child object that shows the levels
LEVEL_KEY = "road_rules_level"  # on the child: the level shown
RULE_KEY = "road_rules_rule"  # on the child: the symbol of the highlighted rule, 0 none
STREET_VERTICES_KEY = "road_rules_street_vertices"  # on the child: vertices before the markers
NODE_GROUP_NAME = "Road Rules"
MODIFIER_NAME = "Road Rules"
MARKER = "road_grammar_rules_version"
ROLE_MARKER = "road_grammar_rules_material"
NODE_GROUP_VERSION = 1
MATERIAL_VERSION = 1

EDGE_RULE = "rule"
EDGE_SLOT = "rule_slot"
MARKER_RULE = "marker_rule"
MARKER_SLOT = "marker_slot"
WIDTH = "width"

# Drawing heights: streets, a little more per colour (so colours are drawn over the
# neutral streets at crossings), the markers above them all.
HEIGHT_M = 0.3
SLOT_STEP_M = 0.004
MARKER_LIFT_M = 0.1
OUTLINE_SCALE = 1.35

NEUTRAL_COLOR = NO_COLOR
OUTLINE_COLOR = (1.0, 1.0, 1.0)


_cache = {"key": None, "streets": None, "views": {}}

# Road graph object name -> why the level of its learned grammar could not be shown (for the
# panel: an update cannot report).
display_problems = {}


def forget_cache():
    _cache["key"], _cache["streets"] = None, None
    _cache["views"].clear()


def forget():
    """Drop what is kept in memory: the problems for the panel and the levels computed (the
    add-on is being disabled)."""
    display_problems.clear()
    forget_cache()


def show_learned(obj):
    """Show the level and chosen rule of ``obj``'s learning (``object.road_learning``, see
    data.learning) in its rules object. Returns the LevelView shown; raises DisplayError (or
    native.NativeModuleError) after remembering the problem for the panel."""
    result = obj.road_learning
    try:
        if result.text is None:
            raise DisplayError("{} has no learned grammar: run Learn first".format(obj.name))
        view = level_view(result.text, result.level)
        show(obj, view, result.highlighted_symbol())
    except (DisplayError, native.NativeModuleError) as ex:
        display_problems[obj.name] = str(ex)
        raise
    display_problems.pop(obj.name, None)
    return view


def level_view(text, level):
    """The LevelView of ``level`` of the grammar in the Text ``text`` (cached by content).
    Raises DisplayError (or native.NativeModuleError)."""
    ggg = native.load()
    try:
        parsed = texts.parse_text(text)
    except ggg.Error as ex:
        raise DisplayError("The grammar text '{}' is not a valid grammar: {}".format(text.name, ex)) from ex
    if not parsed.learned:
        raise DisplayError("The grammar '{}' was not learned from a road graph".format(parsed.name))
    if not 0 <= level <= parsed.levels:
        raise DisplayError("The grammar '{}' has levels 0 to {}, not {}".format(parsed.name, parsed.levels, level))
    key = (text.name_full, text.as_string())
    if _cache["key"] != key:
        forget_cache()
        try:
            _cache["streets"] = ggg.decode(parsed)
        except ggg.Error as ex:
            raise DisplayError("Cannot decode the grammar '{}': {}".format(parsed.name, ex)) from ex
        _cache["key"] = key
    views = _cache["views"]
    if level not in views:
        try:
            views[level] = LevelView(ggg, parsed, level, _cache["streets"])
        except ggg.Error as ex:
            raise DisplayError("Cannot encode the grammar '{}' to level {}: {}".format(parsed.name, level, ex)) from ex
    return views[level]


# --- the display object ------------------------------------------------------------------

def rules_object(graph_obj):
    """The child of ``graph_obj`` that shows its learned grammar's levels, else None."""
    return next((child for child in graph_obj.children if child.get(OBJECT_KEY)), None)


def find_modifier(obj):
    return next((m for m in obj.modifiers if m.type == 'NODES' and m.node_group is not None
                 and m.node_group.get(MARKER) is not None), None)


def _widths(highway):
    """Default width of each street's class (the add-on's preferences where filled in)."""
    ggg = native.load()
    defaults = dict(ggg.default_widths())
    try:
        defaults.update({item.name: item.width for item in preferences.get(bpy.context).class_widths})
    except (KeyError, AttributeError):  # the add-on is not enabled under its package name
        pass
    return class_default_widths(highway, defaults, ggg.highway_classes())


def show(graph_obj, view, highlight=0):
    """Write ``view`` (a LevelView) into the rules object of ``graph_obj`` (made when
    missing), the rule with symbol ``highlight`` (0: none) highlighted: its streets and
    nonterminals in its colour, the others neutral. Returns the rules object."""
    child = ensure_object(graph_obj)
    street_count = len(view.positions)
    points = np.concatenate((view.positions, view.marker_positions)) if len(view.marker_positions) \
        else view.positions
    zeros = np.zeros(street_count, dtype=np.int64)
    mesh_data.fill_edge_mesh(
        child.data, points, view.edges,
        {EDGE_RULE: ('INT', view.edge_rule), EDGE_SLOT: ('INT', view.edge_slots(highlight)),
         WIDTH: ('FLOAT', _widths(view.highway))},
        {MARKER_RULE: ('INT', np.concatenate((zeros, view.marker_rule))),
         MARKER_SLOT: ('INT', np.concatenate((zeros, view.marker_slots(highlight))))})
    child[LEVEL_KEY] = view.level
    child[RULE_KEY] = int(highlight)
    child[STREET_VERTICES_KEY] = street_count
    child.update_tag()
    return child


def clear(graph_obj):
    """Remove the rules object of ``graph_obj``."""
    child = rules_object(graph_obj)
    if child is not None:
        patterns.remove_child(child)


def ensure_object(graph_obj):
    """The rules object of ``graph_obj``: made once, a child at the graph's origin in the
    graph's collections, with the Road Rules modifier."""
    child = rules_object(graph_obj)
    if child is None:
        child = patterns.new_child(graph_obj, graph_obj.name + " Rules", OBJECT_KEY)
    modifier = find_modifier(child)
    if modifier is None or modifier.node_group.get(MARKER) != NODE_GROUP_VERSION:
        if modifier is not None:
            child.modifiers.remove(modifier)
        modifier = child.modifiers.new(MODIFIER_NAME, 'NODES')
        modifier.node_group = node_group()
    return child


def _plain_material(role, name, srgb):
    for existing in bpy.data.materials:
        if existing.get(MARKER) == MATERIAL_VERSION and existing.get(ROLE_MARKER) == role:
            return existing
    color = (*(to_linear(c) for c in srgb), 1.0)
    mat = bpy.data.materials.new(name)
    mat[MARKER] = MATERIAL_VERSION
    mat[ROLE_MARKER] = role
    mat.diffuse_color = color
    mat.use_nodes = True
    bsdf = mat.node_tree.nodes.get("Principled BSDF")
    bsdf.inputs["Base Color"].default_value = color
    bsdf.inputs["Roughness"].default_value = 0.8
    return mat


def slot_material(slot):
    """The material of colour slot ``slot``: the palette's (shared with display.patterns),
    or the neutral grey ("Road Rule Street")."""
    if slot in (NEUTRAL_SLOT, DIMMED_SLOT):
        return _plain_material("neutral", "Road Rule Street", NEUTRAL_COLOR)
    return patterns.material(slot)


def outline_material():
    return _plain_material("outline", "Road Rule Outline", OUTLINE_COLOR)


def node_group():
    """The shared "Road Rules" node group, created on first use.

    Every street (edge) becomes one point at its middle carrying its direction, length,
    width and colour slot; a unit quad, raised by Height (and a little more per colour) and
    with the material of its colour, is instanced on it, turned along it and scaled to
    (length + width) x width. Every marker vertex (``marker_slot`` > 0) gets a disc of
    radius Marker Size in its colour on a larger white one, above the streets."""
    for group in bpy.data.node_groups:
        if group.bl_idname == 'GeometryNodeTree' and group.get(MARKER) == NODE_GROUP_VERSION:
            return group
    tree = bpy.data.node_groups.new(NODE_GROUP_NAME, 'GeometryNodeTree')
    tree[MARKER] = NODE_GROUP_VERSION
    new_socket(tree, 'INPUT', 'NodeSocketGeometry', "Geometry")
    for name, default, low, high in (("Width Scale", 1.0, 0.0, 10.0), ("Min Width", 3.0, 0.0, 1000.0),
                                     ("Height", HEIGHT_M, -1000.0, 1000.0), ("Marker Size", 6.0, 0.0, 1000.0)):
        socket = new_socket(tree, 'INPUT', 'NodeSocketFloat', name)
        socket.default_value, socket.min_value, socket.max_value = default, low, high
    new_socket(tree, 'OUTPUT', 'NodeSocketGeometry', "Geometry")
    nodes, links = tree.nodes, tree.links
    group_in = new_node(nodes, 'NodeGroupInput', (-2000, 0))
    group_out = new_node(nodes, 'NodeGroupOutput', (1400, 0))
    geometry = group_in.outputs["Geometry"]

    def named_int(name, location):
        node = new_node(nodes, 'GeometryNodeInputNamedAttribute', location, data_type='INT')
        node.inputs["Name"].default_value = name
        return find_socket(node.outputs, "Attribute")

    # Streets -> points carrying their ribbon's rotation and scale.
    ribbons = patterns.edge_ribbons(tree, group_in, geometry, -400)

    # Marker vertices -> points; a disc (and its outline) of radius Marker Size.
    marker_slot = named_int(MARKER_SLOT, (-1400, 800))
    is_marker = new_node(nodes, 'FunctionNodeCompare', (-1200, 800), data_type='INT', operation='GREATER_THAN')
    links.new(marker_slot, find_socket(is_marker.inputs, "A", 'INT'))
    find_socket(is_marker.inputs, "B", 'INT').default_value = 0
    marker_points = new_node(nodes, 'GeometryNodeMeshToPoints', (-1000, 800), mode='VERTICES')
    links.new(geometry, marker_points.inputs["Mesh"])
    links.new(find_socket(is_marker.outputs, "Result"), marker_points.inputs["Selection"])
    disc = new_node(nodes, 'GeometryNodeMeshCircle', (-1000, 1100), fill_type='NGON')
    disc.inputs["Vertices"].default_value = 20
    disc.inputs["Radius"].default_value = 1.0
    marker_scale = new_node(nodes, 'ShaderNodeCombineXYZ', (-800, 1000))
    marker_scale.inputs["Z"].default_value = 1.0
    links.new(group_in.outputs["Marker Size"], marker_scale.inputs["X"])
    links.new(group_in.outputs["Marker Size"], marker_scale.inputs["Y"])
    # The outline: larger in x and y only (a z scale would lift it above the disc).
    outline_size = new_node(nodes, 'ShaderNodeMath', (-800, 1200), operation='MULTIPLY')
    links.new(group_in.outputs["Marker Size"], outline_size.inputs[0])
    outline_size.inputs[1].default_value = OUTLINE_SCALE
    outline_scale = new_node(nodes, 'ShaderNodeCombineXYZ', (-600, 1200))
    outline_scale.inputs["Z"].default_value = 1.0
    links.new(outline_size.outputs[0], outline_scale.inputs["X"])
    links.new(outline_size.outputs[0], outline_scale.inputs["Y"])

    join = new_node(nodes, 'GeometryNodeJoinGeometry', (1100, 0))
    street_slot = named_int(EDGE_SLOT, (-400, -900))

    instances = patterns.raised_instances
    y = -1000
    for slot in range(NEUTRAL_SLOT, PALETTE_SIZE + 1):
        instances(tree, group_in, join, ribbons.points.outputs["Points"], ribbons.quad, slot_material(slot),
                  SLOT_STEP_M * slot, ribbons.scale, ribbons.rotation, y, street_slot, slot)
        y -= 260
    top = SLOT_STEP_M * (PALETTE_SIZE + 1) + MARKER_LIFT_M
    y = 1400
    instances(tree, group_in, join, marker_points.outputs["Points"], disc.outputs["Mesh"], outline_material(), top,
              outline_scale.outputs[0], None, y)
    for slot in range(1, DIMMED_SLOT + 1):
        y += 260
        instances(tree, group_in, join, marker_points.outputs["Points"], disc.outputs["Mesh"], slot_material(slot),
                  top + SLOT_STEP_M, marker_scale.outputs[0], None, y, marker_slot, slot)
    links.new(join.outputs["Geometry"], group_out.inputs["Geometry"])
    return tree
