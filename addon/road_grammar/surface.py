"""Road surfaces: widths per edge, and the Geometry Nodes group that turns the edge
polylines into flat ribbons of that width (non-destructive: change the `width`
attribute, the group's inputs or the material, and the surface follows)."""

import bpy
import numpy as np

from . import native

NODE_GROUP_NAME = "Road Surface"
MATERIAL_NAME = "Road Surface"
# Bumped when the node group or material built here changes; older ones are not reused.
NODE_GROUP_VERSION = 1
MATERIAL_VERSION = 1
MARKER = "road_grammar_version"
# The lowest importance rank a node group or material was made for.
RANK_MARKER = "road_grammar_lowest_rank"

# Surface colour per importance rank 1, 2, ... (linear RGB), after the usual map styles:
# motorway red, trunk orange, primary amber, secondary yellow, minor roads light grey,
# paths tan. The ranks themselves come from the native library (ggg.highway_ranks());
# ranks past the end of this table take its last colour.
RANK_COLORS = (
    (0.80, 0.22, 0.20),  # 1 motorway
    (0.90, 0.40, 0.16),  # 2 trunk, motorway links
    (0.95, 0.60, 0.18),  # 3 primary, trunk links
    (0.95, 0.82, 0.30),  # 4 secondary, primary links
    (0.92, 0.90, 0.62),  # 5 tertiary, secondary links
    (0.80, 0.80, 0.78),  # 6 unclassified, tertiary links
    (0.70, 0.70, 0.70),  # 7 residential, road
    (0.62, 0.66, 0.70),  # 8 living street
    (0.50, 0.50, 0.52),  # 9 service, busway
    (0.55, 0.47, 0.38),  # 10 pedestrian, track
    (0.45, 0.36, 0.30),  # 11 footway, cycleway, path, steps
    (0.40, 0.40, 0.40),  # 12 other
)


def lowest_rank():
    """The largest (least important) rank of the native library's highway classes."""
    return int(max(native.load().highway_ranks()))


def rank_color(rank):
    return RANK_COLORS[min(max(int(rank), 1), len(RANK_COLORS)) - 1]


def road_widths(highway, width_tag, lanes, class_widths, lane_width):
    """Width in metres of each edge: its `width` tag if tagged, else lanes x lane width,
    else the default of its class (``class_widths`` is indexed by class code)."""
    highway = np.asarray(highway, dtype=np.int64)
    widths = np.array(width_tag, dtype=np.float64, copy=True)
    lanes = np.asarray(lanes, dtype=np.int64)
    defaults = np.asarray(class_widths, dtype=np.float64)
    tagged = np.isfinite(widths) & (widths > 0.0)
    by_lanes = ~tagged & (lanes > 0)
    widths[by_lanes] = lanes[by_lanes] * float(lane_width)
    rest = ~(tagged | by_lanes)
    widths[rest] = defaults[np.clip(highway[rest], 0, len(defaults) - 1)]
    return widths


# --- node group ----------------------------------------------------------------------

def _new_socket(tree, in_out, socket_type, name):
    """A group input/output socket, on Blender 3.x (tree.inputs) and 4.x (tree.interface)."""
    if hasattr(tree, "interface"):
        return tree.interface.new_socket(name, in_out=in_out, socket_type=socket_type)
    sockets = tree.inputs if in_out == 'INPUT' else tree.outputs
    return sockets.new(socket_type, name)


def _new_geometry_group(name, markers, float_inputs, io_x):
    """A new Geometry Nodes group with the custom properties ``markers`` and the interface
    of the add-on's modifiers: a Geometry input, the float inputs ``float_inputs`` ((name,
    default, min, max), ...), a Material input and a Geometry output. Returns (tree, Group
    Input node at x = -io_x, Group Output node at x = io_x)."""
    tree = bpy.data.node_groups.new(name, 'GeometryNodeTree')
    for key, value in markers.items():
        tree[key] = value
    _new_socket(tree, 'INPUT', 'NodeSocketGeometry', "Geometry")
    for socket_name, default, low, high in float_inputs:
        socket = _new_socket(tree, 'INPUT', 'NodeSocketFloat', socket_name)
        socket.default_value, socket.min_value, socket.max_value = default, low, high
    _new_socket(tree, 'INPUT', 'NodeSocketMaterial', "Material")
    _new_socket(tree, 'OUTPUT', 'NodeSocketGeometry', "Geometry")
    group_in = tree.nodes.new('NodeGroupInput')
    group_in.location = (-io_x, 0)
    group_out = tree.nodes.new('NodeGroupOutput')
    group_out.location = (io_x, 0)
    return tree, group_in, group_out


def _input_sockets(tree):
    if hasattr(tree, "interface"):
        return [item for item in tree.interface.items_tree
                if item.item_type == 'SOCKET' and item.in_out == 'INPUT']
    return list(tree.inputs)


def _enabled_output(node):
    """The first visible output (Named Attribute has one per data type on Blender 3.x)."""
    return next(socket for socket in node.outputs if socket.enabled)


def _named_float(nodes, name, location):
    node = nodes.new('GeometryNodeInputNamedAttribute')
    node.data_type = 'FLOAT'
    node.inputs["Name"].default_value = name
    node.location = location
    return node


def _math(nodes, operation, location, value=None):
    node = nodes.new('ShaderNodeMath')
    node.operation = operation
    node.location = location
    if value is not None:
        node.inputs[1].default_value = value
    return node


def _is_current(datablock, version, lowest):
    return datablock is not None and datablock.get(MARKER) == version and datablock.get(RANK_MARKER) == lowest


def node_group():
    """The shared "Road Surface" node group, created on first use."""
    lowest = lowest_rank()
    for group in bpy.data.node_groups:
        if group.bl_idname == 'GeometryNodeTree' and _is_current(group, NODE_GROUP_VERSION, lowest):
            return group
    tree, group_in, group_out = _new_geometry_group(
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

    width = _named_float(nodes, "width", (-700, -250))
    half = _math(nodes, 'MULTIPLY', (-500, -250), 0.5)
    radius_value = _math(nodes, 'MULTIPLY', (-300, -250))
    radius = nodes.new('GeometryNodeSetCurveRadius')
    radius.location = (-300, 0)

    # Important roads slightly above minor ones: z = step * (lowest rank - rank), so that
    # overlapping ribbons at crossings do not flicker and the main road is drawn on top.
    rank = _named_float(nodes, "rank", (-500, -450))
    lift = _math(nodes, 'SUBTRACT', (-300, -450))
    lift.inputs[0].default_value = float(lowest)
    links.new(_enabled_output(rank), lift.inputs[1])
    lift_clamped = _math(nodes, 'MAXIMUM', (-150, -450), 0.0)
    lift_height = _math(nodes, 'MULTIPLY', (0, -450))
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
    links.new(_enabled_output(width), half.inputs[0])
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
    for socket in _input_sockets(group):
        if socket.name == "Material":
            modifier[socket.identifier] = mat
    return modifier
