"""Build the 3-D city of a road network and render it without the interface: a still from
above the city and, optionally, a fly-through as an MP4.

usage:
  blender -b --factory-startup --python scripts/render_city.py -- INPUT --out DIR
          [--flythrough SECONDS] [--height street|drone] [--engine eevee|cycles]
          [--size 1280x720] [--samples 16] [--fly-size 640x360] [--fly-samples 4]
          [--seed 1] [--highways all|drivable|LIST] [--credit TEXT] [--blend]

Enables the add-on from addon/ of this repository (the native module from $GGG_MODULE_DIR,
by default build/python), imports INPUT (.osm, .osm.pbf, .osm.bz2, .osm.gz, .geojson,
.ggraph) with roads.import_osm, runs roads.build_city, and renders with roads.render_city:
DIR/city.png from the city's view camera, and with --flythrough DIR/flythrough.mp4 of a
seeded tour of the major roads (roads.flythrough). --blend also saves DIR/city.blend.
"""

import argparse
import sys
import time
from pathlib import Path

import bpy

sys.path.insert(0, str(Path(__file__).resolve().parent))
import render_scene  # noqa: E402  (scripts/render_scene.py, after the line above)


def size(text):
    try:
        width, height = (int(v) for v in text.lower().split("x"))
    except ValueError:
        raise argparse.ArgumentTypeError("expected WIDTHxHEIGHT, e.g. 1280x720") from None
    if width < 16 or height < 16:
        raise argparse.ArgumentTypeError("at least 16x16 pixels")
    return width, height


def parse_args():
    parser = argparse.ArgumentParser(prog="blender -b --python scripts/render_city.py --")
    parser.add_argument("input", help="road network file")
    parser.add_argument("--out", required=True, help="folder for city.png (and flythrough.mp4)")
    parser.add_argument("--flythrough", type=float, metavar="SECONDS", default=0.0,
                        help="also render a fly-through of this length (0: none)")
    parser.add_argument("--height", choices=("street", "drone"), default="drone", help="fly-through height")
    parser.add_argument("--engine", choices=("eevee", "cycles"), default="eevee")
    parser.add_argument("--size", type=size, default=(1280, 720), help="still size, WIDTHxHEIGHT")
    parser.add_argument("--samples", type=int, default=16, help="samples of the still")
    parser.add_argument("--fly-size", type=size, default=(640, 360), help="fly-through size, WIDTHxHEIGHT")
    parser.add_argument("--fly-samples", type=int, default=4, help="samples per fly-through frame")
    parser.add_argument("--fps", type=int, default=24, help="frames per second of the fly-through")
    parser.add_argument("--seed", type=int, default=1, help="seed of the lots, heights and tour")
    parser.add_argument("--highways", default="all", help="drivable, all, or comma-separated highway values")
    parser.add_argument("--credit", default="© OpenStreetMap contributors",
                        help="attribution in the corner of the pictures ('' for none; OSM data requires it)")
    parser.add_argument("--blend", action="store_true", help="also save DIR/city.blend")
    return parser.parse_args(render_scene.script_argv())


def run(operator, **kwargs):
    try:
        result = operator(**kwargs)
    except RuntimeError as ex:  # the operator reported an error
        raise SystemExit("error: {}".format(str(ex).strip())) from None
    if result != {'FINISHED'}:
        raise SystemExit("error: {} returned {}".format(operator.idname_py(), result))


def main():
    args = parse_args()
    started = time.monotonic()
    out = Path(args.out).resolve()
    out.mkdir(parents=True, exist_ok=True)
    render_scene.enable_addon()
    bpy.ops.wm.read_homefile(use_empty=True)
    scene = bpy.context.scene

    highways = {"highways": args.highways.upper()} if args.highways in ("drivable", "all") else \
        {"highways": 'CUSTOM', "highways_custom": args.highways}
    run(bpy.ops.roads.import_osm, filepath=str(Path(args.input).resolve()), **highways)
    graph = bpy.context.active_object
    run(bpy.ops.roads.build_city, seed=args.seed)
    built = time.monotonic()
    view = next(o for o in scene.objects if o.get("road_city_part") == "view")
    scene.camera = view
    render_scene.stamp_credit(scene, args.credit)
    engine = 'CYCLES' if args.engine == "cycles" else 'BLENDER_EEVEE'
    run(bpy.ops.roads.render_city, animation=False, engine=engine, resolution_x=args.size[0],
        resolution_y=args.size[1], samples=args.samples, directory=str(out))
    print("wrote {} ({} x {}, {}, {} samples) in {:.1f} s".format(
        out / "city.png", args.size[0], args.size[1], engine, args.samples, time.monotonic() - built))

    if args.flythrough > 0:
        scene.render.fps, scene.render.fps_base = args.fps, 1.0
        run(bpy.ops.roads.flythrough, mode='TOUR', height=args.height.upper(), duration_s=args.flythrough,
            seed=args.seed)
        started_movie = time.monotonic()
        run(bpy.ops.roads.render_city, animation=True, engine=engine, resolution_x=args.fly_size[0],
            resolution_y=args.fly_size[1], samples=args.fly_samples, directory=str(out))
        print("wrote {} ({} frames, {} x {}) in {:.1f} s".format(
            out / "flythrough.mp4", scene.frame_end - scene.frame_start + 1, args.fly_size[0], args.fly_size[1],
            time.monotonic() - started_movie))
    if args.blend:
        bpy.ops.wm.save_as_mainfile(filepath=str(out / "city.blend"))
    collection = next(c for c in bpy.data.collections if c.get("road_city") == graph.name)
    print("{}: {:,} blocks, {:,} buildings; {:.1f} s in all".format(
        graph.name, collection["blocks"], collection["buildings"], time.monotonic() - started))


main()
