"""The 3-D city of a road graph: road surfaces, raised blocks with kerbs and sidewalks,
green yards, buildings, ground, sun and sky, all in one collection per city.

The native library draws the ground plan (``ggg.city_layout``): road pieces (a rectangle
per polyline segment, a triangle at each bend, a disc at each junction), the kerb outline
of every block (its planar face minus every road piece that reaches into it), the yard
inside the sidewalk, and building lots cut along the yard's outline. Here the plan becomes
meshes, in layers that never share a height, so nothing flickers:

====================  =========================================================
ground                GROUND_Z, a plane as large as the network and a margin
footpaths, asphalt    PATH_Z and ROAD_Z (asphalt wins where a path meets a road)
blocks                extruded from GROUND_Z to KERB_Z (Geometry Nodes): the
                      sides are the kerbs, the tops the sidewalks
yards                 YARD_Z, flat, inside the sidewalk
buildings             extruded from YARD_Z by their `height` attribute
====================  =========================================================

Block and building heights come from a Geometry Nodes modifier ("City Extrude") that
reads the `height` point attribute, so they can be scaled without rebuilding; the
building heights follow the seeded rule of ``ggg.city_layout``, and the plan is
computed before the scene is touched (``core.city.Plan``).
"""

import math

import bpy
import numpy as np

from ..core.names import CITY_KEY, CITY_PART_KEY
from ..data import mesh as mesh_data
from ..data.roads import road_graph_object, surface_object
from .nodes import enabled_output, input_sockets, math_node, named_float, new_geometry_group
EXTRUDE_GROUP_NAME = "City Extrude"
EXTRUDE_GROUP_VERSION = 2
MATERIAL_VERSION = 1
MARKER = "road_city_version"

GROUND_Z = -0.05
PATH_Z = 0.0
ROAD_Z = 0.03
KERB_Z = 0.15
YARD_Z = 0.18

# Linear RGB.
COLORS = {
    "asphalt": (0.045, 0.045, 0.05),
    "paving": (0.40, 0.33, 0.25),
    "sidewalk": (0.42, 0.42, 0.40),
    "kerb": (0.62, 0.62, 0.60),
    "yard": (0.09, 0.15, 0.05),
    "ground": (0.13, 0.16, 0.08),
    "roof": (0.09, 0.075, 0.07),
}
# Facade colours the `tint` attribute picks from.
WALL_COLORS = (
    (0.78, 0.66, 0.50),
    (0.60, 0.30, 0.20),
    (0.85, 0.84, 0.80),
    (0.52, 0.53, 0.55),
    (0.80, 0.60, 0.32),
    (0.70, 0.72, 0.66),
)


# --- meshes from polygon arrays ----------------------------------------------------------

def polygon_mesh(name, offsets, points_xy, z, point_attributes=None):
    """A mesh of flat n-gons: polygon i through points_xy[offsets[i]:offsets[i+1]] at height
    ``z`` (a number, or one per polygon). Vertices are not shared between polygons."""
    offsets = np.asarray(offsets, dtype=np.int64)
    points_xy = np.asarray(points_xy, dtype=np.float64).reshape(-1, 2)
    counts = np.diff(offsets)
    co = np.empty((len(points_xy), 3), dtype=np.float32)
    co[:, :2] = points_xy
    co[:, 2] = np.repeat(np.broadcast_to(np.asarray(z, dtype=np.float64), counts.shape), counts) if len(counts) else 0.0
    mesh = bpy.data.meshes.new(name)
    mesh.vertices.add(len(co))
    mesh.vertices.foreach_set("co", co.ravel())
    # Polygons share no vertices, so each loop starts its own edge to the next corner: the
    # edges are known, and Blender need not look for shared ones (calc_edges).
    loops = np.arange(len(co), dtype=np.int32)
    following = loops + 1
    if len(counts):
        following[offsets[1:] - 1] = offsets[:-1]
    mesh.edges.add(len(co))
    mesh.edges.foreach_set("vertices", np.column_stack((loops, following)).ravel())
    mesh.loops.add(len(co))
    mesh.loops.foreach_set("vertex_index", loops)
    mesh.loops.foreach_set("edge_index", loops)
    mesh.polygons.add(len(counts))
    mesh.polygons.foreach_set("loop_start", offsets[:-1].astype(np.int32))
    try:
        mesh.polygons.foreach_set("loop_total", counts.astype(np.int32))
    except (AttributeError, TypeError, RuntimeError):
        pass  # Blender 4: loop_total follows from loop_start
    mesh.update()
    for attribute_name, (kind, values) in (point_attributes or {}).items():
        mesh_data.set_attribute(mesh, attribute_name, kind, 'POINT', values)
    return mesh


def set_face_materials(mesh, materials, face_index=None):
    for mat in materials:
        mesh.materials.append(mat)
    if face_index is not None and len(mesh.polygons):
        mesh.polygons.foreach_set("material_index", np.asarray(face_index, dtype=np.int32))


# --- materials and node groups -------------------------------------------------------------

def _principled(name, color, roughness=0.9, markers=None):
    key = "city:" + name
    for existing in bpy.data.materials:
        if existing.get(MARKER) == MATERIAL_VERSION and existing.get("city_material") == key:
            return existing
    mat = bpy.data.materials.new("City " + name.title())
    mat[MARKER] = MATERIAL_VERSION
    mat["city_material"] = key
    mat.use_nodes = True
    mat.diffuse_color = (*color, 1.0)
    bsdf = mat.node_tree.nodes.get("Principled BSDF")
    bsdf.inputs["Base Color"].default_value = (*color, 1.0)
    bsdf.inputs["Roughness"].default_value = roughness
    if "Specular" in bsdf.inputs:
        bsdf.inputs["Specular"].default_value = 0.2
    return mat


def _wall_material():
    key = "city:wall"
    for existing in bpy.data.materials:
        if existing.get(MARKER) == MATERIAL_VERSION and existing.get("city_material") == key:
            return existing
    mat = _principled("wall", WALL_COLORS[0], roughness=0.85)
    mat["city_material"] = key
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    attribute = nodes.new('ShaderNodeAttribute')
    attribute.attribute_type = 'GEOMETRY'
    attribute.attribute_name = "tint"
    attribute.location = (-700, 300)
    ramp = nodes.new('ShaderNodeValToRGB')
    ramp.location = (-450, 300)
    ramp.color_ramp.interpolation = 'CONSTANT'
    elements = ramp.color_ramp.elements
    elements[0].color = (*WALL_COLORS[0], 1.0)
    elements[1].position = 1.0 / len(WALL_COLORS)
    elements[1].color = (*WALL_COLORS[1], 1.0)
    for k in range(2, len(WALL_COLORS)):
        elements.new(k / len(WALL_COLORS)).color = (*WALL_COLORS[k], 1.0)
    links.new(attribute.outputs["Fac"], ramp.inputs["Fac"])
    links.new(ramp.outputs["Color"], nodes["Principled BSDF"].inputs["Base Color"])
    return mat


def materials():
    """{part: material}, shared by every city of the file."""
    found = {name: _principled(name, color) for name, color in COLORS.items()}
    found["asphalt"].node_tree.nodes["Principled BSDF"].inputs["Roughness"].default_value = 0.95
    found["wall"] = _wall_material()
    return found


def extrude_group():
    """"City Extrude": extrude every face up by its `height` point attribute times Height
    Scale; the new sides get the Material input, the tops keep their own material."""
    for group in bpy.data.node_groups:
        if group.bl_idname == 'GeometryNodeTree' and group.get(MARKER) == EXTRUDE_GROUP_VERSION:
            return group
    tree, group_in, group_out = new_geometry_group(
        EXTRUDE_GROUP_NAME, {MARKER: EXTRUDE_GROUP_VERSION}, (("Height Scale", 1.0, 0.0, 100.0),), io_x=700)
    nodes, links = tree.nodes, tree.links
    height = named_float(nodes, "height", (-500, -200))
    scaled = math_node(nodes, 'MULTIPLY', (-300, -200))
    offset = nodes.new('ShaderNodeCombineXYZ')
    offset.location = (-100, -200)
    extrude = nodes.new('GeometryNodeExtrudeMesh')
    extrude.mode = 'FACES'
    extrude.location = (100, 0)
    # Footprints share no vertices, so extruding each face on its own gives the same mesh,
    # three times faster than the connected extrusion.
    extrude.inputs["Individual"].default_value = True
    set_material = nodes.new('GeometryNodeSetMaterial')
    set_material.location = (400, 0)
    links.new(group_in.outputs["Geometry"], extrude.inputs["Mesh"])
    links.new(enabled_output(height), scaled.inputs[0])
    links.new(group_in.outputs["Height Scale"], scaled.inputs[1])
    links.new(scaled.outputs[0], offset.inputs["Z"])
    links.new(offset.outputs[0], extrude.inputs["Offset"])
    links.new(extrude.outputs["Mesh"], set_material.inputs["Geometry"])
    links.new(extrude.outputs["Side"], set_material.inputs["Selection"])
    links.new(group_in.outputs["Material"], set_material.inputs["Material"])
    links.new(set_material.outputs["Geometry"], group_out.inputs["Geometry"])
    return tree


# --- the city --------------------------------------------------------------------------------

def find_collection(graph_obj):
    return next((c for c in bpy.data.collections if c.get(CITY_KEY) == graph_obj.name), None)


def remove_collection(collection):
    """Remove a city collection with its objects and the data only they used."""
    stores = ((bpy.types.Mesh, bpy.data.meshes), (bpy.types.Light, bpy.data.lights),
              (bpy.types.Camera, bpy.data.cameras), (bpy.types.Curve, bpy.data.curves))
    for obj in list(collection.objects):
        data = obj.data
        bpy.data.objects.remove(obj)
        if data is None or data.users:
            continue
        for kind, store in stores:
            if isinstance(data, kind):
                store.remove(data)
                break
    bpy.data.collections.remove(collection)


def build(context, graph_obj, plan, settings):
    """Create the city collection from ``plan``; returns it. Replaces an earlier city of
    the same road graph."""
    old = find_collection(graph_obj)
    if old is not None:
        remove_collection(old)
    name = graph_obj.name + " City"
    collection = bpy.data.collections.new(name)
    collection[CITY_KEY] = graph_obj.name
    context.scene.collection.children.link(collection)
    mats = materials()
    layout = plan.layout
    matrix = graph_obj.matrix_world.copy()

    def add(part, mesh_or_data, obj_name=None):
        obj = bpy.data.objects.new(obj_name or "{} {}".format(graph_obj.name, part.title()), mesh_or_data)
        obj[CITY_PART_KEY] = part
        collection.objects.link(obj)
        if isinstance(mesh_or_data, bpy.types.Mesh):
            obj.matrix_world = matrix
        return obj

    # Ground.
    # Wide enough to reach the horizon of the overview and of a drone's view.
    margin = max(2000.0, 4.0 * float(np.max(plan.high - plan.low)))
    low, high = plan.low - margin, plan.high + margin
    ground = polygon_mesh(graph_obj.name + " Ground", [0, 4],
                          [[low[0], low[1]], [high[0], low[1]], [high[0], high[1]], [low[0], high[1]]], GROUND_Z)
    set_face_materials(ground, [mats["ground"]])
    add("ground", ground)

    # Roads: asphalt above paving.
    is_path = plan.road_is_path
    z = np.where(is_path, PATH_Z, ROAD_Z)
    roads = polygon_mesh(graph_obj.name + " Roads", layout["road_offsets"], layout["road_points"], z)
    set_face_materials(roads, [mats["asphalt"], mats["paving"]], is_path.astype(np.int32))
    mesh_data.set_attribute(roads, "graph_edge", 'INT', 'FACE', layout["road_edge"])
    add("roads", roads)

    # Blocks: kerb outlines raised to the kerb height (sides = kerbs, tops = sidewalks).
    block_offsets = layout["block_offsets"]
    blocks = polygon_mesh(graph_obj.name + " Blocks", block_offsets, layout["block_points"], GROUND_Z,
                          {"height": ('FLOAT', np.full(int(block_offsets[-1]), KERB_Z - GROUND_Z))})
    set_face_materials(blocks, [mats["sidewalk"]])
    mesh_data.set_attribute(blocks, "face", 'INT', 'FACE', layout["block_face"])
    _extrude(add("blocks", blocks), mats["kerb"])

    # Yards.
    yards = polygon_mesh(graph_obj.name + " Yards", layout["yard_offsets"], layout["yard_points"], YARD_Z)
    set_face_materials(yards, [mats["yard"]])
    add("yards", yards)

    # Buildings.
    offsets = layout["building_offsets"]
    counts = np.diff(offsets)
    buildings = polygon_mesh(graph_obj.name + " Buildings", offsets, layout["building_points"], YARD_Z, {
        "height": ('FLOAT', np.repeat(plan.heights, counts)),
        "tint": ('FLOAT', np.repeat(plan.tints, counts)),
    })
    set_face_materials(buildings, [mats["roof"]])
    mesh_data.set_attribute(buildings, "face", 'INT', 'FACE', layout["building_face"])
    _extrude(add("buildings", buildings), mats["wall"])

    # The import's flat surface would lie on the city's roads; the city replaces it.
    surface_obj = surface_object(graph_obj)
    if surface_obj is not None:
        surface_obj.hide_render = True
        if surface_obj.name in context.view_layer.objects:
            surface_obj.hide_set(True)

    # Sun, sky and a camera over the city.
    sun_data = bpy.data.lights.new(graph_obj.name + " Sun", 'SUN')
    sun_data.energy = 4.0
    sun_data.angle = math.radians(1.0)
    sun = add("sun", sun_data)
    sun.rotation_euler = (math.radians(90.0 - settings.sun_elevation), 0.0, math.radians(settings.sun_azimuth))
    setup_world(context.scene, settings)

    centre = matrix @ _vector(((plan.low + plan.high) / 2.0).tolist() + [0.0])
    extent = float(np.max(plan.high - plan.low))
    camera = add("view", bpy.data.cameras.new(graph_obj.name + " View"), graph_obj.name + " View")
    aim_overview(camera, centre, extent)
    if context.scene.camera is None:
        context.scene.camera = camera

    collection["faces"] = plan.face_count
    collection["blocks"] = len(layout["block_face"])
    collection["buildings"] = len(offsets) - 1
    collection["road_pieces"] = len(layout["road_edge"])
    collection["seed"] = settings.seed
    return collection


def _vector(values):
    from mathutils import Vector
    return Vector(values)


def _extrude(obj, side_material):
    group = extrude_group()
    modifier = obj.modifiers.new(EXTRUDE_GROUP_NAME, 'NODES')
    modifier.node_group = group
    for socket in input_sockets(group):
        if socket.name == "Material":
            modifier[socket.identifier] = side_material
    return modifier


def aim_overview(camera, centre, extent):
    """A perspective camera looking down at ``centre`` from the south-east, far enough to
    show a square of ``extent`` metres."""
    from mathutils import Vector
    data = camera.data
    data.lens = 35.0
    distance = max(60.0, 1.05 * extent)
    direction = Vector((0.45, -0.8, 0.5)).normalized()
    camera.location = centre + direction * distance
    camera.rotation_euler = (-direction).to_track_quat('-Z', 'Y').to_euler()
    # A near plane far from the camera keeps depth precision for the cm-thin layers (parks,
    # pavements): the nearest of the city is about a third of the distance away, its farthest
    # under twice it, so the depth range is 1 to 20 rather than 1 to 2,000, and a park does not
    # flicker through the ground of a large town.
    data.clip_start = max(0.5, distance / 10.0)
    data.clip_end = 2.0 * distance + extent


def setup_world(scene, settings):
    """A Nishita sky (Eevee and Cycles) lit from the sun's direction."""
    world = bpy.data.worlds.get("City Sky") or bpy.data.worlds.new("City Sky")
    scene.world = world
    world.use_nodes = True
    nodes, links = world.node_tree.nodes, world.node_tree.links
    background = nodes.get("Background") or nodes.new('ShaderNodeBackground')
    sky = nodes.get("City Sky Texture")
    if sky is None:
        sky = nodes.new('ShaderNodeTexSky')
        sky.name = "City Sky Texture"
        sky.location = (-300, 300)
        links.new(sky.outputs["Color"], background.inputs["Color"])
    sky.sky_type = 'NISHITA'
    sky.sun_disc = False
    sky.sun_elevation = math.radians(settings.sun_elevation)
    sky.sun_rotation = math.radians(settings.sun_azimuth) + math.pi / 2.0
    background.inputs["Strength"].default_value = 0.3
    scene.view_settings.view_transform = 'Filmic'
    scene.view_settings.look = 'High Contrast'
    return world


def city_graph(context):
    """The road graph object of the active object (graph, its surface, or part of its city)."""
    obj = context.active_object
    graph = road_graph_object(obj)
    if graph is None and obj is not None:
        for collection in obj.users_collection:
            name = collection.get(CITY_KEY)
            if name and name in bpy.data.objects:
                return bpy.data.objects[name]
    return graph
