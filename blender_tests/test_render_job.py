"""Render City as a job: from the sidebar (render_session.py, in a windowed Blender under Xvfb)
it starts Blender's own render job and returns at once, shows the frames written in the
status bar, and reports the file written, or that the render was cancelled by Esc, once the
job has ended, leaving none of its render handlers behind; from a script and in background
mode it renders at once; while a render of the scene runs, the panel shows its progress
instead of the buttons and a second one is refused."""

import json
import os
import shutil
import subprocess
from pathlib import Path
from types import SimpleNamespace

import bpy
import pytest

import road_grammar
from conftest import HERE, PanelLayout
from road_grammar.core.jobs import RenderProgress
from road_grammar.operators import city as city_ops
from road_grammar.operators import jobs as job_ops
from road_grammar.ui import city as city_ui

TINY = dict(engine='BLENDER_EEVEE', resolution_x=48, resolution_y=32, samples=1)
HANDLERS = ("render_write", "render_complete", "render_cancel")


def _ours():
    """The add-on's render handlers in Blender's lists."""
    return [name for name in HANDLERS for handler in getattr(bpy.app.handlers, name)
            if isinstance(getattr(handler, "__self__", None), RenderProgress)]


@pytest.fixture
def scene_with_camera():
    """A plane under a camera looking down at it."""
    scene = bpy.context.scene
    mesh = bpy.data.meshes.new("Ground")
    mesh.from_pydata([(-5, -5, 0), (5, -5, 0), (5, 5, 0), (-5, 5, 0)], [], [(0, 1, 2, 3)])
    scene.collection.objects.link(bpy.data.objects.new("Ground", mesh))
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    camera.location = (0.0, 0.0, 10.0)
    scene.collection.objects.link(camera)
    scene.camera = camera
    scene.frame_start, scene.frame_end = 1, 3
    yield scene
    for key in list(job_ops.renders):
        job_ops.unwatch_render(key)


# --- in background mode ------------------------------------------------------------------------

def test_invoked_in_background_renders_at_once(scene_with_camera, tmp_path, reports):
    """INVOKE_DEFAULT without a window renders to the end before returning, as from a script."""
    assert bpy.ops.roads.render_city('INVOKE_DEFAULT', directory=str(tmp_path), **TINY) == {'FINISHED'}
    assert (tmp_path / "city.png").is_file()
    assert bpy.ops.roads.render_city('INVOKE_DEFAULT', animation=True, directory=str(tmp_path), **TINY) == \
        {'FINISHED'}
    assert (tmp_path / "flythrough.mp4").stat().st_size > 0
    assert reports()[-1] == ('INFO', "Rendered {}".format(tmp_path / "flythrough.mp4"))
    assert not job_ops.renders and not _ours()


def test_the_handlers_count_what_blender_renders(scene_with_camera, tmp_path):
    """Blender's render handlers, handed to a RenderProgress, count the frames written and say
    when the render is complete; taking them back leaves Blender's lists as they were."""
    before = {name: list(getattr(bpy.app.handlers, name)) for name in HANDLERS}
    scene = scene_with_camera
    city_ops.configure_render(scene, TINY["engine"], TINY["resolution_x"], TINY["resolution_y"], TINY["samples"])
    city_ops.configure_movie(scene)
    path = str(tmp_path / "flythrough.mp4")
    scene.render.filepath = path
    progress = RenderProgress(path, 3)
    job_ops.watch_render(scene.name, progress)
    assert sorted(_ours()) == sorted(HANDLERS) and job_ops.renders == {scene.name: progress}
    assert not city_ops.ROADS_OT_render_city.poll(bpy.context)  # one render of a scene at a time
    bpy.ops.render.render(animation=True)
    assert (progress.written, progress.completed, progress.stopped) == (3, True, False)
    assert progress.outcome(os.path.isfile(path)) == ('INFO', "Rendered {}".format(path))
    assert job_ops.unwatch_render(scene.name) is progress
    assert job_ops.unwatch_render(scene.name) is None  # (twice: nothing happens)
    assert {name: list(getattr(bpy.app.handlers, name)) for name in HANDLERS} == before
    assert city_ops.ROADS_OT_render_city.poll(bpy.context)


def test_disabling_the_add_on_takes_the_handlers_back(scene_with_camera):
    job_ops.watch_render(bpy.context.scene.name, RenderProgress("/nowhere/city.png", 1))
    assert _ours()
    job_ops.stop_all()
    assert not job_ops.renders and not _ours()


def test_the_panel_shows_a_running_render(scene_with_camera):
    progress = RenderProgress("/out/flythrough.mp4", 4)
    progress.on_write(None)
    job_ops.watch_render(bpy.context.scene.name, progress)
    labels, buttons = [], []
    city_ui.VIEW3D_PT_roads_city.draw(SimpleNamespace(layout=PanelLayout(labels, buttons)), bpy.context)
    assert "frame 2 of 4 (25%)" in labels and "Esc cancels" in labels
    assert city_ops.ROADS_OT_render_city.bl_idname not in [idname for idname, _ in buttons]
    progress.cancel()
    labels.clear()
    city_ui.VIEW3D_PT_roads_city.draw(SimpleNamespace(layout=PanelLayout(labels, [])), bpy.context)
    assert "Cancelling\u2026" in labels
    job_ops.unwatch_render(bpy.context.scene.name)
    labels, buttons = [], []
    city_ui.VIEW3D_PT_roads_city.draw(SimpleNamespace(layout=PanelLayout(labels, buttons)), bpy.context)
    still, animation = [properties for idname, properties in buttons
                        if idname == city_ops.ROADS_OT_render_city.bl_idname]
    assert not still["animation"] and animation["animation"]


# --- from the sidebar, in a windowed Blender -------------------------------------------------------

@pytest.fixture(scope="module")
def session(ggg, tmp_path_factory):
    """Run render_session.py in a windowed Blender under Xvfb; its JSON result."""
    xvfb_run = shutil.which("xvfb-run")
    if xvfb_run is None:
        pytest.skip("xvfb-run is not installed (apt-get install xvfb xauth): a render job needs a Blender window")
    folder = tmp_path_factory.mktemp("render_session")
    output = folder / "session.json"
    env = dict(os.environ)
    env["GGG_MODULE_DIR"] = str(Path(ggg.__file__).parent)
    command = [xvfb_run, "-a", bpy.app.binary_path, "--factory-startup", "--python-exit-code", "1",
               "--python", str(HERE / "render_session.py"), "--",
               str(Path(road_grammar.__file__).parent.parent), str(folder), str(output)]
    completed = subprocess.run(command, env=env, stdin=subprocess.DEVNULL, capture_output=True, text=True,
                               timeout=600)
    assert output.is_file(), "the windowed Blender wrote nothing:\n" + completed.stdout[-3000:] + \
        completed.stderr[-3000:]
    result = json.loads(output.read_text())
    assert "error" not in result, result.get("error")
    result["folder"] = str(folder)
    return result


def _check_finished(run, path, label):
    # The operator returned at once, with Blender's render job running and its handlers in.
    assert run["invoke"] == ['RUNNING_MODAL'] and run["running"] and run["job_running"]
    assert sorted(run["handlers"]) == sorted(HANDLERS)
    # The job ended: the file, the report, the status bar; no handler left behind.
    assert run["finished"] == ['FINISHED']
    assert run["report"] == ['INFO', "Rendered {}".format(path)]
    assert run["file"] and run["file"] > 0
    assert run["handlers left"] == []
    assert any(text.startswith(label) and "Esc to cancel" in text for text in run["status"]), run["status"]


def test_a_still_from_the_sidebar(session):
    path = os.path.join(session["folder"], "city.png")
    _check_finished(session["runs"]["still"], path, "Rendering city.png: frame 1 of 1 (0%)")


def test_an_animation_from_the_sidebar(session):
    path = os.path.join(session["folder"], "flythrough.mp4")
    run = session["runs"]["animation"]
    _check_finished(run, path, "Rendering flythrough.mp4: frame ")
    assert run["written"] == 3


def test_esc_cancels_a_render_from_the_sidebar(session):
    run = session["runs"]["escape"]
    assert run["invoke"] == ['RUNNING_MODAL'] and run["running"]
    if run["esc"] == "no XTest":
        pytest.skip("libXtst is not installed (apt-get install libxtst6): Esc cannot be pressed as a keyboard does")
    assert run["esc"] == "pressed"
    assert run["finished"] == ['CANCELLED']
    kind, message = run["report"]
    assert kind == 'WARNING' and message.startswith("Rendering {} was cancelled after ".format(
        os.path.join(session["folder"], "flythrough.mp4"))) and message.endswith(" of 400 frames")
    assert 1 <= run["written"] < 400
    assert run["handlers left"] == []
    # (The key may go to the render's window rather than to the operator's: Blender stops the
    # render either way, and the operator learns it from the render_cancel handler.)
    assert any(text.startswith("Rendering flythrough.mp4: frame ") for text in run["status"]), run["status"]


def test_a_still_from_a_script_in_the_window_renders_at_once(session):
    run = session["runs"]["script"]
    assert run["invoke"] == ['FINISHED'] and not run["running"] and not run["job_running"]
    assert run["file"] and run["file"] > 0
    assert run["handlers left"] == [] and run["handlers"] == []
