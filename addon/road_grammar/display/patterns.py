"""Showing street patterns on a road graph (paper Figs. 13 and 17): colours per edge and
the selection of occurrence vertices.

The colour of each graph edge is the INT edge attribute ``road_pattern`` of the graph
mesh: 0 = none, 1..PALETTE_SIZE = the isogroup with that colour in the overview,
MATCH_SLOT = an occurrence found by Find Similar (or an isogroup without an overview
colour), SEED_SLOT = the seed itself.

A child object of the graph, "<graph> Patterns", draws them: its Geometry Nodes modifier
("Road Patterns") reads the graph's evaluated mesh (Object Info, so it follows Edit Mode
too) and makes every coloured edge a flat ribbon a little above the road surfaces, as
wide as the road (at least **Min Width**), along the road's polyline in the surface
while that still fits the graph (else straight), with one material per colour, so the
colours show in the Solid view (the materials' viewport colours), in Material Preview and
in renders. Being a separate object that cannot be selected in the viewport, it gets no
selection outline when the graph is selected, and it renders while the graph's own edges
do not.

Writing works in Object Mode (bulk foreach_set) and in Edit Mode (through bmesh, so that
an edit-mode undo step restores it).
"""

import collections

import bmesh
import bpy
import numpy as np

from ..core.analysis import StaleAnalysis
from ..core.names import PATTERNS_KEY, SURFACE_EDGE
from ..core.palette import MATCH_SLOT, SLOT_COLORS, SLOT_NAMES, slot_color_linear
from ..core.polylines import segment_polylines
from ..core.topology import EdgeLookup
from ..core.updates import suspended_updates
from ..data import analysis
from ..data import mesh as mesh_data
from ..data import roads
from .nodes import find_socket, input_sockets, new_node, new_socket

ATTRIBUTE = "road_pattern"
NODE_GROUP_NAME = "Road Patterns"
MODIFIER_NAME = "Road Patterns"
OBJECT_KEY = PATTERNS_KEY  # marks the child object that draws the colours
# A surface polyline fits its graph edge when its ends are this close to the edge's vertices.
SURFACE_FIT_M = 0.05
# Colours are drawn this much higher per slot, so two colours meeting at a crossing do not
# flicker (the seed, the highest slot, is on top).
SLOT_STEP_M = 0.004
MATERIAL_PREFIX = "Road Pattern"
MARKER = "road_grammar_patterns_version"
SLOT_MARKER = "road_grammar_pattern_slot"
NODE_GROUP_VERSION = 1
MATERIAL_VERSION = 1


# --- writing colours and selection --------------------------------------------------------

def write(obj, slots, vertex_mask, topology):
    """Set the colour slot of every edge of the road graph ``obj`` (``slots`` (M,)) and,
    when ``vertex_mask`` (N,) is given, select exactly those vertices and the edges between
    them (nothing else). ``topology`` (analysis.MeshTopology) is the graph as it is now.
    Adds (or refreshes) the object that draws the colours."""
    mesh = obj.data
    slots = np.ascontiguousarray(slots, dtype=np.int32)
    edges = np.asarray(topology.edges, dtype=np.int64).reshape(-1, 2)
    if len(slots) != len(edges):
        raise ValueError("{} colours for {} edges".format(len(slots), len(edges)))
    edge_mask = None
    if vertex_mask is not None:
        vertex_mask = np.ascontiguousarray(vertex_mask, dtype=bool)
        edge_mask = vertex_mask[edges[:, 0]] & vertex_mask[edges[:, 1]] if len(edges) else np.zeros(0, dtype=bool)
    polylines = surface_polylines(obj, topology.positions, edges)
    existing = mesh.attributes.get(ATTRIBUTE)
    if existing is not None and (existing.domain != 'EDGE' or existing.data_type != 'INT'):
        mesh.attributes.remove(existing)
    if obj.mode == 'EDIT':
        _write_edit_mesh(mesh, slots, vertex_mask, edge_mask)
    else:
        mesh_data.set_attribute(mesh, ATTRIBUTE, 'INT', 'EDGE', slots)
        if vertex_mask is not None:
            mesh.vertices.foreach_set("select", vertex_mask)
            mesh.edges.foreach_set("select", edge_mask)
            if len(mesh.polygons):
                mesh.polygons.foreach_set("select", _face_mask(mesh, vertex_mask))
        mesh.update()
    ensure_object(obj, polylines, (topology.vertex_count, len(edges)))


# --- the stored analysis shown (data.analysis) -----------------------------------------------

def show_isogroup(obj, index, select=True, only_non_overlapping=False):
    """Colour the occurrences of stored isogroup ``index`` (its overview colour, or the
    match colour when it has none) and select their vertices. Returns (occurrences shown,
    vertices selected)."""
    topology = analysis.check_current(obj)
    result = obj.road_analysis
    if not 0 <= index < len(result.isogroups):
        raise StaleAnalysis("{} has no isogroup {}".format(obj.name, index + 1))
    occurrences, non_overlapping, pattern_edges = analysis.isogroup_arrays(obj, index)
    if only_non_overlapping:
        occurrences = occurrences[non_overlapping]
    slot = result.isogroups[index].color_slot or MATCH_SLOT
    lookup = EdgeLookup(topology.edges, topology.vertex_count)
    slots = np.zeros(len(topology.edges), dtype=np.int32)
    slots[lookup.occurrence_edges(occurrences, pattern_edges).ravel()] = slot
    vertex_mask = None
    if select:
        vertex_mask = np.zeros(topology.vertex_count, dtype=bool)
        vertex_mask[occurrences.ravel()] = True
    write(obj, slots, vertex_mask, topology)
    return len(occurrences), 0 if vertex_mask is None else int(vertex_mask.sum())


def show_overview(obj, count=None):
    """Colour the graph by isogroup (paper Fig. 13): the non-overlapping occurrences of each
    of the first ``count`` coloured isogroups in its own colour, the best ones first (an
    occurrence is coloured only where no better isogroup was). Returns the number of
    occurrences coloured."""
    topology = analysis.check_current(obj)
    result = obj.road_analysis
    lookup = EdgeLookup(topology.edges, topology.vertex_count)
    slots = np.zeros(len(topology.edges), dtype=np.int32)
    shown = 0
    for index, item in enumerate(result.isogroups):
        if item.color_slot <= 0 or (count is not None and item.color_slot > count):
            continue
        occurrences, non_overlapping, pattern_edges = analysis.isogroup_arrays(obj, index)
        if len(pattern_edges) == 0 or len(non_overlapping) == 0:
            continue
        edge_ids = lookup.occurrence_edges(occurrences[non_overlapping], pattern_edges)
        # Non-overlapping occurrences share no vertex, hence no edge: testing them all at
        # once against the colours so far is exact.
        free = (slots[edge_ids] == 0).all(axis=1)
        slots[edge_ids[free].ravel()] = item.color_slot
        shown += int(free.sum())
    write(obj, slots, None, topology)
    with suspended_updates():
        result.active_index = -1
    return shown


def surface_polylines(graph_obj, positions, edges):
    """(points, segments, graph edge of each segment, width of each segment) of the road
    surface of ``graph_obj`` when it still fits the graph (``positions``, ``edges``): every
    edge has a polyline, from its first vertex to its second. Else None (e.g. no surface, or
    vertices or edges edited since it was built): the colours are then drawn straight."""
    surface_obj = roads.surface_object(graph_obj)
    if surface_obj is None or surface_obj.type != 'MESH':
        return None
    mesh = surface_obj.data
    for name, kind in ((SURFACE_EDGE, 'INT'), ("width", 'FLOAT')):
        attribute = mesh.attributes.get(name)
        if attribute is None or attribute.domain != 'EDGE' or attribute.data_type != kind:
            return None
    points = mesh_data.positions_xy(mesh)
    segments = mesh_data.edge_vertices(mesh)
    owner = mesh_data.read_attribute(mesh, SURFACE_EDGE, np.int64)
    width = mesh_data.read_attribute(mesh, "width", np.float64)
    edge_count = len(edges)
    if edge_count == 0 or len(owner) == 0 or owner.min() < 0 or owner.max() >= edge_count:
        return None
    offsets, line_points = segment_polylines(points, segments, owner, edge_count)
    if np.any(np.diff(offsets) < 2):
        return None
    positions = np.asarray(positions, dtype=np.float64)
    ends_fit = (np.linalg.norm(line_points[offsets[:-1]] - positions[edges[:, 0]], axis=1) < SURFACE_FIT_M) & \
               (np.linalg.norm(line_points[offsets[1:] - 1] - positions[edges[:, 1]], axis=1) < SURFACE_FIT_M)
    if not np.all(ends_fit):
        return None
    return points, segments, owner, width


def _face_mask(mesh, vertex_mask):
    loops = np.empty(len(mesh.loops), dtype=np.int64)
    mesh.loops.foreach_get("vertex_index", loops)
    starts = np.empty(len(mesh.polygons), dtype=np.int64)
    mesh.polygons.foreach_get("loop_start", starts)
    return np.logical_and.reduceat(vertex_mask[loops], starts) if len(loops) else np.zeros(len(starts), dtype=bool)


def _write_edit_mesh(mesh, slots, vertex_mask, edge_mask):
    bm = bmesh.from_edit_mesh(mesh)
    if len(bm.edges) != len(slots):
        raise ValueError("the edit mesh has {} edges, not {}".format(len(bm.edges), len(slots)))
    layer = bm.edges.layers.int.get(ATTRIBUTE) or bm.edges.layers.int.new(ATTRIBUTE)
    for edge, slot in zip(bm.edges, slots.tolist()):
        edge[layer] = slot
    if vertex_mask is not None:
        # Deselecting a face or an edge deselects its vertices too, so: everything off,
        # then the vertices, then the edges and faces whose vertices are all on.
        for face in bm.faces:
            face.select = False
        for edge in bm.edges:
            edge.select = False
        for vertex, selected in zip(bm.verts, vertex_mask.tolist()):
            vertex.select = selected
        for edge, selected in zip(bm.edges, edge_mask.tolist()):
            if selected:
                edge.select = True
        bm.verts.index_update()
        for face in bm.faces:
            if all(vertex_mask[v.index] for v in face.verts):
                face.select = True
        bm.select_history.clear()
    bmesh.update_edit_mesh(mesh, loop_triangles=False, destructive=False)


def read_slots(obj):
    """The colour slot of every edge of ``obj`` (zeros without the attribute); Object Mode."""
    mesh = obj.data
    attribute = mesh.attributes.get(ATTRIBUTE)
    if attribute is None or attribute.domain != 'EDGE' or attribute.data_type != 'INT':
        return np.zeros(len(mesh.edges), dtype=np.int64)
    return mesh_data.read_attribute(mesh, ATTRIBUTE, np.int64)


def clear(obj):
    """Remove the colours (the attribute and the object that draws them) from the road
    graph ``obj``."""
    mesh = obj.data
    if obj.mode == 'EDIT':
        bm = bmesh.from_edit_mesh(mesh)
        layer = bm.edges.layers.int.get(ATTRIBUTE)
        if layer is not None:
            bm.edges.layers.int.remove(layer)
        bmesh.update_edit_mesh(mesh, loop_triangles=False, destructive=False)
    else:
        attribute = mesh.attributes.get(ATTRIBUTE)
        if attribute is not None:
            mesh.attributes.remove(attribute)
        mesh.update()
    child = patterns_object(obj)
    if child is not None:
        remove_child(child)


# --- the object, its node group and the materials -------------------------------------------

def new_child(graph_obj, name, key):
    """A new mesh object ``name`` marked ``key`` that draws for ``graph_obj``: its child at its
    origin, in its collections, that cannot be selected in the viewport (clicks select the
    graph, and no selection outline covers the drawing)."""
    child = bpy.data.objects.new(name, bpy.data.meshes.new(name))
    child[key] = 1
    child.parent = graph_obj
    child.hide_select = True
    for collection in graph_obj.users_collection or (bpy.context.scene.collection,):
        collection.objects.link(child)
    return child


def remove_child(child):
    """Remove the object ``child`` made by new_child, and its mesh when nothing else uses it."""
    child_mesh = child.data
    bpy.data.objects.remove(child)
    if child_mesh is not None and child_mesh.users == 0:
        bpy.data.meshes.remove(child_mesh)


def patterns_object(graph_obj):
    """The child of ``graph_obj`` that draws its pattern colours, else None."""
    return next((child for child in graph_obj.children if child.get(OBJECT_KEY)), None)


def find_modifier(obj):
    """The Road Patterns modifier of ``obj`` (a patterns object), else None."""
    return next((m for m in obj.modifiers if m.type == 'NODES' and m.node_group is not None
                 and m.node_group.get(MARKER) is not None), None)


def ensure_object(graph_obj, polylines=None, counts=(0, 0)):
    """The patterns object of ``graph_obj``: made once, a child at the graph's origin in the
    graph's collections, with the Road Patterns modifier reading the graph. ``polylines``
    (from surface_polylines, for the graph with ``counts`` = (vertices, edges)) become its
    mesh, so the colours follow the roads' curves; without them it draws the graph's
    straight edges."""
    child = patterns_object(graph_obj)
    if child is None:
        child = new_child(graph_obj, graph_obj.name + " Patterns", OBJECT_KEY)
    if polylines is None:
        child.data.clear_geometry()
    else:
        points, segments, owner, width = polylines
        mesh_data.fill_edge_mesh(child.data, points, segments,
                                  {SURFACE_EDGE: ('INT', owner), "width": ('FLOAT', width)})
    child.data.update()
    modifier = find_modifier(child)
    if modifier is None or modifier.node_group.get(MARKER) != NODE_GROUP_VERSION:
        if modifier is not None:
            child.modifiers.remove(modifier)
        modifier = child.modifiers.new(MODIFIER_NAME, 'NODES')
        modifier.node_group = node_group()
    graph_input = modifier_input(modifier, "Graph")
    if modifier.get(graph_input) != graph_obj:
        modifier[graph_input] = graph_obj
    modifier[modifier_input(modifier, "Follow Surface")] = polylines is not None
    modifier[modifier_input(modifier, "Graph Vertices")] = counts[0] if polylines else 0
    modifier[modifier_input(modifier, "Graph Edges")] = counts[1] if polylines else 0
    child.update_tag()
    return child


def modifier_input(modifier, name):
    """The identifier of the node group input ``name`` of ``modifier``."""
    return next(socket.identifier for socket in input_sockets(modifier.node_group) if socket.name == name)


def material(slot):
    """The shared material of colour slot ``slot`` ("Road Pattern 1", ..., "Road Pattern
    Seed"): the colour, slightly emissive so that it reads in shadow and from far away."""
    for existing in bpy.data.materials:
        if existing.get(MARKER) == MATERIAL_VERSION and existing.get(SLOT_MARKER) == slot:
            return existing
    color = (*slot_color_linear(slot), 1.0)
    mat = bpy.data.materials.new("{} {}".format(MATERIAL_PREFIX, SLOT_NAMES[slot - 1]))
    mat[MARKER] = MATERIAL_VERSION
    mat[SLOT_MARKER] = slot
    mat.diffuse_color = color  # Solid view and Workbench
    mat.use_nodes = True
    bsdf = mat.node_tree.nodes.get("Principled BSDF")
    bsdf.inputs["Base Color"].default_value = color
    bsdf.inputs["Roughness"].default_value = 0.7
    emission = bsdf.inputs.get("Emission Color") or bsdf.inputs.get("Emission")
    if emission is not None:
        emission.default_value = color
    strength = bsdf.inputs.get("Emission Strength")
    if strength is not None:
        strength.default_value = 0.6
    return mat


Ribbons = collections.namedtuple("Ribbons", "points rotation scale quad")


def edge_ribbons(tree, group_in, geometry, x):
    """Nodes of ``tree`` that make every edge of the mesh ``geometry`` (a socket) a point at
    its middle (the Mesh to Points node ``points``) with the ``rotation`` and ``scale``
    (sockets) that turn a unit ``quad`` (a socket) into the edge's ribbon: along the edge (its
    direction is captured on the edges), (length + width) x width, the width being the
    edge's ``width`` attribute times Width Scale, at least Min Width (inputs of the group,
    ``group_in``); the extra length covers the corners. ``x`` shifts the nodes' places."""
    nodes, links = tree.nodes, tree.links
    edge_vertices = new_node(nodes, 'GeometryNodeInputMeshEdgeVertices', (x - 1200, -500))
    direction = new_node(nodes, 'ShaderNodeVectorMath', (x - 1000, -500), operation='SUBTRACT')
    links.new(edge_vertices.outputs["Position 2"], direction.inputs[0])
    links.new(edge_vertices.outputs["Position 1"], direction.inputs[1])
    capture = new_node(nodes, 'GeometryNodeCaptureAttribute', (x - 800, 0), data_type='FLOAT_VECTOR', domain='EDGE')
    links.new(geometry, capture.inputs["Geometry"])
    links.new(direction.outputs["Vector"], find_socket(capture.inputs, "Value", 'VECTOR'))
    points = new_node(nodes, 'GeometryNodeMeshToPoints', (x - 600, 0), mode='EDGES')
    links.new(capture.outputs["Geometry"], points.inputs["Mesh"])

    # On the points: angle, length and width of the ribbon.
    captured = find_socket(capture.outputs, "Attribute", 'VECTOR')
    xyz = new_node(nodes, 'ShaderNodeSeparateXYZ', (x - 600, -300))
    links.new(captured, xyz.inputs[0])
    angle = new_node(nodes, 'ShaderNodeMath', (x - 400, -300), operation='ARCTAN2')
    links.new(xyz.outputs["Y"], angle.inputs[0])
    links.new(xyz.outputs["X"], angle.inputs[1])
    rotation = new_node(nodes, 'ShaderNodeCombineXYZ', (x - 200, -300))
    links.new(angle.outputs[0], rotation.inputs["Z"])
    length = new_node(nodes, 'ShaderNodeVectorMath', (x - 400, -500), operation='LENGTH')
    links.new(captured, length.inputs[0])
    width = new_node(nodes, 'GeometryNodeInputNamedAttribute', (x - 600, -700), data_type='FLOAT')
    width.inputs["Name"].default_value = "width"
    scaled = new_node(nodes, 'ShaderNodeMath', (x - 400, -700), operation='MULTIPLY')
    links.new(find_socket(width.outputs, "Attribute"), scaled.inputs[0])
    links.new(group_in.outputs["Width Scale"], scaled.inputs[1])
    ribbon_width = new_node(nodes, 'ShaderNodeMath', (x - 200, -700), operation='MAXIMUM')
    links.new(scaled.outputs[0], ribbon_width.inputs[0])
    links.new(group_in.outputs["Min Width"], ribbon_width.inputs[1])
    ribbon_length = new_node(nodes, 'ShaderNodeMath', (x - 200, -500), operation='ADD')
    links.new(length.outputs["Value"], ribbon_length.inputs[0])
    links.new(ribbon_width.outputs[0], ribbon_length.inputs[1])
    scale = new_node(nodes, 'ShaderNodeCombineXYZ', (x, -500))
    scale.inputs["Z"].default_value = 1.0
    links.new(ribbon_length.outputs[0], scale.inputs["X"])
    links.new(ribbon_width.outputs[0], scale.inputs["Y"])

    # The unit quad.
    quad = new_node(nodes, 'GeometryNodeMeshGrid', (x - 600, 400))
    quad.inputs["Size X"].default_value = 1.0
    quad.inputs["Size Y"].default_value = 1.0
    quad.inputs["Vertices X"].default_value = 2
    quad.inputs["Vertices Y"].default_value = 2
    return Ribbons(points, rotation.outputs[0], scale.outputs[0], quad.outputs["Mesh"])


def raised_instances(tree, group_in, join, points, mesh, mat, lift, scale, rotation, y, slot_field=None, slot=None):
    """Nodes of ``tree`` that instance ``mesh`` (a socket; material ``mat``, raised by the
    group's Height + ``lift``) on the ``points`` (a socket) whose INT ``slot_field`` is
    ``slot`` (every point when ``slot`` is None), scaled by ``scale`` and turned by
    ``rotation`` (sockets; None: not turned), into the Join Geometry node ``join``; the
    nodes stand in the row ``y``."""
    nodes, links = tree.nodes, tree.links
    height = new_node(nodes, 'ShaderNodeMath', (-200, y), operation='ADD')
    links.new(group_in.outputs["Height"], height.inputs[0])
    height.inputs[1].default_value = lift
    offset = new_node(nodes, 'ShaderNodeCombineXYZ', (0, y))
    links.new(height.outputs[0], offset.inputs["Z"])
    raised = new_node(nodes, 'GeometryNodeTransform', (200, y))
    links.new(mesh, raised.inputs["Geometry"])
    links.new(offset.outputs[0], raised.inputs["Translation"])
    set_material = new_node(nodes, 'GeometryNodeSetMaterial', (400, y))
    set_material.inputs["Material"].default_value = mat
    links.new(raised.outputs["Geometry"], set_material.inputs["Geometry"])
    is_slot = None
    if slot is not None:
        is_slot = new_node(nodes, 'FunctionNodeCompare', (400, y - 150), data_type='INT', operation='EQUAL')
        links.new(slot_field, find_socket(is_slot.inputs, "A", 'INT'))
        find_socket(is_slot.inputs, "B", 'INT').default_value = slot
    instance = new_node(nodes, 'GeometryNodeInstanceOnPoints', (700, y))
    links.new(points, instance.inputs["Points"])
    if is_slot is not None:
        links.new(find_socket(is_slot.outputs, "Result"), instance.inputs["Selection"])
    links.new(set_material.outputs["Geometry"], instance.inputs["Instance"])
    if rotation is not None:
        links.new(rotation, instance.inputs["Rotation"])
    links.new(scale, instance.inputs["Scale"])
    links.new(instance.outputs["Instances"], join.inputs["Geometry"])


def node_group():
    """The shared "Road Patterns" node group, created on first use.

    With **Follow Surface**, the object's own mesh (a copy of the road surface's
    polylines, each segment with its `graph_edge` and `width`) is drawn, each segment in the
    colour of its graph edge, read from the **Graph** object's mesh (Sample Index of
    `road_pattern` at `graph_edge`): so the colours follow the roads' curves and still come
    from the graph, also in Edit Mode. Without it, or when the graph no longer has the
    **Graph Vertices** and **Graph Edges** it had when the copy was made, the graph's own
    (straight) edges are drawn. Every coloured edge or segment becomes one point at its middle carrying its
    direction, length and width; a unit quad, raised by Height (and a little more per
    colour) and with the material of its colour, is instanced on it, turned along it and
    scaled to (length + width) x width (the extra length covers the corners)."""
    for group in bpy.data.node_groups:
        if group.bl_idname == 'GeometryNodeTree' and group.get(MARKER) == NODE_GROUP_VERSION:
            return group
    tree = bpy.data.node_groups.new(NODE_GROUP_NAME, 'GeometryNodeTree')
    tree[MARKER] = NODE_GROUP_VERSION
    new_socket(tree, 'INPUT', 'NodeSocketGeometry', "Geometry")  # the surface polylines, or nothing
    new_socket(tree, 'INPUT', 'NodeSocketObject', "Graph")
    new_socket(tree, 'INPUT', 'NodeSocketBool', "Follow Surface")
    for name in ("Graph Vertices", "Graph Edges"):
        socket = new_socket(tree, 'INPUT', 'NodeSocketInt', name)
        socket.default_value, socket.min_value = 0, 0
    for name, default, low, high in (("Width Scale", 1.0, 0.0, 10.0), ("Min Width", 4.0, 0.0, 1000.0),
                                     ("Height", 0.4, -1000.0, 1000.0)):
        socket = new_socket(tree, 'INPUT', 'NodeSocketFloat', name)
        socket.default_value, socket.min_value, socket.max_value = default, low, high
    new_socket(tree, 'OUTPUT', 'NodeSocketGeometry', "Geometry")
    nodes, links = tree.nodes, tree.links
    group_in = new_node(nodes, 'NodeGroupInput', (-2000, 0))
    group_out = new_node(nodes, 'NodeGroupOutput', (1400, 0))
    graph = new_node(nodes, 'GeometryNodeObjectInfo', (-1800, 300), transform_space='ORIGINAL')
    links.new(group_in.outputs["Graph"], graph.inputs["Object"])

    # The surface polylines with the colour of their graph edge stored on each segment.
    pattern = new_node(nodes, 'GeometryNodeInputNamedAttribute', (-1800, -300), data_type='INT')
    pattern.inputs["Name"].default_value = ATTRIBUTE
    owner = new_node(nodes, 'GeometryNodeInputNamedAttribute', (-1800, -450), data_type='INT')
    owner.inputs["Name"].default_value = SURFACE_EDGE
    sample = new_node(nodes, 'GeometryNodeSampleIndex', (-1600, -300), data_type='INT', domain='EDGE')
    links.new(graph.outputs["Geometry"], sample.inputs["Geometry"])
    links.new(find_socket(pattern.outputs, "Attribute"), find_socket(sample.inputs, "Value", 'INT'))
    links.new(find_socket(owner.outputs, "Attribute"), sample.inputs["Index"])
    store = new_node(nodes, 'GeometryNodeStoreNamedAttribute', (-1400, 0), data_type='INT', domain='EDGE')
    store.inputs["Name"].default_value = ATTRIBUTE
    links.new(group_in.outputs["Geometry"], store.inputs["Geometry"])
    links.new(find_socket(sample.outputs, "Value", 'INT'), find_socket(store.inputs, "Value", 'INT'))
    # The copy fits the graph only while it has the vertex and edge counts it had when the
    # copy was made (a grow or a topology edit changes them; the colours are then drawn
    # straight until they are written again).
    size = new_node(nodes, 'GeometryNodeAttributeDomainSize', (-1600, 500), component='MESH')
    links.new(graph.outputs["Geometry"], size.inputs["Geometry"])
    follow = group_in.outputs["Follow Surface"]
    for count, name in (("Point Count", "Graph Vertices"), ("Edge Count", "Graph Edges")):
        same = new_node(nodes, 'FunctionNodeCompare', (-1400, 500), data_type='INT', operation='EQUAL')
        links.new(size.outputs[count], find_socket(same.inputs, "A", 'INT'))
        links.new(group_in.outputs[name], find_socket(same.inputs, "B", 'INT'))
        both = new_node(nodes, 'FunctionNodeBooleanMath', (-1300, 400), operation='AND')
        links.new(follow, both.inputs[0])
        links.new(find_socket(same.outputs, "Result"), both.inputs[1])
        follow = both.outputs[0]
    lines = new_node(nodes, 'GeometryNodeSwitch', (-1200, 200), input_type='GEOMETRY')
    links.new(follow, find_socket(lines.inputs, "Switch", 'BOOLEAN'))
    links.new(graph.outputs["Geometry"], find_socket(lines.inputs, "False", 'GEOMETRY'))
    links.new(store.outputs["Geometry"], find_socket(lines.inputs, "True", 'GEOMETRY'))

    # Coloured edges -> points carrying their ribbon's rotation and scale.
    coloured = new_node(nodes, 'FunctionNodeCompare', (-1000, -300), data_type='INT', operation='GREATER_THAN')
    links.new(find_socket(pattern.outputs, "Attribute"), find_socket(coloured.inputs, "A", 'INT'))
    find_socket(coloured.inputs, "B", 'INT').default_value = 0
    ribbons = edge_ribbons(tree, group_in, find_socket(lines.outputs, "Output", 'GEOMETRY'), 0)
    links.new(find_socket(coloured.outputs, "Result"), ribbons.points.inputs["Selection"])

    # One instancing per colour, each with its material and height.
    join = new_node(nodes, 'GeometryNodeJoinGeometry', (1100, 0))
    for slot in range(len(SLOT_COLORS), 0, -1):
        raised_instances(tree, group_in, join, ribbons.points.outputs["Points"], ribbons.quad, material(slot),
                         SLOT_STEP_M * slot, ribbons.scale, ribbons.rotation, 800 - 260 * slot,
                         find_socket(pattern.outputs, "Attribute"), slot)
    links.new(join.outputs["Geometry"], group_out.inputs["Geometry"])
    return tree
