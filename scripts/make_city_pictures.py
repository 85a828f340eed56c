"""The pictures of the user guide's city chapter (docs/user-guide.md), made with the add-on's
operators on the bundled sample town (and on a real extract when it is there).

  GGG_MODULE_DIR=build/python blender -b --factory-startup --python scripts/make_city_pictures.py -- \
      --out-dir docs/figures [--osm ../shared/osm/paris_marais.osm.pbf]

Writes city_overview.png (Build City, the view camera), city_closeup.png (kerbs, sidewalks
and junctions from close by), city_flythrough.png (the tour of Fly-Through drawn on the city
from above), city_street.png (a frame of a street-level fly-through, Render City) and, with
--osm, city_<name>.png. PNGs are reduced to 256 colours to stay small.
"""

import argparse
import math
import sys
from pathlib import Path

import bpy
import numpy as np
from mathutils import Vector

sys.path.insert(0, str(Path(__file__).resolve().parent))
import render_scene  # noqa: E402

SIZE = (960, 540)


def parse_args():
    parser = argparse.ArgumentParser(prog="make_city_pictures.py")
    parser.add_argument("--out-dir", required=True)
    parser.add_argument("--osm", help="a real extract for one more picture (credited to OpenStreetMap)")
    parser.add_argument("--samples", type=int, default=16)
    return parser.parse_args(render_scene.script_argv())


def ok(result):
    if result != {'FINISHED'}:
        raise SystemExit("error: {}".format(result))


def town(path, seed=1, highways='ALL'):
    bpy.ops.wm.read_homefile(use_empty=True)
    ok(bpy.ops.roads.import_osm(filepath=str(path), highways=highways))
    graph = bpy.context.active_object
    ok(bpy.ops.roads.build_city(seed=seed))
    return graph


def render(out, name, samples, credit=""):
    scene = bpy.context.scene
    render_scene.stamp_credit(scene, credit)
    ok(bpy.ops.roads.render_city(animation=False, engine='BLENDER_EEVEE', resolution_x=SIZE[0],
                                 resolution_y=SIZE[1], samples=samples, directory=str(out)))
    target = out / name
    (out / "city.png").replace(target)
    shrink(target)
    print("wrote", target)


def shrink(path):
    from PIL import Image

    with Image.open(path) as image:
        image.convert("RGB").quantize(colors=256, method=Image.Quantize.MEDIANCUT, dither=Image.Dither.NONE) \
            .save(path, optimize=True)


def look_at(camera, location, target, lens=35.0):
    camera.location = Vector(location)
    camera.rotation_euler = (Vector(target) - Vector(location)).to_track_quat('-Z', 'Y').to_euler()
    camera.data.lens = lens
    camera.data.clip_start = max(0.3, (Vector(target) - Vector(location)).length / 300.0)


def view_camera():
    return next(o for o in bpy.context.scene.objects if o.get("road_city_part") == "view")


def main():
    args = parse_args()
    out = Path(args.out_dir).resolve()
    out.mkdir(parents=True, exist_ok=True)
    render_scene.enable_addon()
    sample = render_scene.REPO / "samples" / "sample_city.osm"

    # Build City: the view camera it adds.
    town(sample)
    render(out, "city_overview.png", args.samples)

    # Close by: the roundabout of the old town, where eight streets meet.
    scene = bpy.context.scene
    camera = view_camera()
    scene.camera = camera
    look_at(camera, (330.0, -190.0, 150.0), (400.0, -40.0, 0.0), lens=40.0)
    render(out, "city_closeup.png", args.samples)

    # Fly-Through: a drone tour, drawn from above.
    ok(bpy.ops.roads.flythrough(mode='TOUR', height='DRONE', duration_s=120.0, seed=2))
    path = next(o for o in scene.objects if o.get("road_city_part") == "flythrough path")
    path.data.bevel_depth = 4.0
    path.hide_render = False
    path.visible_shadow = False
    material = bpy.data.materials.new("Flythrough Path")
    material.use_nodes = True
    material.shadow_method = 'NONE'  # Eevee: the path casts no shadow on the city
    nodes = material.node_tree.nodes
    emission = nodes.new('ShaderNodeEmission')
    emission.inputs["Color"].default_value = (1.0, 0.05, 0.02, 1.0)
    emission.inputs["Strength"].default_value = 3.0
    material.node_tree.links.new(emission.outputs[0], nodes["Material Output"].inputs["Surface"])
    path.data.materials.append(material)
    top = bpy.data.objects.new("Top", bpy.data.cameras.new("Top"))
    scene.collection.objects.link(top)
    top.data.type = 'ORTHO'
    graph = bpy.data.objects["sample_city"]
    xy = np.array([v.co[:2] for v in graph.data.vertices])
    low, high = xy.min(axis=0), xy.max(axis=0)
    top.data.ortho_scale = 1.04 * max(high[0] - low[0], (high[1] - low[1]) * SIZE[0] / SIZE[1])
    top.data.clip_start, top.data.clip_end = 10.0, 3000.0
    top.location = ((low[0] + high[0]) / 2, (low[1] + high[1]) / 2, 1500.0)
    scene.camera = top
    render(out, "city_flythrough.png", args.samples)

    # A frame of a street-level fly-through.
    path.hide_render = True
    ok(bpy.ops.roads.flythrough(mode='TOUR', height='STREET', duration_s=30.0, seed=4))
    scene.frame_set(scene.frame_start + 200)
    render(out, "city_street.png", args.samples)

    if args.osm:
        graph = town(Path(args.osm).resolve(), seed=2)
        render(out, "city_{}.png".format(graph.name), args.samples, credit="© OpenStreetMap contributors")


main()
