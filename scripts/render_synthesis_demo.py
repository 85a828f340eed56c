"""Render learning and growth in the Road Grammar add-on: the sample town with its learned
rules coloured at the top level of the hierarchy (Learn, like the paper's Fig. 13), and the
town with a district grown west of it by those rules (Grow into Region).

usage:
  blender -b --factory-startup --python scripts/render_synthesis_demo.py -- LEARNED.png GROWN.png
          [--input samples/sample_city.osm] [--size PIXELS] [--engine eevee|cycles|workbench]

Enables the add-on from addon/ of this repository (the native module comes from
$GGG_MODULE_DIR, by default build/python), imports the input's drivable streets, runs
roads.learn and renders from above; then adds a rectangle west of the town as the region,
runs roads.grow_region and renders again.
"""

import argparse
import sys
import time
from pathlib import Path

import bpy

sys.path.insert(0, str(Path(__file__).resolve().parent))
import render_scene  # noqa: E402  (scripts/render_scene.py, after the line above)


def parse_args():
    parser = argparse.ArgumentParser(prog="blender -b --python scripts/render_synthesis_demo.py --")
    parser.add_argument("learned", help="PNG to write: the town coloured by learned rule")
    parser.add_argument("grown", help="PNG to write: the town with a grown district")
    parser.add_argument("--input", default=str(render_scene.REPO / "samples" / "sample_city.osm"),
                        help="road file (default: samples/sample_city.osm)")
    render_scene.add_render_arguments(parser, size=1400)
    parser.add_argument("--credit", default="", help="attribution written in the corner ('' for none)")
    return parser.parse_args(render_scene.script_argv())


def run(operator, **kwargs):
    result = operator(**kwargs)
    if result != {'FINISHED'}:
        raise SystemExit("error: {} returned {}".format(operator.idname_py(), result))


def render(scene, output):
    scene.render.filepath = str(Path(output).resolve())
    bpy.ops.render.render(write_still=True)


def main():
    args = parse_args()
    started = time.monotonic()
    render_scene.enable_addon()
    bpy.ops.wm.read_homefile(use_empty=True)
    scene = bpy.context.scene
    run(bpy.ops.roads.import_osm, filepath=str(Path(args.input).resolve()), highways='DRIVABLE')
    graph = bpy.context.active_object
    surface = next(child for child in graph.children if child.get("road_surface"))
    run(bpy.ops.roads.learn)

    # The region: a rectangle west of the town, as wide as a third of it.
    low, high = render_scene.world_bounds([surface])
    width = 0.5 * (high[0] - low[0])
    bpy.ops.mesh.primitive_plane_add()
    region = bpy.context.active_object
    region.name = "New district"
    region.scale = (width / 2, (high[1] - low[1]) / 2 * 0.9, 1)
    region.location = (low[0] - width / 2 - 5.0, 0.5 * (low[1] + high[1]), 0)
    region.hide_render = True
    low_all = low.copy()
    low_all.x -= width + 10.0

    render_scene.add_ground(scene, low_all, high)
    render_scene.add_camera_and_light(scene, low_all, high, args.size, margin=1.04, clip_end=4000.0)
    render_scene.setup_render(scene, args.engine, args.learned, eevee_samples=8)
    render_scene.stamp_credit(scene, args.credit)
    render(scene, args.learned)

    bpy.ops.object.select_all(action='DESELECT')
    graph.select_set(True)
    bpy.context.view_layer.objects.active = graph
    run(bpy.ops.roads.grow_region, region=region.name, seed=1)
    render(scene, args.grown)
    print("wrote {} and {} ({} x {} px, {}); {:.1f} s".format(
        args.learned, args.grown, scene.render.resolution_x, scene.render.resolution_y, scene.render.engine,
        time.monotonic() - started))


main()
