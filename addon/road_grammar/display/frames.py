"""Showing nonterminals: an arrow along the x axis of each nonterminal's frame (paper 3.2,
Fig. 3: "the red arrows symbolize one of the axes of the transformed local coordinate
system used for next rule placement").

A Geometry Nodes modifier, "Rule Frames", on the road graph object instances a flat red
arrow (with a dot on the vertex) at every vertex whose `symbol` is > 0, turned by the
frame's angle atan2(frame_b, frame_a) and as long as its scale hypot(frame_a, frame_b)
times **Arrow Size**. It reads the point attributes, so it follows every change of the
mesh (placing a rule, growing, editing) and renders like any geometry.
"""

import bpy

from .nodes import enabled_output, input_sockets, math_node, named_float, new_geometry_group

NODE_GROUP_NAME = "Rule Frames"
MATERIAL_NAME = "Rule Frame"
MODIFIER_NAME = "Rule Frames"
NODE_GROUP_VERSION = 1
MATERIAL_VERSION = 1
MARKER = "road_grammar_frames_version"

ARROW_COLOR = (0.80, 0.015, 0.01)  # linear RGB: the paper's red arrows

# The arrow in the frame's units (x along the frame's first axis, tip at x = 1).
SHAFT_LENGTH = 0.66
SHAFT_WIDTH = 0.11
HEAD_RADIUS = 0.24  # circumradius of the triangular head
DOT_RADIUS = 0.11


def _is_current(datablock, version):
    return datablock is not None and datablock.get(MARKER) == version


def _node(nodes, kind, location, **inputs):
    node = nodes.new(kind)
    node.location = location
    for name, value in inputs.items():
        node.inputs[name.replace("_", " ")].default_value = value
    return node


def _arrow(nodes, links, location):
    """Nodes making the arrow mesh; returns the node whose first output is the arrow."""
    x, y = location
    shaft = _node(nodes, 'GeometryNodeMeshGrid', (x, y), Size_X=SHAFT_LENGTH, Size_Y=SHAFT_WIDTH,
                  Vertices_X=2, Vertices_Y=2)
    shaft_move = _node(nodes, 'GeometryNodeTransform', (x + 200, y),
                       Translation=(SHAFT_LENGTH / 2.0, 0.0, 0.0))
    head = _node(nodes, 'GeometryNodeMeshCircle', (x, y - 200), Vertices=3, Radius=HEAD_RADIUS)
    head.fill_type = 'NGON'
    # The circle's first vertex is on +x: the tip, at x = 1.
    head_move = _node(nodes, 'GeometryNodeTransform', (x + 200, y - 200),
                      Translation=(1.0 - HEAD_RADIUS, 0.0, 0.0))
    dot = _node(nodes, 'GeometryNodeMeshCircle', (x, y - 400), Vertices=24, Radius=DOT_RADIUS)
    dot.fill_type = 'NGON'
    join = _node(nodes, 'GeometryNodeJoinGeometry', (x + 400, y - 200))
    links.new(shaft.outputs["Mesh"], shaft_move.inputs["Geometry"])
    links.new(head.outputs["Mesh"], head_move.inputs["Geometry"])
    # Joined in reverse order of the sockets' links: dot, head, shaft.
    links.new(shaft_move.outputs["Geometry"], join.inputs["Geometry"])
    links.new(head_move.outputs["Geometry"], join.inputs["Geometry"])
    links.new(dot.outputs["Mesh"], join.inputs["Geometry"])
    return join


def node_group():
    """The shared "Rule Frames" node group, created on first use."""
    for group in bpy.data.node_groups:
        if group.bl_idname == 'GeometryNodeTree' and _is_current(group, NODE_GROUP_VERSION):
            return group
    tree, group_in, group_out = new_geometry_group(
        NODE_GROUP_NAME, {MARKER: NODE_GROUP_VERSION},
        (("Arrow Size", 0.3, 0.0, 10.0), ("Height", 0.5, -1000.0, 1000.0)), io_x=1000)
    nodes, links = tree.nodes, tree.links

    # Selection: nonterminal vertices (symbol > 0).
    symbol = named_float(nodes, "symbol", (-800, -100))
    is_nonterminal = math_node(nodes, 'GREATER_THAN', (-600, -100), 0.5)
    links.new(enabled_output(symbol), is_nonterminal.inputs[0])

    # Rotation: the frame's angle atan2(b, a) about z. Scale: hypot(a, b) x Arrow Size in
    # x and y; z stays 1 so that the arrow's height above the roads is in metres.
    frame_a = named_float(nodes, "frame_a", (-800, -300))
    frame_b = named_float(nodes, "frame_b", (-800, -500))
    angle = math_node(nodes, 'ARCTAN2', (-600, -400))
    links.new(enabled_output(frame_b), angle.inputs[0])
    links.new(enabled_output(frame_a), angle.inputs[1])
    rotation = _node(nodes, 'ShaderNodeCombineXYZ', (-400, -400))
    links.new(angle.outputs[0], rotation.inputs["Z"])
    ab = _node(nodes, 'ShaderNodeCombineXYZ', (-600, -650))
    links.new(enabled_output(frame_a), ab.inputs["X"])
    links.new(enabled_output(frame_b), ab.inputs["Y"])
    length = nodes.new('ShaderNodeVectorMath')
    length.operation = 'LENGTH'
    length.location = (-400, -650)
    links.new(ab.outputs[0], length.inputs[0])
    scaled = math_node(nodes, 'MULTIPLY', (-200, -650))
    links.new(length.outputs["Value"], scaled.inputs[0])
    links.new(group_in.outputs["Arrow Size"], scaled.inputs[1])
    scale = _node(nodes, 'ShaderNodeCombineXYZ', (0, -650), Z=1.0)
    links.new(scaled.outputs[0], scale.inputs["X"])
    links.new(scaled.outputs[0], scale.inputs["Y"])

    arrow = _arrow(nodes, links, (-800, 400))
    lift_offset = _node(nodes, 'ShaderNodeCombineXYZ', (-400, 200))
    links.new(group_in.outputs["Height"], lift_offset.inputs["Z"])
    lift = _node(nodes, 'GeometryNodeTransform', (-200, 400))
    links.new(arrow.outputs["Geometry"], lift.inputs["Geometry"])
    links.new(lift_offset.outputs[0], lift.inputs["Translation"])
    set_material = _node(nodes, 'GeometryNodeSetMaterial', (0, 400))
    links.new(lift.outputs["Geometry"], set_material.inputs["Geometry"])
    links.new(group_in.outputs["Material"], set_material.inputs["Material"])

    instance = _node(nodes, 'GeometryNodeInstanceOnPoints', (300, 0))
    links.new(group_in.outputs["Geometry"], instance.inputs["Points"])
    links.new(is_nonterminal.outputs[0], instance.inputs["Selection"])
    links.new(set_material.outputs["Geometry"], instance.inputs["Instance"])
    links.new(rotation.outputs[0], instance.inputs["Rotation"])
    links.new(scale.outputs[0], instance.inputs["Scale"])

    # The graph itself stays (it is what Edit Mode shows and edits); the arrows join it.
    join = _node(nodes, 'GeometryNodeJoinGeometry', (600, 0))
    links.new(instance.outputs["Instances"], join.inputs["Geometry"])
    links.new(group_in.outputs["Geometry"], join.inputs["Geometry"])
    links.new(join.outputs["Geometry"], group_out.inputs["Geometry"])
    return tree


def material():
    """The shared "Rule Frame" material: the paper's red, slightly emissive so that the
    arrows stay visible in shadow and from far away."""
    for existing in bpy.data.materials:
        if _is_current(existing, MATERIAL_VERSION):
            return existing
    mat = bpy.data.materials.new(MATERIAL_NAME)
    mat[MARKER] = MATERIAL_VERSION
    mat.use_nodes = True
    mat.diffuse_color = (*ARROW_COLOR, 1.0)  # solid view and Workbench
    bsdf = mat.node_tree.nodes.get("Principled BSDF")
    bsdf.inputs["Base Color"].default_value = (*ARROW_COLOR, 1.0)
    bsdf.inputs["Roughness"].default_value = 0.6
    emission = bsdf.inputs.get("Emission Color") or bsdf.inputs.get("Emission")
    if emission is not None:
        emission.default_value = (*ARROW_COLOR, 1.0)
    strength = bsdf.inputs.get("Emission Strength")
    if strength is not None:
        strength.default_value = 0.25
    return mat


def find_modifier(obj):
    """The Rule Frames modifier of ``obj``, else None."""
    return next((m for m in obj.modifiers if m.type == 'NODES' and m.node_group is not None
                 and m.node_group.get(MARKER) is not None), None)


def add_modifier(obj, group, mat):
    """Give ``obj`` the Rule Frames modifier using ``group``, with ``mat`` for the arrows."""
    modifier = obj.modifiers.new(MODIFIER_NAME, 'NODES')
    modifier.node_group = group
    modifier.show_in_editmode = True
    for socket in input_sockets(group):
        if socket.name == "Material":
            modifier[socket.identifier] = mat
    return modifier


def add_to(graph_obj, created):
    """The Rule Frames modifier on ``graph_obj`` (once), with the shared node group and
    material (a data.roads.Created remembers them when they are new); the graph object then
    renders."""
    if find_modifier(graph_obj) is not None:
        return
    add_modifier(graph_obj, created.shared(node_group), created.shared(material))
    graph_obj.hide_render = False
