"""Render learning and growth in the Road Grammar add-on: the sample town with its learned
rules coloured at the top level of the hierarchy (Learn, like the paper's Fig. 13), and the
town with a district grown west of it by those rules (Grow into Region).

usage:
  blender -b --factory-startup --python scripts/render_synthesis_demo.py -- LEARNED.png GROWN.png
          [--replaced REPLACED.png] [--stitched STITCHED.png]
          [--input samples/sample_city.osm] [--size PIXELS] [--engine eevee|cycles|workbench]

Enables the add-on from addon/ of this repository (the native module comes from
$GGG_MODULE_DIR, by default build/python), imports the input's drivable streets, runs
roads.learn and renders from above; then adds a rectangle west of the town as the region,
runs roads.grow_region and renders again. With --replaced, a fresh scene: the town analysed,
its most frequent block replaced by a round plaza (roads.store_replacement,
roads.replace_isogroup). With --stitched, a fresh scene: the town imported twice, 1.6 km
apart, each learned, and the gap between them grown with both grammars (roads.stitch_cities).
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
    parser.add_argument("--replaced", help="PNG to write: the most frequent block replaced by a plaza")
    parser.add_argument("--stitched", help="PNG to write: two copies of the town stitched by growth")
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
    size = (scene.render.resolution_x, scene.render.resolution_y, scene.render.engine)
    if args.replaced:
        replaced(args)
    if args.stitched:
        stitched(args)
    print("wrote {} and {} ({} x {} px, {}); {:.1f} s".format(args.learned, args.grown, *size, time.monotonic() - started))


def top_view(args, objects, output):
    scene = bpy.context.scene
    low, high = render_scene.world_bounds(objects)
    render_scene.add_ground(scene, low, high)
    render_scene.add_camera_and_light(scene, low, high, args.size, margin=1.04, clip_end=4000.0)
    render_scene.setup_render(scene, args.engine, output, eevee_samples=8)
    render_scene.stamp_credit(scene, args.credit)
    render(scene, output)


def surface_of(graph):
    return next(child for child in graph.children if child.get("road_surface"))


def replaced(args):
    import bmesh
    bpy.ops.wm.read_homefile(use_empty=True)
    run(bpy.ops.roads.import_osm, filepath=str(Path(args.input).resolve()), highways='DRIVABLE')
    graph = bpy.context.active_object
    run(bpy.ops.roads.analyze, max_order=8, min_aspect=0.0)
    items = graph.road_analysis.isogroups
    blocks = [i for i, item in enumerate(items) if item.order >= 4 and item.edge_count == item.order]
    if not blocks:
        raise SystemExit("error: the analysis found no closed block to replace")
    best = max(blocks, key=lambda i: (items[i].frequency, -i))
    # The plaza: a ring of 16 streets around a small square, joined by four.
    mesh = bpy.data.meshes.new("Plaza")
    bm = bmesh.new()
    import math
    outer = [bm.verts.new((40 * math.cos(2 * math.pi * i / 16), 40 * math.sin(2 * math.pi * i / 16), 0)) for i in range(16)]
    inner = [bm.verts.new((15 * math.cos(2 * math.pi * i / 4), 15 * math.sin(2 * math.pi * i / 4), 0)) for i in range(4)]
    for ring in (outer, inner):
        for a, b in zip(ring, ring[1:] + ring[:1]):
            bm.edges.new((a, b))
    for j in range(4):
        bm.edges.new((outer[4 * j], inner[j]))
    bm.to_mesh(mesh)
    bm.free()
    plaza = bpy.data.objects.new("Plaza", mesh)
    bpy.context.scene.collection.objects.link(plaza)
    plaza.location = (5000.0, 0.0, 0.0)  # out of the picture
    bpy.ops.object.select_all(action='DESELECT')
    graph.select_set(True)
    bpy.context.view_layer.objects.active = graph
    run(bpy.ops.roads.store_replacement, object=plaza.name)
    run(bpy.ops.roads.replace_isogroup, index=best)
    plaza.hide_render = True
    top_view(args, [surface_of(graph)], args.replaced)


def stitched(args):
    bpy.ops.wm.read_homefile(use_empty=True)
    towns = []
    for offset in (0.0, 2200.0):
        run(bpy.ops.roads.import_osm, filepath=str(Path(args.input).resolve()), highways='DRIVABLE')
        town = bpy.context.active_object
        town.location.x += offset
        bpy.context.view_layer.update()
        run(bpy.ops.roads.learn)
        towns.append(town)
    low, high = render_scene.world_bounds([surface_of(towns[0])])
    bpy.ops.mesh.primitive_plane_add()
    gap = bpy.context.active_object
    gap.name = "Gap"
    gap.location = (high.x + 340.0, 0.5 * (low.y + high.y), 0.0)
    gap.scale = (340.0, 0.45 * (high.y - low.y), 1.0)
    gap.hide_render = True
    bpy.ops.object.select_all(action='DESELECT')
    towns[1].select_set(True)
    towns[0].select_set(True)
    bpy.context.view_layer.objects.active = towns[0]
    run(bpy.ops.roads.stitch_cities, other=towns[1].name, region=gap.name)
    top_view(args, [surface_of(towns[0])], args.stitched)


main()
