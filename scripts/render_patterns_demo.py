"""Render the street patterns the Road Grammar add-on finds: the sample town coloured by
isogroup (like the paper's Fig. 13) and the places similar to one block (Fig. 17).

usage:
  blender -b --factory-startup --python scripts/render_patterns_demo.py -- OVERVIEW.png SIMILAR.png
          [--input samples/sample_city.osm] [--max-order 8] [--size PIXELS]
          [--engine eevee|cycles|workbench]

Enables the add-on from addon/ of this repository (the native module comes from
$GGG_MODULE_DIR, by default build/python), imports the input, runs Analyze and renders the
overview colours from above; then takes the first occurrence of the most frequent closed
block (an isogroup whose pattern is a cycle) as the seed, runs Find Similar and renders
again: every similar block in sky blue, the seed in magenta.
"""

import argparse
import sys
import time
from pathlib import Path

import bpy
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import render_scene  # noqa: E402  (scripts/render_scene.py, after the line above)


def parse_args():
    parser = argparse.ArgumentParser(prog="blender -b --python scripts/render_patterns_demo.py --")
    parser.add_argument("overview", help="PNG to write: the graph coloured by isogroup")
    parser.add_argument("similar", help="PNG to write: Find Similar on one block")
    parser.add_argument("--input", default=str(render_scene.REPO / "samples" / "sample_city.osm"),
                        help="road file (default: samples/sample_city.osm)")
    parser.add_argument("--max-order", type=int, default=8, help="largest pattern in vertices (default: 8)")
    parser.add_argument("--min-aspect", type=float, default=0.0,
                        help="list only patterns at least this close to square (default: 0, any)")
    render_scene.add_render_arguments(parser, size=1400)
    parser.add_argument("--credit", default="",
                        help="attribution written in the corner ('' for none: the sample town is fictional; "
                        "OpenStreetMap data requires crediting OpenStreetMap contributors)")
    return parser.parse_args(render_scene.script_argv())


def run(operator, **kwargs):
    result = operator(**kwargs)
    if result != {'FINISHED'}:
        raise SystemExit("error: {} returned {}".format(operator.idname_py(), result))


def block_seed(obj):
    """The vertices of the first occurrence of the most frequent closed block of four
    streets (else of any size) among the isogroups found."""
    from road_grammar.data import analysis

    items = obj.road_analysis.isogroups
    cycles = [i for i, item in enumerate(items) if item.order >= 4 and item.edge_count == item.order]
    if not cycles:
        raise SystemExit("error: the analysis found no closed block to use as a seed")
    best = max(cycles, key=lambda i: (items[i].order == 4, items[i].frequency, -i))
    occurrences, _, _ = analysis.isogroup_arrays(obj, best)
    return occurrences[0]


def select_vertices(obj, vertices):
    mesh = obj.data
    mask = np.zeros(len(mesh.vertices), dtype=bool)
    mask[vertices] = True
    mesh.vertices.foreach_set("select", mask)
    mesh.edges.foreach_set("select", np.zeros(len(mesh.edges), dtype=bool))
    mesh.update()


def render(scene, output):
    scene.render.filepath = str(Path(output).resolve())
    bpy.ops.render.render(write_still=True)


def main():
    args = parse_args()
    started = time.monotonic()
    render_scene.enable_addon()
    bpy.ops.wm.read_homefile(use_empty=True)
    scene = bpy.context.scene
    run(bpy.ops.roads.import_osm, filepath=str(Path(args.input).resolve()), highways='ALL')
    graph = bpy.context.active_object
    surface = next(child for child in graph.children if child.get("road_surface"))
    run(bpy.ops.roads.analyze, max_order=args.max_order, min_aspect=args.min_aspect)

    low, high = render_scene.world_bounds([surface])
    render_scene.add_ground(scene, low, high)
    render_scene.add_camera_and_light(scene, low, high, args.size, margin=1.04, clip_end=2000.0)
    render_scene.setup_render(scene, args.engine, args.overview, eevee_samples=8)
    render_scene.stamp_credit(scene, args.credit)
    render(scene, args.overview)
    groups = len(graph.road_analysis.isogroups)

    select_vertices(graph, block_seed(graph))
    run(bpy.ops.roads.find_similar)
    render(scene, args.similar)
    print("wrote {} and {} ({} x {} px, {}): {} isogroups; {:.1f} s".format(
        args.overview, args.similar, scene.render.resolution_x, scene.render.resolution_y, scene.render.engine,
        groups, time.monotonic() - started))


main()
