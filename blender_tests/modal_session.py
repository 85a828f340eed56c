"""Runs inside a Blender *with a window* (under Xvfb, started with --enable-event-simulate),
driven by test_modal_jobs.py: Grow into Region, Stitch Cities and Build City run as a user
runs them from the sidebar (modal, in a worker thread).

In background mode (-b) Blender runs no modal operators and keeps no undo stack, so this
script does what a user does. It imports the road file INPUT and sets up the scene for the
operator MODE ("grow_region": learn the town's grammar, a plane "Region" east of it picked
in the Grammar panel; "stitch": the town twice, the second 1.8 km east, each learned, a plane
"Gap" between them picked in the panel, both selected; "city": the town only), then

1. starts the operator (INVOKE_DEFAULT, no properties: the panel's settings), each progress
   report slowed down, presses Esc while it runs and waits until it has stopped;
2. starts it again at full speed and waits until it has finished;
3. undoes that run;
4. runs it from a script (EXEC_DEFAULT, the panel's settings).

It writes what the file held at each step, the operator's results, the status bar texts and
the number of progress reports as JSON to OUTPUT.

  blender --factory-startup --enable-event-simulate --python modal_session.py -- \
      ADDON_PARENT INPUT OUTPUT.json MODE
"""

import hashlib
import json
import sys
import time
import traceback

import addon_utils
import bpy
import numpy as np

_args = sys.argv[sys.argv.index("--") + 1:]
addon_parent, input_path, output_path, mode = _args[:4]
TIMEOUT = 120.0
KINDS = ("objects", "meshes", "materials", "node_groups", "collections", "texts", "lights", "cameras", "worlds")
OPERATORS = {"grow_region": "grow_region", "stitch": "stitch_cities", "city": "build_city"}
result = {"mode": mode, "finished": [], "status": [], "progress_calls": 0}


def _raise(ex):
    raise ex


def mesh_digest(mesh):
    """Counts, and a hash of the positions, edges and attributes of a mesh."""
    co = np.empty(len(mesh.vertices) * 3, dtype=np.float32)
    mesh.vertices.foreach_get("co", co)
    edges = np.empty(len(mesh.edges) * 2, dtype=np.int32)
    mesh.edges.foreach_get("vertices", edges)
    digest = hashlib.sha1(np.round(co.astype(np.float64), 3).tobytes())
    digest.update(edges.tobytes())
    for attribute in sorted(mesh.attributes, key=lambda a: a.name):
        if attribute.name.startswith(".") or attribute.data_type not in ('INT', 'FLOAT'):
            continue
        values = np.empty(len(attribute.data), dtype=np.float64)
        attribute.data.foreach_get("value", values)
        digest.update(attribute.name.encode())
        digest.update(np.round(values, 3).tobytes())
    return [len(mesh.vertices), len(mesh.edges), len(mesh.polygons), digest.hexdigest(),
            sorted(a.name for a in mesh.attributes if not a.name.startswith("."))]


def state():
    data = {kind: sorted(getattr(bpy.data, kind).keys()) for kind in KINDS}
    data["scene objects"] = sorted(obj.name for obj in bpy.context.scene.objects)
    data["meshes held"] = {mesh.name: mesh_digest(mesh) for mesh in bpy.data.meshes}
    data["locations"] = {obj.name: [round(c, 3) for c in obj.location] for obj in bpy.data.objects}
    data["hidden"] = sorted(obj.name for obj in bpy.context.view_layer.objects if obj.hide_get())
    active = bpy.context.view_layer.objects.active
    data["active"] = active.name if active is not None else None
    return data


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


def operator_class():
    from road_grammar.operators import city, region, stitch
    return {"grow_region": region.ROADS_OT_grow_region, "stitch": stitch.ROADS_OT_stitch_cities,
            "city": city.ROADS_OT_build_city}[mode]


def running():
    return bool(operator_class()._running)


def run_operator(how):
    """The operator of MODE, as from the sidebar (INVOKE_DEFAULT, no properties) or from a
    script (EXEC_DEFAULT with the panel's settings)."""
    call = getattr(bpy.ops.roads, OPERATORS[mode])
    if how == 'INVOKE_DEFAULT':
        return sorted(call('INVOKE_DEFAULT', True))
    cls = operator_class()
    names = cls._FROM_SETTINGS
    pairs = names.items() if isinstance(names, dict) else ((name, name) for name in names)
    settings = {"city": bpy.context.scene.road_city}.get(mode, bpy.context.scene.road_grammar)
    return sorted(call('EXEC_DEFAULT', True, **{name: getattr(settings, setting) for name, setting in pairs}))


def instrument():
    """Record what the jobs report: progress calls (slowed down while ``slow[0]``), the
    status bar texts and the results of the finished jobs."""
    from road_grammar.core import jobs
    from road_grammar.operators import jobs as job_ops

    progress = jobs.NativeJob.__call__

    def counted(self, fraction, message):
        result["progress_calls"] += 1
        if slow[0]:
            time.sleep(0.3)
        return progress(self, fraction, message)

    jobs.NativeJob.__call__ = counted
    status = job_ops._status_text

    def recorded_status(context, text):
        if text is not None:
            result["status"].append(text)
        return status(context, text)

    job_ops._status_text = recorded_status
    finish_job = job_ops.ModalJobOperator._finish

    def recorded_finish(self, context):
        outcome = finish_job(self, context)
        result["finished"].append(sorted(outcome))
        return outcome

    job_ops.ModalJobOperator._finish = recorded_finish


slow = [False]


def wait_until_done(then):
    """Poll (from timers) until the job has ended, then call ``then``."""
    started = time.monotonic()

    def poll():
        try:
            if running():
                if time.monotonic() - started > TIMEOUT:
                    raise TimeoutError("the job did not end within {} s".format(TIMEOUT))
                return 0.1
            then()
        except Exception:
            fail()
        return None

    bpy.app.timers.register(poll, first_interval=0.1)


def set_up():
    """The scene of MODE, from the road file INPUT."""
    ops = bpy.ops.roads
    result["load"] = [sorted(ops.import_osm('EXEC_DEFAULT', True, filepath=input_path))]
    town = bpy.context.view_layer.objects.active
    if mode == "city":
        return
    result["learn"] = [sorted(ops.learn('EXEC_DEFAULT', True))]
    towns = [town]
    if mode == "stitch":
        result["load"].append(sorted(ops.import_osm('EXEC_DEFAULT', True, filepath=input_path)))
        second = bpy.context.view_layer.objects.active
        second.location = (1800.0, 0.0, 0.0)
        result["learn"].append(sorted(ops.learn('EXEC_DEFAULT', True)))
        towns.append(second)
        corners = [(650.0, -700.0, 0.0), (1150.0, -700.0, 0.0), (1150.0, 700.0, 0.0), (650.0, 700.0, 0.0)]
        name = "Gap"
    else:
        corners = [(700.0, -600.0, 0.0), (1500.0, -600.0, 0.0), (1500.0, 600.0, 0.0), (700.0, 600.0, 0.0)]
        name = "Region"
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(corners, [], [(0, 1, 2, 3)])
    region_obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(region_obj)
    bpy.context.scene.road_grammar.region = region_obj
    for obj in bpy.context.view_layer.objects:
        obj.select_set(obj in towns)
    bpy.context.view_layer.objects.active = town
    bpy.context.view_layer.update()


def start():
    try:
        sys.path.insert(0, addon_parent)
        addon_utils.enable("road_grammar", default_set=True, handle_error=_raise)
        instrument()
        window, override = window_context()
        with override:
            set_up()
            result["finished"].clear()  # (Learn's)
            result["progress_calls"] = 0
            bpy.ops.ed.undo_push(message="before")
            result["before"] = state()
            slow[0] = True
            result["escape_invoke"] = run_operator('INVOKE_DEFAULT')
            result["escape_was_running"] = running()
        bpy.app.timers.register(_press_escape, first_interval=0.6)
    except Exception:
        fail()


def _press_escape():
    try:
        result["running_at_escape"] = running()
        window = bpy.context.window_manager.windows[0]
        window.event_simulate(type='ESC', value='PRESS')
        window.event_simulate(type='ESC', value='RELEASE')
        wait_until_done(_after_escape)
    except Exception:
        fail()
    return None


def _after_escape():
    window, override = window_context()
    with override:
        result["escaped"] = state()
        result["escape_status"], result["status"] = result["status"], []
        result["escape_progress_calls"], result["progress_calls"] = result["progress_calls"], 0
        slow[0] = False
        result["modal_invoke"] = run_operator('INVOKE_DEFAULT')
        result["modal_was_running"] = running()
    wait_until_done(_after_modal)


def _after_modal():
    window, override = window_context()
    with override:
        result["modal"] = state()
        result["undo"] = sorted(bpy.ops.ed.undo())
        result["undone"] = state()
        result["sync"] = run_operator('EXEC_DEFAULT')
        result["synced"] = state()
    finish()


# The window and its undo stack exist once the event loop runs.
bpy.app.timers.register(start, first_interval=0.5)
