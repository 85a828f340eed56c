"""Runs inside a Blender *with a window* (under Xvfb), driven by test_undo.py.

In background mode (-b) Blender keeps no undo stack, so ed.undo cannot run there. This
script runs an operator as a user would (an undo step pushed), undoes, redoes, and writes
what the file held at each step as JSON.

  blender --factory-startup --python undo_session.py -- ADDON_PARENT INPUT OUTPUT.json [MODE]

MODE "import" (default): import the road file INPUT. MODE "grow": load the grammar file
INPUT, add its axiom, then grow it by two steps (the step that is undone). MODE "city":
import the road file INPUT, then build its city (the step that is undone). MODE "learn":
import the road file INPUT, then learn a grammar of it (the step that is undone). MODE
"grow_region": import the road file INPUT, learn its grammar, add a plane "Region" east of
it, then grow the graph into the plane (the step that is undone). MODE "replace": import the
road file INPUT (a street grid), analyse it (max order 4), choose the isogroup of the square
blocks, store a ring object "Piece" as the replacement piece, then replace the squares by it
(the step that is undone).
"""

import json
import math
import sys
import traceback

import addon_utils
import bpy

_args = sys.argv[sys.argv.index("--") + 1:]
addon_parent, input_path, output_path = _args[:3]
mode = _args[3] if len(_args) > 3 else "import"
KINDS = ("objects", "meshes", "materials", "node_groups", "collections", "texts", "lights", "cameras", "worlds")


def state():
    data = {kind: sorted(getattr(bpy.data, kind).keys()) for kind in KINDS}
    data["scene keys"] = sorted(bpy.context.scene.keys())
    grammar_text = bpy.context.scene.road_grammar.text
    data["scene grammar"] = grammar_text.name if grammar_text is not None else None
    data["learned"] = {obj.name: obj.road_learning.stats for obj in bpy.data.objects if obj.get("road_graph")}
    # What each mesh holds: counts, a checksum of the positions, its attributes.
    data["meshes held"] = {
        mesh.name: [len(mesh.vertices), len(mesh.edges), round(sum(v.co.x + 2.0 * v.co.y for v in mesh.vertices), 3),
                    sorted(a.name for a in mesh.attributes if not a.name.startswith("."))]
        for mesh in bpy.data.meshes}
    # The analysis kept on each road graph, and the scene's replacement piece.
    data["analysis"] = {obj.name: [obj.road_analysis.topology, len(obj.road_analysis.isogroups),
                                   obj.road_analysis.active_index]
                        for obj in bpy.data.objects if obj.get("road_graph")}
    data["piece"] = bpy.context.scene.road_replacement.piece
    return data


def _raise(ex):
    raise ex


def run():
    result = {}
    try:
        sys.path.insert(0, addon_parent)
        addon_utils.enable("road_grammar", default_set=True, handle_error=_raise)
        window = bpy.context.window_manager.windows[0]
        area = next(a for a in window.screen.areas if a.type == 'VIEW_3D')
        region = next(r for r in area.regions if r.type == 'WINDOW')
        with bpy.context.temp_override(window=window, screen=window.screen, area=area, region=region):
            if mode in ("city", "learn", "grow_region", "replace"):
                result["load"] = sorted(bpy.ops.roads.import_osm('EXEC_DEFAULT', True, filepath=input_path,
                                                                 highways='ALL'))
            if mode == "grow":
                result["load"] = sorted(bpy.ops.roads.load_grammar('EXEC_DEFAULT', True, filepath=input_path))
                result["axiom"] = sorted(bpy.ops.roads.add_axiom('EXEC_DEFAULT', True))
            if mode == "grow_region":
                graph_obj = bpy.context.view_layer.objects.active
                result["learn"] = sorted(bpy.ops.roads.learn('EXEC_DEFAULT', True))
                mesh = bpy.data.meshes.new("Region")
                mesh.from_pydata([(700.0, -600.0, 0.0), (1500.0, -600.0, 0.0), (1500.0, 600.0, 0.0),
                                  (700.0, 600.0, 0.0)], [], [(0, 1, 2, 3)])
                bpy.context.scene.collection.objects.link(bpy.data.objects.new("Region", mesh))
                bpy.context.view_layer.objects.active = graph_obj
            if mode == "replace":
                graph_obj = bpy.context.view_layer.objects.active
                result["analyze"] = sorted(bpy.ops.roads.analyze('EXEC_DEFAULT', True, max_order=4))
                squares = [i for i, item in enumerate(graph_obj.road_analysis.isogroups)
                           if item.order == 4 and item.edge_count == 4]
                graph_obj.road_analysis.active_index = squares[0]
                angles = [math.pi / 8 + k * math.pi / 4 for k in range(8)]
                mesh = bpy.data.meshes.new("Piece")
                mesh.from_pydata([(3000.0 + 10.0 * math.cos(a), 10.0 * math.sin(a), 0.0) for a in angles],
                                 [(k, (k + 1) % 8) for k in range(8)], [])
                bpy.context.scene.collection.objects.link(bpy.data.objects.new("Piece", mesh))
                bpy.context.view_layer.objects.active = graph_obj
                result["store"] = sorted(bpy.ops.roads.store_replacement('EXEC_DEFAULT', True, object="Piece"))
            bpy.ops.ed.undo_push(message="before")
            result["before"] = state()
            # undo=True: push an undo step as when the user runs the operator from the menu.
            if mode == "city":
                result["city"] = sorted(bpy.ops.roads.build_city('EXEC_DEFAULT', True))
            elif mode == "learn":
                result["learn"] = sorted(bpy.ops.roads.learn('EXEC_DEFAULT', True, mode='LOSSLESS'))
            elif mode == "grow":
                result["grow"] = sorted(bpy.ops.roads.grow('EXEC_DEFAULT', True, steps=2))
            elif mode == "grow_region":
                result["grow_region"] = sorted(bpy.ops.roads.grow_region('EXEC_DEFAULT', True, region="Region"))
            elif mode == "replace":
                result["replace"] = sorted(bpy.ops.roads.replace_isogroup('EXEC_DEFAULT', True))
            else:
                result["import"] = sorted(bpy.ops.roads.import_osm('EXEC_DEFAULT', True, filepath=input_path))
            result["imported"] = state()
            result["undo"] = sorted(bpy.ops.ed.undo())
            result["undone"] = state()
            result["redo"] = sorted(bpy.ops.ed.redo())
            result["redone"] = state()
    except Exception:
        result["error"] = traceback.format_exc()
    with open(output_path, "w", encoding="utf-8") as out:
        json.dump(result, out, indent=1)
    bpy.ops.wm.quit_blender()


# The window and its undo stack exist once the event loop runs.
bpy.app.timers.register(run, first_interval=0.5)
