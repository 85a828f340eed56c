"""Runs inside a Blender *with a window* (under Xvfb), driven by test_stitch.py: undo of
Stitch Cities (background Blender keeps no undo stack).

  blender --factory-startup --python stitch_session.py -- ADDON_PARENT INPUT OUTPUT.json

Imports the road file INPUT twice (the second moved 1.8 km east), learns each, adds a plane
"Gap" between them, stitches them (the step that is undone), undoes and redoes, and writes
what the file held at each step as JSON.
"""

import json
import sys
import traceback

import addon_utils
import bpy

_args = sys.argv[sys.argv.index("--") + 1:]
addon_parent, input_path, output_path = _args[:3]
KINDS = ("objects", "meshes", "materials", "node_groups", "collections", "texts")


def state():
    data = {kind: sorted(getattr(bpy.data, kind).keys()) for kind in KINDS}
    data["scene objects"] = sorted(obj.name for obj in bpy.context.scene.objects)
    data["meshes held"] = {
        mesh.name: [len(mesh.vertices), len(mesh.edges), round(sum(v.co.x + 2.0 * v.co.y for v in mesh.vertices), 3),
                    sorted(a.name for a in mesh.attributes if not a.name.startswith("."))]
        for mesh in bpy.data.meshes}
    data["locations"] = {obj.name: [round(c, 3) for c in obj.location] for obj in bpy.data.objects}
    active = bpy.context.view_layer.objects.active
    data["active"] = active.name if active is not None else None
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
            towns = []
            for offset in (0.0, 1800.0):
                result.setdefault("load", []).append(
                    sorted(bpy.ops.roads.import_osm('EXEC_DEFAULT', True, filepath=input_path)))
                town = bpy.context.view_layer.objects.active
                town.location = (offset, 0.0, 0.0)
                result.setdefault("learn", []).append(sorted(bpy.ops.roads.learn('EXEC_DEFAULT', True)))
                towns.append(town)
            mesh = bpy.data.meshes.new("Gap")
            mesh.from_pydata([(650.0, -700.0, 0.0), (1150.0, -700.0, 0.0), (1150.0, 700.0, 0.0),
                              (650.0, 700.0, 0.0)], [], [(0, 1, 2, 3)])
            bpy.context.scene.collection.objects.link(bpy.data.objects.new("Gap", mesh))
            for obj in bpy.context.view_layer.objects:
                obj.select_set(obj in towns)
            bpy.context.view_layer.objects.active = towns[0]
            bpy.context.view_layer.update()
            bpy.ops.ed.undo_push(message="before")
            result["before"] = state()
            result["stitch"] = sorted(bpy.ops.roads.stitch_cities('EXEC_DEFAULT', True, region="Gap"))
            result["stitched"] = state()
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
