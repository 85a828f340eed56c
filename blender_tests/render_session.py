"""Runs inside a Blender *with a window* (under Xvfb), driven by test_render_job.py: Render
City as a user runs it from the sidebar (INVOKE_DEFAULT: Blender's own render job, watched by
the operator until it has ended).

Blender stops its render job on a real Esc key only (its render thread looks at a flag that
the keyboard sets, not at events), so this Blender runs without --enable-event-simulate and
presses Esc through the X server's XTest extension (libXtst), as a keyboard does.

On the factory scene (a cube, a light, a camera), into the folder OUTDIR:

1. a still from the sidebar: city.png;
2. an animation of 3 frames from the sidebar: flythrough.mp4;
3. an animation of 400 frames, each frame slowed down, with Esc pressed once the first frame
   is written (skipped, saying so, without libXtst);
4. a still from a script (EXEC_DEFAULT), which renders at once.

It writes, for each run, what invoke returned, what the operator returned and reported, the
status bar texts and the render handlers left behind, as JSON to OUTPUT.

  blender --factory-startup --python render_session.py -- ADDON_PARENT OUTDIR OUTPUT.json
"""

import ctypes
import json
import os
import sys
import time
import traceback

import addon_utils
import bpy

_args = sys.argv[sys.argv.index("--") + 1:]
addon_parent, outdir, output_path = _args[:3]
TIMEOUT = 180.0
TINY = dict(engine='BLENDER_EEVEE', resolution_x=48, resolution_y=32, samples=1)
result = {"runs": {}}
current = {"name": None, "run": None}
slow = [False]


def _raise(ex):
    raise ex


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
    return bpy.context.temp_override(window=window, screen=window.screen, area=area, region=region)


def handlers_left():
    """The add-on's render handlers still in Blender's lists."""
    from road_grammar.core.jobs import RenderProgress
    return sorted(name for name in ("render_write", "render_complete", "render_cancel")
                  for handler in getattr(bpy.app.handlers, name)
                  if isinstance(getattr(handler, "__self__", None), RenderProgress))


def press_escape():
    """A real Esc key press and release through XTest; False without libXtst."""
    try:
        x11 = ctypes.CDLL("libX11.so.6")
        xtst = ctypes.CDLL("libXtst.so.6")
    except OSError:
        return False
    x11.XOpenDisplay.restype = ctypes.c_void_p
    x11.XOpenDisplay.argtypes = [ctypes.c_char_p]
    x11.XKeysymToKeycode.argtypes = [ctypes.c_void_p, ctypes.c_ulong]
    x11.XSetInputFocus.argtypes = [ctypes.c_void_p, ctypes.c_ulong, ctypes.c_int, ctypes.c_ulong]
    x11.XFlush.argtypes = [ctypes.c_void_p]
    x11.XCloseDisplay.argtypes = [ctypes.c_void_p]
    xtst.XTestFakeMotionEvent.argtypes = [ctypes.c_void_p, ctypes.c_int, ctypes.c_int, ctypes.c_int, ctypes.c_ulong]
    xtst.XTestFakeKeyEvent.argtypes = [ctypes.c_void_p, ctypes.c_uint, ctypes.c_int, ctypes.c_ulong]
    display = x11.XOpenDisplay(None)
    if not display:
        return False
    try:
        # Without a window manager the keyboard goes to the window under the pointer.
        xtst.XTestFakeMotionEvent(display, -1, 200, 200, 0)
        x11.XSetInputFocus(display, 1, 1, 0)  # PointerRoot, RevertToPointerRoot, CurrentTime
        code = x11.XKeysymToKeycode(display, 0xFF1B)  # XK_Escape
        xtst.XTestFakeKeyEvent(display, code, 1, 0)
        xtst.XTestFakeKeyEvent(display, code, 0, 0)
        x11.XFlush(display)
    finally:
        x11.XCloseDisplay(display)
    return True


def instrument():
    """Record the status bar texts, the operator's outcome (report) and result, and slow each
    written frame down while ``slow[0]``."""
    from road_grammar.core import jobs
    from road_grammar.operators import jobs as job_ops

    status = job_ops._status_text

    def recorded_status(context, text):
        if text is not None and current["run"] is not None:
            current["run"]["status"].append(text)
        return status(context, text)

    job_ops._status_text = recorded_status
    outcome = jobs.RenderProgress.outcome

    def recorded_outcome(self, file_exists):
        found = outcome(self, file_exists)
        current["run"]["report"] = list(found)
        current["run"]["written"] = self.written
        return found

    jobs.RenderProgress.outcome = recorded_outcome
    end = job_ops.ModalRenderOperator._end

    def recorded_end(self, context):
        returned = end(self, context)
        current["run"]["finished"] = sorted(returned)
        return returned

    job_ops.ModalRenderOperator._end = recorded_end

    def slowly(*_args):
        if slow[0]:
            time.sleep(0.3)

    bpy.app.handlers.render_write.append(slowly)


def rendering():
    from road_grammar.operators import jobs as job_ops
    return bool(job_ops.renders)


def file_size(run):
    path = os.path.join(outdir, "flythrough.mp4" if run["animation"] else "city.png")
    return os.path.getsize(path) if os.path.isfile(path) else None


def start_run(name, animation, frames, how='INVOKE_DEFAULT'):
    scene = bpy.context.scene
    scene.frame_start, scene.frame_end = 1, frames
    run = {"status": [], "esc": None, "animation": animation}
    result["runs"][name] = run
    current["name"], current["run"] = name, run
    with window_context():
        run["invoke"] = sorted(bpy.ops.roads.render_city(how, True, animation=animation, directory=outdir, **TINY))
    run["running"] = rendering()
    run["job_running"] = bpy.app.is_job_running('RENDER')
    run["handlers"] = handlers_left()
    return run


def wait_until_done(run, then, escape=False):
    """Poll (from timers) until the render has ended (pressing Esc once a frame is written,
    with ``escape``), then call ``then``."""
    started = time.monotonic()

    def poll():
        try:
            from road_grammar.operators import jobs as job_ops
            progress = next(iter(job_ops.renders.values()), None)
            if progress is not None:
                if time.monotonic() - started > TIMEOUT:
                    raise TimeoutError("the render did not end within {} s".format(TIMEOUT))
                if escape and run["esc"] is None and progress.written >= 1:
                    run["esc"] = "pressed" if press_escape() else "no XTest"
                    if run["esc"] == "no XTest":
                        slow[0] = False  # let it end by itself
                return 0.1
            run["handlers left"] = handlers_left()
            run["file"] = file_size(run)
            then()
        except Exception:
            fail()
        return None

    bpy.app.timers.register(poll, first_interval=0.1)


def start():
    try:
        sys.path.insert(0, addon_parent)
        addon_utils.enable("road_grammar", default_set=True, handle_error=_raise)
        instrument()
        run = start_run("still", False, 1)
        wait_until_done(run, _animation)
    except Exception:
        fail()


def _animation():
    try:
        wait_until_done(start_run("animation", True, 3), _escape)
    except Exception:
        fail()


def _escape():
    try:
        os.remove(os.path.join(outdir, "flythrough.mp4"))
        slow[0] = True
        wait_until_done(start_run("escape", True, 400), _script, escape=True)
    except Exception:
        fail()


def _script():
    try:
        slow[0] = False
        os.remove(os.path.join(outdir, "city.png"))
        run = start_run("script", False, 1, how='EXEC_DEFAULT')
        run["file"] = file_size(run)
        run["handlers left"] = handlers_left()
    except Exception:
        fail()
        return
    finish()


# The window exists once the event loop runs.
bpy.app.timers.register(start, first_interval=0.5)
