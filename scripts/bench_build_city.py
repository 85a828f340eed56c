"""Times Build City on a real extract (figures in docs/benchmarks.md).

  GGG_MODULE_DIR=build/python blender -b --factory-startup --python scripts/bench_build_city.py -- \
      ../shared/osm/porto_metro.osm.pbf [--highways ALL] [--repeat 1]

Each run imports the file into a fresh scene (not timed), then times the operator
roads.build_city (the native ground plan, ggg.city_layout, timed on its own as well, the
Blender meshes, and the evaluation of the city's Geometry Nodes that Blender runs after the
operator: the extruded blocks and buildings), then reads the evaluated meshes.
"""

import argparse
import resource
import sys
import time
from pathlib import Path

import addon_utils
import bpy
import numpy as np

REPO = Path(__file__).resolve().parent.parent


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    parser = argparse.ArgumentParser(prog="bench_build_city.py")
    parser.add_argument("input")
    parser.add_argument("--highways", default="ALL", choices=["DRIVABLE", "ALL"])
    parser.add_argument("--repeat", type=int, default=1)
    args = parser.parse_args(argv)

    sys.path.insert(0, str(REPO / "addon"))
    addon_utils.enable("road_grammar", default_set=True)
    from road_grammar.core import native
    from road_grammar.data import graph_edit
    from road_grammar.display import city

    ggg = native.load()
    rows = []
    for _ in range(args.repeat):
        bpy.ops.wm.read_factory_settings(use_empty=True)
        addon_utils.enable("road_grammar", default_set=True)
        if bpy.ops.roads.import_osm(filepath=str(Path(args.input).resolve()), highways=args.highways) != {'FINISHED'}:
            raise SystemExit("import failed")
        graph_obj = bpy.context.active_object
        columns = graph_edit.MeshGraph(graph_obj)
        graph = columns.graph(ggg)
        widths = ggg.road_widths(graph)
        start = time.perf_counter()
        layout = ggg.city_layout(graph, half_widths=widths / 2.0)
        native_s = time.perf_counter() - start

        start = time.perf_counter()
        if bpy.ops.roads.build_city() != {'FINISHED'}:
            raise SystemExit("build_city failed")
        operator_s = time.perf_counter() - start
        start = time.perf_counter()
        depsgraph = bpy.context.evaluated_depsgraph_get()
        collection = city.find_collection(graph_obj)
        vertices = 0
        for obj in collection.objects:
            if obj.type == 'MESH':
                evaluated = obj.evaluated_get(depsgraph)
                vertices += len(evaluated.data.vertices)
        evaluate_s = time.perf_counter() - start
        rows.append((native_s, operator_s, evaluate_s))
    peak_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    best = np.min(np.array(rows), axis=0)
    print("build_city {} ({}): {:,} edges, {:,} faces, {:,} blocks, {:,} buildings, {:,} road pieces, "
          "{:,} evaluated vertices".format(
              Path(args.input).name, args.highways.lower(), graph.edge_count, collection["faces"],
              collection["blocks"], collection["buildings"], collection["road_pieces"], vertices))
    print("best of {}: city_layout {:.2f} s, build_city operator {:.2f} s (layout included), "
          "reading the evaluated meshes {:.2f} s; peak memory {:.0f} MB".format(len(rows), *best, peak_mb))


main()
