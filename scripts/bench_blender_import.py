"""Times the Blender import operator on a real extract (figures in docs/benchmarks.md).

  GGG_MODULE_DIR=build/python blender -b --factory-startup --python scripts/bench_blender_import.py -- \
      ../shared/osm/porto_metro.osm.pbf [--highways ALL] [--repeat 3]

Each run imports into a fresh scene: reading, graph mesh, surface object, and one evaluation
of the surface's geometry nodes (what the first redraw would cost).
"""

import argparse
import resource
import sys
import time
from pathlib import Path

import addon_utils
import bpy

REPO = Path(__file__).resolve().parent.parent


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    parser = argparse.ArgumentParser(prog="bench_blender_import.py")
    parser.add_argument("input")
    parser.add_argument("--highways", default="ALL", choices=["DRIVABLE", "ALL"])
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args(argv)

    sys.path.insert(0, str(REPO / "addon"))
    addon_utils.enable("road_grammar", default_set=True)
    times = []
    for _ in range(args.repeat):
        bpy.ops.wm.read_factory_settings(use_empty=True)
        addon_utils.enable("road_grammar", default_set=True)
        start = time.perf_counter()
        result = bpy.ops.roads.import_osm(filepath=str(Path(args.input).resolve()), highways=args.highways)
        if result != {'FINISHED'}:
            raise SystemExit(f"import failed: {result}")
        graph = next(o for o in bpy.context.scene.objects if o.get("road_graph"))
        surface = next(o for o in bpy.context.scene.objects if o.parent == graph)
        evaluated = surface.evaluated_get(bpy.context.evaluated_depsgraph_get())
        faces = len(evaluated.data.polygons)
        times.append(time.perf_counter() - start)
    peak_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(f"blender import {Path(args.input).name} ({args.highways.lower()}): "
          f"{len(graph.data.vertices)} vertices, {len(graph.data.edges)} edges, {faces} surface faces; "
          f"best {min(times):.2f} s, median {sorted(times)[len(times) // 2]:.2f} s over {len(times)} runs; "
          f"peak memory {peak_mb:.0f} MB")


main()
