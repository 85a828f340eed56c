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
import sys
import time
from pathlib import Path

import bpy

sys.path.insert(0, str(Path(__file__).resolve().parent))
import render_scene  # noqa: E402  (scripts/render_scene.py, after the line above)


def parse_args():
    parser = argparse.ArgumentParser(prog="blender -b --python scripts/render_grammar_demo.py --")
    parser.add_argument("output", help="PNG to write")
    parser.add_argument("--grammar", default=str(render_scene.REPO / "samples" / "sierpinski.grammar.json"),
                        help="grammar file (default: samples/sierpinski.grammar.json)")
    parser.add_argument("--steps", type=int, default=4, help="derivation steps (default: 4)")
    render_scene.add_render_arguments(parser, size=1200)
    return parser.parse_args(render_scene.script_argv())


def run(operator, **kwargs):
    result = operator(**kwargs)
    if result != {'FINISHED'}:
        raise SystemExit("error: {} returned {}".format(operator.idname_py(), result))


def main():
    args = parse_args()
    started = time.monotonic()
    render_scene.enable_addon()
    bpy.ops.wm.read_homefile(use_empty=True)
    scene = bpy.context.scene
    run(bpy.ops.roads.load_grammar, filepath=str(Path(args.grammar).resolve()))
    run(bpy.ops.roads.add_axiom)
    graph = bpy.context.active_object
    if args.steps > 0:
        run(bpy.ops.roads.grow, steps=args.steps)
    surface = next(child for child in graph.children if child.get("road_surface"))
    low, high = render_scene.world_bounds([graph, surface])
    render_scene.add_ground(scene, low, high)
    render_scene.add_camera_and_light(scene, low, high, args.size, margin=1.06, clip_end=5000.0)
    render_scene.setup_render(scene, args.engine, args.output, eevee_samples=8)
    bpy.ops.render.render(write_still=True)
    print("wrote {} ({} x {} px, {}): {} vertices, {} edges, {:.1f} s".format(
        args.output, scene.render.resolution_x, scene.render.resolution_y, scene.render.engine,
        len(graph.data.vertices), len(graph.data.edges), time.monotonic() - started))


main()
