"""Render a grammar's derivation with the Road Grammar add-on: road surfaces and the red
arrows of the nonterminals' frames (paper Fig. 3).

usage:
  blender -b --factory-startup --python scripts/render_grammar_demo.py -- OUTPUT.png
          [--grammar samples/sierpinski.grammar.json] [--steps 4] [--size PIXELS]
          [--engine eevee|cycles|workbench]

Enables the add-on from addon/ of this repository (the native module comes from
$GGG_MODULE_DIR, by default build/python), loads the grammar, adds its axiom, grows it by
--steps derivation steps and renders it from above with an orthographic camera.
"""

import argparse
import os
import sys
import time
from pathlib import Path

import bpy
from mathutils import Vector

REPO = Path(__file__).resolve().parent.parent
GROUND_COLOR = (0.030, 0.036, 0.042, 1.0)


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    parser = argparse.ArgumentParser(prog="blender -b --python scripts/render_grammar_demo.py --")
    parser.add_argument("output", help="PNG to write")
    parser.add_argument("--grammar", default=str(REPO / "samples" / "sierpinski.grammar.json"),
                        help="grammar file (default: samples/sierpinski.grammar.json)")
    parser.add_argument("--steps", type=int, default=4, help="derivation steps (default: 4)")
    parser.add_argument("--size", type=int, default=1200, help="longer side of the picture in pixels")
    parser.add_argument("--engine", choices=("eevee", "cycles", "workbench"), default="eevee")
    return parser.parse_args(argv)


def _raise(ex):
    raise ex


def enable_addon():
    import addon_utils

    os.environ.setdefault("GGG_MODULE_DIR", str(REPO / "build" / "python"))
    addon_dir = str(REPO / "addon")
    if addon_dir not in sys.path:
        sys.path.insert(0, addon_dir)
    addon_utils.enable("road_grammar", default_set=True, handle_error=_raise)
    if "road_grammar" not in bpy.context.preferences.addons:
        raise SystemExit("error: the road_grammar add-on could not be enabled")


def run(operator, **kwargs):
    result = operator(**kwargs)
    if result != {'FINISHED'}:
        raise SystemExit("error: {} returned {}".format(operator.idname_py(), result))


def world_bounds(objects):
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


def add_camera_and_light(scene, low, high, size):
    width, height = high.x - low.x, high.y - low.y
    camera_data = bpy.data.cameras.new("Top View")
    camera_data.type = 'ORTHO'
    camera_data.ortho_scale = max(width, height) * 1.06
    camera_data.clip_start = 1.0
    camera_data.clip_end = 5000.0
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

    sun = bpy.data.objects.new("Sun", bpy.data.lights.new("Sun", 'SUN'))
    sun.data.energy = 2.5
    sun.rotation_euler = (0.2, 0.1, 0.0)
    scene.collection.objects.link(sun)
    world = scene.world or bpy.data.worlds.new("World")
    scene.world = world
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.15, 0.15, 0.15, 1.0)


def setup_render(scene, engine, output):
    scene.view_settings.view_transform = 'Standard'
    scene.render.image_settings.file_format = 'PNG'
    scene.render.filepath = str(Path(output).resolve())
    if engine == "eevee":
        scene.render.engine = 'BLENDER_EEVEE'
        scene.eevee.taa_render_samples = 8
    elif engine == "cycles":
        scene.render.engine = 'CYCLES'
        scene.cycles.device = 'CPU'
        scene.cycles.samples = 16
        scene.cycles.use_denoising = False
    else:
        scene.render.engine = 'BLENDER_WORKBENCH'
        scene.display.shading.light = 'FLAT'
        scene.display.shading.color_type = 'MATERIAL'


def main():
    args = parse_args()
    started = time.monotonic()
    enable_addon()
    bpy.ops.wm.read_homefile(use_empty=True)
    scene = bpy.context.scene
    run(bpy.ops.roads.load_grammar, filepath=str(Path(args.grammar).resolve()))
    run(bpy.ops.roads.add_axiom)
    graph = bpy.context.active_object
    if args.steps > 0:
        run(bpy.ops.roads.grow, steps=args.steps)
    surface = next(child for child in graph.children if child.get("road_surface"))
    low, high = world_bounds([graph, surface])
    add_ground(scene, low, high)
    add_camera_and_light(scene, low, high, args.size)
    setup_render(scene, args.engine, args.output)
    bpy.ops.render.render(write_still=True)
    print("wrote {} ({} x {} px, {}): {} vertices, {} edges, {:.1f} s".format(
        args.output, scene.render.resolution_x, scene.render.resolution_y, scene.render.engine,
        len(graph.data.vertices), len(graph.data.edges), time.monotonic() - started))


main()
