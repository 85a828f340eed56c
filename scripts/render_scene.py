"""Scene and render set-up shared by the render scripts (blender_demo.py and
render_grammar_demo.py): their common command-line options, enabling the add-on from
addon/ of this repository, and a top-down picture of some objects (ground, orthographic
camera, sun, world, render settings, credit stamp).

The scripts run as ``blender -b --python scripts/X.py -- args`` and put this folder on
sys.path before importing this module.
"""

import os
import sys
from pathlib import Path

import bpy
from mathutils import Vector

REPO = Path(__file__).resolve().parent.parent

GROUND_COLOR = (0.030, 0.036, 0.042, 1.0)


def script_argv():
    """The script's arguments: those after ``--`` on Blender's command line."""
    return sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []


def add_render_arguments(parser, size):
    """--size (default ``size`` pixels) and --engine."""
    parser.add_argument("--size", type=int, default=size, help="longer side of the picture in pixels")
    parser.add_argument("--engine", choices=("eevee", "cycles", "workbench"), default="eevee")


def _raise(ex):
    raise ex


def enable_addon():
    """Enable the road_grammar add-on from addon/ of this repository (the native module from
    $GGG_MODULE_DIR, by default build/python)."""
    import addon_utils

    os.environ.setdefault("GGG_MODULE_DIR", str(REPO / "build" / "python"))
    addon_dir = str(REPO / "addon")
    if addon_dir not in sys.path:
        sys.path.insert(0, addon_dir)
    addon_utils.enable("road_grammar", default_set=True, handle_error=_raise)
    if "road_grammar" not in bpy.context.preferences.addons:
        raise SystemExit("error: the road_grammar add-on could not be enabled")


def world_bounds(objects):
    """(min corner, max corner) of the evaluated objects in world space."""
    depsgraph = bpy.context.evaluated_depsgraph_get()
    corners = []
    for obj in objects:
        evaluated = obj.evaluated_get(depsgraph)
        corners += [evaluated.matrix_world @ Vector(corner) for corner in evaluated.bound_box]
    low = Vector((min(c.x for c in corners), min(c.y for c in corners), min(c.z for c in corners)))
    high = Vector((max(c.x for c in corners), max(c.y for c in corners), max(c.z for c in corners)))
    return low, high


def add_ground(scene, low, high):
    size = max(high.x - low.x, high.y - low.y) * 1.5
    half = size / 2.0
    mesh = bpy.data.meshes.new("Ground")
    mesh.from_pydata([(-half, -half, 0.0), (half, -half, 0.0), (half, half, 0.0), (-half, half, 0.0)],
                     [], [(0, 1, 2, 3)])
    ground = bpy.data.objects.new("Ground", mesh)
    center = (low + high) / 2.0
    ground.location = (center.x, center.y, low.z - 0.05)
    material = bpy.data.materials.new("Ground")
    material.use_nodes = True
    bsdf = material.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = GROUND_COLOR
    bsdf.inputs["Roughness"].default_value = 1.0
    material.diffuse_color = GROUND_COLOR
    mesh.materials.append(material)
    scene.collection.objects.link(ground)


def add_camera_and_light(scene, low, high, size, *, margin, clip_end):
    """An orthographic camera looking straight down on the box (low, high), showing it
    ``margin`` times as wide; a picture of ``size`` pixels on its longer side; a sun and a
    grey world."""
    width, height = high.x - low.x, high.y - low.y
    camera_data = bpy.data.cameras.new("Top View")
    camera_data.type = 'ORTHO'
    camera_data.ortho_scale = max(width, height) * margin
    camera_data.clip_start = 1.0
    camera_data.clip_end = clip_end
    camera = bpy.data.objects.new("Top View", camera_data)
    camera.location = ((low.x + high.x) / 2.0, (low.y + high.y) / 2.0, high.z + 1000.0)
    scene.collection.objects.link(camera)
    scene.camera = camera

    aspect = width / height if height > 0 else 1.0
    if aspect >= 1.0:
        scene.render.resolution_x, scene.render.resolution_y = size, max(64, round(size / aspect))
    else:
        scene.render.resolution_x, scene.render.resolution_y = max(64, round(size * aspect)), size
    scene.render.resolution_percentage = 100

    sun_data = bpy.data.lights.new("Sun", 'SUN')
    sun_data.energy = 2.5
    sun = bpy.data.objects.new("Sun", sun_data)
    sun.rotation_euler = (0.2, 0.1, 0.0)
    scene.collection.objects.link(sun)

    world = scene.world or bpy.data.worlds.new("World")
    scene.world = world
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.15, 0.15, 0.15, 1.0)
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 1.0


def stamp_credit(scene, text):
    """Burn ``text`` into the picture's top-left corner (and nothing else)."""
    render = scene.render
    render.use_stamp = bool(text)
    if not text:
        return
    for flag in ("date", "time", "render_time", "frame", "frame_range", "memory", "hostname", "camera",
                 "lens", "scene", "marker", "filename", "sequencer_strip", "note"):
        setattr(render, "use_stamp_" + flag, False)
    render.use_stamp_note = True
    render.stamp_note_text = text
    render.stamp_font_size = max(12, scene.render.resolution_y // 60)
    render.stamp_background = (0.0, 0.0, 0.0, 0.5)


def setup_render(scene, engine, output, *, eevee_samples):
    """Render with ``engine`` (eevee, cycles or workbench) to the PNG ``output``."""
    scene.view_settings.view_transform = 'Standard'
    scene.render.image_settings.file_format = 'PNG'
    scene.render.filepath = str(Path(output).resolve())
    if engine == "eevee":
        scene.render.engine = 'BLENDER_EEVEE'
        scene.eevee.taa_render_samples = eevee_samples
    elif engine == "cycles":
        scene.render.engine = 'CYCLES'
        scene.cycles.device = 'CPU'
        scene.cycles.samples = 16
        scene.cycles.use_denoising = False
    else:
        scene.render.engine = 'BLENDER_WORKBENCH'
        scene.display.shading.light = 'FLAT'
        scene.display.shading.color_type = 'MATERIAL'
