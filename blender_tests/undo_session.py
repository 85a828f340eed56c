"""Runs inside a Blender *with a window* (under Xvfb), driven by test_undo.py.

In background mode (-b) Blender keeps no undo stack, so ed.undo cannot run there. This
script imports a file as a user would (an undo step pushed), undoes, redoes, and writes
what the file held at each step as JSON.

  blender --factory-startup --python undo_session.py -- ADDON_PARENT INPUT OUTPUT.json
"""

import json
import sys
import traceback

import addon_utils
import bpy

addon_parent, input_path, output_path = sys.argv[sys.argv.index("--") + 1:][:3]
KINDS = ("objects", "meshes", "materials", "node_groups", "collections")


def state():
    data = {kind: sorted(getattr(bpy.data, kind).keys()) for kind in KINDS}
    data["scene keys"] = sorted(bpy.context.scene.keys())
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
            bpy.ops.ed.undo_push(message="before import")
            result["before"] = state()
            # undo=True: push an undo step as when the user runs the operator from the menu.
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
