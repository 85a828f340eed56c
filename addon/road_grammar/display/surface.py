"""Road surfaces: the Geometry Nodes group that turns the edge polylines into flat ribbons
of their width (non-destructive: change the `width` attribute, the group's inputs or the
material, and the surface follows), and its material, coloured by importance. (The widths
themselves: core.widths.)"""

import bpy

from ..core import native
from ..core.palette import rank_color
from .nodes import enabled_output, input_sockets, math_node, named_float, new_geometry_group

NODE_GROUP_NAME = "Road Surface"
MATERIAL_NAME = "Road Surface"
# Bumped when the node group or material built here changes; older ones are not reused.
NODE_GROUP_VERSION = 1
MATERIAL_VERSION = 1
MARKER = "road_grammar_version"
# The lowest importance rank a node group or material was made for.
RANK_MARKER = "road_grammar_lowest_rank"


def lowest_rank():
    """The largest (least important) rank of the native library's highway classes."""
    return int(max(native.load().highway_ranks()))


def _is_current(datablock, version, lowest):
    return datablock is not None and datablock.get(MARKER) == version and datablock.get(RANK_MARKER) == lowest


def node_group():
    """The shared "Road Surface" node group, created on first use."""
    lowest = lowest_rank()
    for group in bpy.data.node_groups:
        if group.bl_idname == 'GeometryNodeTree' and _is_current(group, NODE_GROUP_VERSION, lowest):
            return group
    tree, group_in, group_out = new_geometry_group(
        NODE_GROUP_NAME, {MARKER: NODE_GROUP_VERSION, RANK_MARKER: lowest},
        (("Width Scale", 1.0, 0.0, 10.0), ("Layer Step", 0.02, 0.0, 1.0)), io_x=900)
    nodes, links = tree.nodes, tree.links

    # Each edge polyline of the mesh becomes a curve; its `width` edge attribute arrives on
    # the curve points.
    to_curve = nodes.new('GeometryNodeMeshToCurve')
    to_curve.location = (-700, 0)
    # Normals in the XY plane (Z up), so that the profile below lies flat, not upright.
    normal = nodes.new('GeometryNodeSetCurveNormal')
    normal.mode = 'Z_UP'
    normal.location = (-500, 0)

    width = named_float(nodes, "width", (-700, -250))
    half = math_node(nodes, 'MULTIPLY', (-500, -250), 0.5)
    radius_value = math_node(nodes, 'MULTIPLY', (-300, -250))
    radius = nodes.new('GeometryNodeSetCurveRadius')
    radius.location = (-300, 0)

    # Important roads slightly above minor ones: z = step * (lowest rank - rank), so that
    # overlapping ribbons at crossings do not flicker and the main road is drawn on top.
    rank = named_float(nodes, "rank", (-500, -450))
    lift = math_node(nodes, 'SUBTRACT', (-300, -450))
    lift.inputs[0].default_value = float(lowest)
    links.new(enabled_output(rank), lift.inputs[1])
    lift_clamped = math_node(nodes, 'MAXIMUM', (-150, -450), 0.0)
    lift_height = math_node(nodes, 'MULTIPLY', (0, -450))
    offset = nodes.new('ShaderNodeCombineXYZ')
    offset.location = (150, -450)
    lift_position = nodes.new('GeometryNodeSetPosition')
    lift_position.location = (-100, 0)

    profile = nodes.new('GeometryNodeCurvePrimitiveLine')
    profile.location = (100, -200)
    profile.inputs["Start"].default_value = (-1.0, 0.0, 0.0)
    profile.inputs["End"].default_value = (1.0, 0.0, 0.0)
    to_mesh = nodes.new('GeometryNodeCurveToMesh')
    to_mesh.location = (300, 0)
    set_material = nodes.new('GeometryNodeSetMaterial')
    set_material.location = (600, 0)

    links.new(group_in.outputs["Geometry"], to_curve.inputs["Mesh"])
    links.new(to_curve.outputs["Curve"], normal.inputs["Curve"])
    links.new(normal.outputs["Curve"], radius.inputs["Curve"])
    links.new(enabled_output(width), half.inputs[0])
    links.new(half.outputs[0], radius_value.inputs[0])
    links.new(group_in.outputs["Width Scale"], radius_value.inputs[1])
    links.new(radius_value.outputs[0], radius.inputs["Radius"])
    links.new(radius.outputs["Curve"], lift_position.inputs["Geometry"])
    links.new(lift.outputs[0], lift_clamped.inputs[0])
    links.new(lift_clamped.outputs[0], lift_height.inputs[0])
    links.new(group_in.outputs["Layer Step"], lift_height.inputs[1])
    links.new(lift_height.outputs[0], offset.inputs["Z"])
    links.new(offset.outputs[0], lift_position.inputs["Offset"])
    links.new(lift_position.outputs["Geometry"], to_mesh.inputs["Curve"])
    links.new(profile.outputs["Curve"], to_mesh.inputs["Profile Curve"])
    if "Scale" in to_mesh.inputs:
        # Newer Blender scales the profile by this input instead of the curve radius.
        radius_read = nodes.new('GeometryNodeInputRadius')
        radius_read.location = (100, -350)
        links.new(radius_read.outputs[0], to_mesh.inputs["Scale"])
    links.new(to_mesh.outputs["Mesh"], set_material.inputs["Geometry"])
    links.new(group_in.outputs["Material"], set_material.inputs["Material"])
    links.new(set_material.outputs["Geometry"], group_out.inputs["Geometry"])
    return tree


def material():
    """The shared "Road Surface" material: colour by road importance (`rank` attribute)."""
    lowest = lowest_rank()
    for existing in bpy.data.materials:
        if _is_current(existing, MATERIAL_VERSION, lowest):
            return existing
    mat = bpy.data.materials.new(MATERIAL_NAME)
    mat[MARKER] = MATERIAL_VERSION
    mat[RANK_MARKER] = lowest
    mat.use_nodes = True
    mat.diffuse_color = (*rank_color(7), 1.0)  # solid view and Workbench: a minor road
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    bsdf = nodes.get("Principled BSDF")
    bsdf.inputs["Roughness"].default_value = 0.8
    attribute = nodes.new('ShaderNodeAttribute')
    attribute.attribute_type = 'GEOMETRY'
    attribute.attribute_name = "rank"
    attribute.location = (-900, 300)
    to_fraction = nodes.new('ShaderNodeMath')
    to_fraction.operation = 'DIVIDE'
    to_fraction.inputs[1].default_value = float(lowest)
    to_fraction.location = (-700, 300)
    ramp = nodes.new('ShaderNodeValToRGB')
    ramp.location = (-500, 300)
    ramp.color_ramp.interpolation = 'CONSTANT'
    elements = ramp.color_ramp.elements
    # Element k covers fractions from (k - 0.5) / lowest, so rank k / lowest hits it.
    elements[0].position = 0.0
    elements[0].color = (*rank_color(1), 1.0)
    elements[1].position = 1.5 / lowest
    elements[1].color = (*rank_color(2), 1.0)
    for k in range(3, lowest + 1):
        element = elements.new((k - 0.5) / lowest)
        element.color = (*rank_color(k), 1.0)
    links.new(attribute.outputs["Fac"], to_fraction.inputs[0])
    links.new(to_fraction.outputs[0], ramp.inputs["Fac"])
    links.new(ramp.outputs["Color"], bsdf.inputs["Base Color"])
    return mat


def add_modifier(obj, group, mat):
    """Give ``obj`` the surface modifier using ``group``, with ``mat`` as its material."""
    modifier = obj.modifiers.new(NODE_GROUP_NAME, 'NODES')
    modifier.node_group = group
    for socket in input_sockets(group):
        if socket.name == "Material":
            modifier[socket.identifier] = mat
    return modifier


def add_to(surface_obj, created):
    """The surface modifier on ``surface_obj``, with the shared node group and material (a
    data.roads.Created remembers them when they are new)."""
    add_modifier(surface_obj, created.shared(node_group), created.shared(material))
