"""Runs inside a Blender *with a window* (under Xvfb), driven by test_analysis.py and
test_learning.py.

In background mode (-b) Blender keeps no undo stack and runs no modal operators, so this
script does what a user does: it imports the road file INPUT, then

* MODE "undo": runs Analyze as from the sidebar (modal, in a worker thread), waits for it,
  undoes and redoes it; then selects one block in Edit Mode, runs Find Similar and undoes
  it;
* MODE "escape" (Blender started with --enable-event-simulate): starts Analyze, presses
  Esc while it runs, and waits until it has stopped;
* MODE "learn": sets the Learn panel's settings (lossless, max order 4), runs Learn as from
  the sidebar or F3 (modal, in a worker thread), waits for it, undoes and redoes it;
* MODE "learn_escape" (with --enable-event-simulate): starts Learn, presses Esc while it
  runs, and waits until it has stopped.

It writes what the file held at each step as JSON to OUTPUT.

  blender --factory-startup [--enable-event-simulate] --python analysis_session.py -- \
      ADDON_PARENT INPUT OUTPUT.json MODE
"""

import json
import sys
import time
import traceback

import addon_utils
import bmesh
import bpy

_args = sys.argv[sys.argv.index("--") + 1:]
addon_parent, input_path, output_path, mode = _args[:4]
TIMEOUT = 120.0
result = {}


def _raise(ex):
    raise ex


def graph():
    return next(o for o in bpy.data.objects if o.get("road_graph"))


def state():
    """What Analyze and Find Similar change: the stored isogroups, the colours, the
    modifiers and the selection."""
    obj = graph()
    mesh = obj.data
    if obj.mode == 'EDIT':
        bm = bmesh.from_edit_mesh(mesh)
        layer = bm.edges.layers.int.get("road_pattern")
        coloured = sum(1 for e in bm.edges if layer is not None and e[layer] != 0)
        selected = sum(1 for v in bm.verts if v.select)
    else:
        attribute = mesh.attributes.get("road_pattern")
        coloured = sum(1 for item in attribute.data if item.value != 0) if attribute is not None else 0
        selected = sum(1 for v in mesh.vertices if v.select)
    analysis = obj.road_analysis
    return {"isogroups": len(analysis.isogroups), "topology": analysis.topology,
            "stored": len(analysis["occurrences"]) if "occurrences" in analysis else 0,
            "coloured": coloured, "selected": selected,
            "modifiers": [m.name for child in obj.children for m in child.modifiers],
            "mode": obj.mode, "objects": sorted(bpy.data.objects.keys())}


def finish():
    with open(output_path, "w", encoding="utf-8") as out:
        json.dump(result, out, indent=1)
    bpy.ops.wm.quit_blender()


def fail():
    result["error"] = traceback.format_exc()
    finish()


def window_context():
    window = bpy.context.window_manager.windows[0]
    area = next(a for a in window.screen.areas if a.type == 'VIEW_3D')
    region = next(r for r in area.regions if r.type == 'WINDOW')
    return window, bpy.context.temp_override(window=window, screen=window.screen, area=area, region=region)


def running():
    from road_grammar.operators import analysis as analysis_ops
    from road_grammar.operators import learning as learning_ops
    return bool(analysis_ops.running) or bool(learning_ops.running)


def learn_state():
    """What Learn changes: the texts, the scene's grammar, the stored result, the objects."""
    obj = graph()
    text = bpy.context.scene.road_grammar.text
    stats = json.loads(obj.road_learning.stats) if obj.road_learning.stats else {}
    return {"texts": sorted(bpy.data.texts.keys()), "scene grammar": text.name if text is not None else None,
            "mode": stats.get("mode"), "levels": obj.road_learning.levels, "rules": len(obj.road_learning.rules),
            "max rule vertices": max((item.vertex_count for item in obj.road_learning.rules), default=0),
            "objects": sorted(bpy.data.objects.keys())}


def wait_until_done(then, started=None):
    """Poll (from timers) until no analysis runs, then call ``then``."""
    started = started or time.monotonic()

    def poll():
        try:
            if running():
                if time.monotonic() - started > TIMEOUT:
                    raise TimeoutError("the analysis did not end within {} s".format(TIMEOUT))
                return 0.1
            then()
        except Exception:
            fail()
        return None

    bpy.app.timers.register(poll, first_interval=0.1)


def start():
    try:
        sys.path.insert(0, addon_parent)
        addon_utils.enable("road_grammar", default_set=True, handle_error=_raise)
        window, override = window_context()
        with override:
            result["import"] = sorted(bpy.ops.roads.import_osm('EXEC_DEFAULT', True, filepath=input_path,
                                                               highways='ALL'))
            bpy.ops.ed.undo_push(message="before")
            result["before"] = state()
            if mode == "escape":
                _slow_down()
                result["analyze"] = sorted(bpy.ops.roads.analyze('INVOKE_DEFAULT', True, max_order=8, full=True))
                bpy.app.timers.register(_press_escape, first_interval=0.6)
            elif mode in ("learn", "learn_escape"):
                result["before"] = learn_state()
                settings = bpy.context.scene.road_learning
                settings.mode, settings.max_order = 'LOSSLESS', 4
                if mode == "learn_escape":
                    _slow_down()
                # No properties given: the operator takes the panel's settings.
                result["learn"] = sorted(bpy.ops.roads.learn('INVOKE_DEFAULT', True))
                result["was_running"] = running()
                if mode == "learn_escape":
                    bpy.app.timers.register(_press_escape, first_interval=0.6)
                else:
                    wait_until_done(_after_learning)
            else:
                result["analyze"] = sorted(bpy.ops.roads.analyze('INVOKE_DEFAULT', True, max_order=4))
                wait_until_done(_after_analysis)
    except Exception:
        fail()


# -- undo

def _after_analysis():
    result["finished"] = True
    window, override = window_context()
    with override:
        result["analysed"] = state()
        result["undo"] = sorted(bpy.ops.ed.undo())
        result["undone"] = state()
        result["redo"] = sorted(bpy.ops.ed.redo())
        result["redone"] = state()

        # Find Similar in Edit Mode on one block, then undo.
        obj = graph()
        bpy.ops.object.mode_set(mode='EDIT')
        bm = bmesh.from_edit_mesh(obj.data)
        for element in (*bm.verts, *bm.edges):
            element.select = False
        from road_grammar.data import analysis
        index = next(i for i, item in enumerate(obj.road_analysis.isogroups)
                     if item.order == 4 and item.edge_count == 4)
        occurrences, _, _ = analysis.isogroup_arrays(obj, index)
        bm.verts.ensure_lookup_table()
        for v in occurrences[0].tolist():
            bm.verts[v].select = True
        bm.select_flush(True)
        bmesh.update_edit_mesh(obj.data)
        bpy.ops.ed.undo_push(message="seeded")
        result["seeded"] = state()
        result["find_similar"] = sorted(bpy.ops.roads.find_similar('EXEC_DEFAULT', True))
        result["found"] = state()
        result["find_undo"] = sorted(bpy.ops.ed.undo())
        result["found_undone"] = state()
    finish()


def _after_learning():
    result["finished"] = True
    window, override = window_context()
    with override:
        result["learned"] = learn_state()
        result["undo"] = sorted(bpy.ops.ed.undo())
        result["undone"] = learn_state()
        result["redo"] = sorted(bpy.ops.ed.redo())
        result["redone"] = learn_state()
    finish()


# -- Esc

def _slow_down():
    """Make each progress report take a while, so that Esc comes during the analysis (or
    the learning)."""
    from road_grammar.core import jobs
    original = jobs.NativeJob.__call__
    result["progress_calls"] = 0

    def slow(self, fraction, message):
        result["progress_calls"] += 1
        time.sleep(0.3)
        return original(self, fraction, message)

    jobs.NativeJob.__call__ = slow


def _press_escape():
    try:
        result["was_running"] = running()
        window = bpy.context.window_manager.windows[0]
        window.event_simulate(type='ESC', value='PRESS')
        window.event_simulate(type='ESC', value='RELEASE')
        wait_until_done(_after_escape)
    except Exception:
        fail()
    return None


def _after_escape():
    result["still_running"] = running()
    window, override = window_context()
    with override:
        result["after"] = learn_state() if mode == "learn_escape" else state()
    finish()


# The window and its undo stack exist once the event loop runs.
bpy.app.timers.register(start, first_interval=0.5)
