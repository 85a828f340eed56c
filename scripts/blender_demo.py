"""Render a top-down picture of an OpenStreetMap road network with the Road Grammar add-on.

usage:
  blender -b --factory-startup --python scripts/blender_demo.py -- INPUT OUTPUT.png
          [--highways drivable|all|LIST] [--size PIXELS] [--engine eevee|cycles|workbench]

Enables the add-on from addon/ of this repository (the native module comes from
$GGG_MODULE_DIR, by default build/python), imports INPUT, frames the network with an
orthographic camera looking straight down, and writes OUTPUT.png.
"""

import argparse
import sys
import time
from pathlib import Path

import bpy

sys.path.insert(0, str(Path(__file__).resolve().parent))
import render_scene  # noqa: E402  (scripts/render_scene.py, after the line above)


def parse_args():
    parser = argparse.ArgumentParser(prog="blender -b --python scripts/blender_demo.py --")
    parser.add_argument("input", help=".osm, .osm.pbf, .osm.bz2, .osm.gz, .geojson or .ggraph file")
    parser.add_argument("output", help="PNG to write")
    parser.add_argument("--highways", default="all",
                        help="drivable, all, or comma-separated highway values (default: all)")
    render_scene.add_render_arguments(parser, size=1600)
    parser.add_argument("--credit", default="© OpenStreetMap contributors",
                        help="attribution written in the corner of the picture ('' for none; "
                        "OSM data requires crediting OpenStreetMap contributors)")
    return parser.parse_args(render_scene.script_argv())


def clear_scene():
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj)
    for mesh in list(bpy.data.meshes):
        bpy.data.meshes.remove(mesh)


def import_roads(args):
    kwargs = {"filepath": str(Path(args.input).resolve())}
    if args.highways in ("drivable", "all"):
        kwargs["highways"] = args.highways.upper()
    else:
        kwargs["highways"] = 'CUSTOM'
        kwargs["highways_custom"] = args.highways
    result = bpy.ops.roads.import_osm(**kwargs)
    if result != {'FINISHED'}:
        raise SystemExit("error: import failed: {}".format(result))
    graph = bpy.context.active_object
    surface = next(child for child in graph.children if child.get("road_surface"))
    return graph, surface


def main():
    args = parse_args()
    started = time.monotonic()
    render_scene.enable_addon()
    clear_scene()
    scene = bpy.context.scene
    graph, surface = import_roads(args)
    low, high = render_scene.world_bounds([surface])
    render_scene.add_ground(scene, low, high)
    render_scene.add_camera_and_light(scene, low, high, args.size, margin=1.04, clip_end=2000.0)
    render_scene.setup_render(scene, args.engine, args.output, eevee_samples=4)
    render_scene.stamp_credit(scene, args.credit)
    bpy.ops.render.render(write_still=True)
    print("wrote {} ({} x {} px, {}): {} vertices, {} edges, {:.0f} x {:.0f} m, {:.1f} s".format(
        args.output, scene.render.resolution_x, scene.render.resolution_y, scene.render.engine,
        len(graph.data.vertices), len(graph.data.edges), high.x - low.x, high.y - low.y,
        time.monotonic() - started))


main()
