"""Grow into Region, Stitch Cities and Build City as jobs: run from the sidebar (modal, in a
worker thread; modal_session.py in a windowed Blender under Xvfb) they report their progress
in the status bar, Esc cancels them and leaves the file as it was, a finished run is one undo
step and makes the same meshes as the run from a script; in background mode they wait for
the worker (cancelled through the progress callback, a cancelled run changes nothing); the
panels show a running job's progress instead of its button."""

import json
import os
import shutil
import subprocess
from pathlib import Path
from types import SimpleNamespace

import bpy
import pytest

import road_grammar
from conftest import HERE, PanelLayout, activate, cancel_at_first_progress, record_executes, snapshot
from road_grammar.core import jobs
from road_grammar.operators import city as city_ops
from road_grammar.operators import region as region_ops
from road_grammar.operators import stitch as stitch_ops
from road_grammar.ui import city as city_ui
from road_grammar.ui import grammar as grammar_ui
from test_grow_region import mesh_region, mesh_state
from test_stitch import scene_state, towns  # noqa: F401 (towns: a fixture)

LABELS = {"grow_region": "Growing sample_city", "stitch": "Stitching sample_city", "city": "Building the city of "
          "sample_city"}


def _session(ggg, tmp_path, input_path, mode):
    """Run modal_session.py in a windowed Blender under Xvfb; its JSON result."""
    xvfb_run = shutil.which("xvfb-run")
    if xvfb_run is None:
        pytest.skip("xvfb-run is not installed (apt-get install xvfb xauth): modal operators need a Blender "
                    "window, and `blender -b` has no undo stack")
    output = tmp_path / "modal.json"
    env = dict(os.environ)
    env["GGG_MODULE_DIR"] = str(Path(ggg.__file__).parent)
    command = [xvfb_run, "-a", bpy.app.binary_path, "--factory-startup", "--enable-event-simulate",
               "--python-exit-code", "1", "--python", str(HERE / "modal_session.py"), "--",
               str(Path(road_grammar.__file__).parent.parent), str(input_path), str(output), mode]
    completed = subprocess.run(command, env=env, stdin=subprocess.DEVNULL, capture_output=True, text=True,
                               timeout=300)
    assert output.is_file(), "the windowed Blender wrote nothing:\n" + completed.stdout[-3000:] + \
        completed.stderr[-3000:]
    result = json.loads(output.read_text())
    assert "error" not in result, result.get("error")
    return result


def _check_session(result, mode):
    before = result["before"]
    label = LABELS[mode]
    # Esc: the job was running, reported its progress, stopped, and nothing changed.
    assert result["escape_invoke"] == ['RUNNING_MODAL']
    assert result["escape_was_running"] and result["running_at_escape"]
    assert result["escape_progress_calls"] >= 1
    assert any(text.startswith(label) and "Esc to cancel" in text for text in result["escape_status"]), \
        result["escape_status"]
    assert result["finished"][0] == ['CANCELLED']
    assert result["escaped"] == before
    # The full run: modal, its progress in the status bar, then one undo step.
    assert result["modal_invoke"] == ['RUNNING_MODAL'] and result["modal_was_running"]
    assert result["finished"][1] == ['FINISHED']
    assert result["progress_calls"] >= 2
    assert any(text.startswith(label) and "%" in text for text in result["status"]), result["status"]
    modal = result["modal"]
    assert modal != before
    assert result["undo"] == ['FINISHED'] and result["undone"] == before
    # From a script: the same meshes.
    assert result["sync"] == ['FINISHED']
    assert result["synced"] == modal
    return before, modal


def test_modal_grow_region(sample_city, ggg, tmp_path):
    result = _session(ggg, tmp_path, sample_city, "grow_region")
    before, modal = _check_session(result, "grow_region")
    old, new = before["meshes held"]["sample_city"], modal["meshes held"]["sample_city"]
    assert new[0] > old[0] and new[1] > old[1]


def test_modal_stitch_cities(sample_city, ggg, tmp_path):
    result = _session(ggg, tmp_path, sample_city, "stitch")
    before, modal = _check_session(result, "stitch")
    assert "sample_city.001" in before["objects"] and "sample_city.001" not in modal["objects"]
    old, new = before["meshes held"]["sample_city"], modal["meshes held"]["sample_city"]
    assert new[0] > 2 * old[0] and new[1] > 2 * old[1]


def test_modal_build_city(sample_city, ggg, tmp_path):
    result = _session(ggg, tmp_path, sample_city, "city")
    before, modal = _check_session(result, "city")
    assert "sample_city City" not in before["collections"] and "sample_city City" in modal["collections"]
    assert modal["meshes held"]["sample_city Buildings"][2] > 100


# --- in background mode: the operators wait for the worker -------------------------------------

@pytest.fixture
def learned_town(town):
    assert bpy.ops.roads.learn() == {'FINISHED'}
    activate(town)
    return town


@pytest.fixture(params=["between the calls", "in the library"])
def cancelling(request, monkeypatch):
    """The jobs cancelled at their first progress report: stopped by the job between the
    library's calls, or (the job's own checks off) by the library through the progress
    callback; the progress calls."""
    if request.param == "in the library":
        monkeypatch.setattr(jobs.StepsJob, "check", lambda self: None)
    return cancel_at_first_progress(monkeypatch, jobs.StepsJob)


def test_grow_region_cancelled_changes_nothing(learned_town, ggg, monkeypatch, reports, cancelling):
    region_obj = mesh_region()
    activate(learned_town)
    results = record_executes(monkeypatch, region_ops.ROADS_OT_grow_region)
    before, mesh = snapshot(), mesh_state(learned_town)
    assert bpy.ops.roads.grow_region(region=region_obj.name) == {'CANCELLED'}
    assert results == [{'CANCELLED'}] and len(cancelling) >= 1
    assert snapshot() == before and mesh_state(learned_town) == mesh
    assert reports()[-1] == ('WARNING', "Growing sample_city was cancelled; nothing changed")
    assert not region_ops.running


def test_stitch_cancelled_changes_nothing(towns, ggg, monkeypatch, reports, cancelling):
    first, second, region_obj = towns
    results = record_executes(monkeypatch, stitch_ops.ROADS_OT_stitch_cities)
    before = scene_state(first, second)
    assert bpy.ops.roads.stitch_cities(region=region_obj.name) == {'CANCELLED'}
    assert results == [{'CANCELLED'}] and len(cancelling) >= 1
    assert scene_state(first, second) == before
    assert reports()[-1] == ('WARNING', "Stitching sample_city was cancelled; nothing changed")


def test_build_city_cancelled_changes_nothing(town, ggg, monkeypatch, reports, cancelling):
    results = record_executes(monkeypatch, city_ops.ROADS_OT_build_city)
    before = snapshot()
    assert bpy.ops.roads.build_city() == {'CANCELLED'}
    assert results == [{'CANCELLED'}] and len(cancelling) >= 1
    assert snapshot() == before
    assert reports()[-1] == ('WARNING', "Building the city of sample_city was cancelled; nothing changed")


def test_progress_is_reported_in_stages(learned_town, ggg, monkeypatch):
    """The progress of a run goes from 0 to 1 without going back, with the library's messages."""
    seen = []
    progress = jobs.StepsJob.__call__

    def recording(self, fraction, message):
        seen.append((fraction, message))
        return progress(self, fraction, message)

    monkeypatch.setattr(jobs.StepsJob, "__call__", recording)
    region_obj = mesh_region()
    activate(learned_town)
    assert bpy.ops.roads.grow_region(region=region_obj.name) == {'FINISHED'}
    fractions = [fraction for fraction, _ in seen]
    assert fractions == sorted(fractions) and fractions[0] == 0.0 and fractions[-1] == 1.0
    assert any(message == "placing rules" for _, message in seen)
    seen.clear()
    assert bpy.ops.roads.build_city() == {'FINISHED'}
    fractions = [fraction for fraction, _ in seen]
    assert fractions == sorted(fractions) and fractions[-1] == 1.0
    assert any(message == "blocks and buildings" for _, message in seen)


def test_invoked_in_background_waits(learned_town, ggg, reports):
    """INVOKE_DEFAULT in background mode (no window, no event: Blender runs execute) waits for
    the job: the mesh is there when the call returns."""
    region_obj = mesh_region()
    bpy.context.scene.road_grammar.region = region_obj
    activate(learned_town)
    count = len(learned_town.data.vertices)
    assert bpy.ops.roads.grow_region('INVOKE_DEFAULT') == {'FINISHED'}
    assert reports()[-1][1].startswith("Grew sample_city into Region:")
    assert len(learned_town.data.vertices) > count and not region_ops.running
    assert bpy.ops.roads.build_city('INVOKE_DEFAULT') == {'FINISHED'}
    assert "sample_city City" in bpy.data.collections and not city_ops.running


def test_panels_show_a_running_job(learned_town, ggg):
    """While a job runs on the active graph, its box shows the progress, not its button."""
    job = jobs.StepsJob(ggg, lambda job: None)
    job(0.25, "placing rules")
    for operator, panel in ((region_ops.ROADS_OT_grow_region, grammar_ui.VIEW3D_PT_roads_grammar),
                            (stitch_ops.ROADS_OT_stitch_cities, grammar_ui.VIEW3D_PT_roads_grammar),
                            (city_ops.ROADS_OT_build_city, city_ui.VIEW3D_PT_roads_city)):
        operator._running[learned_town.name] = job
        try:
            labels, buttons = [], []
            panel.draw(SimpleNamespace(layout=PanelLayout(labels, buttons)), bpy.context)
            assert "placing rules (25%)" in labels and "Esc cancels" in labels
            assert operator.bl_idname not in [idname for idname, _ in buttons]
            assert not operator.poll(bpy.context)
        finally:
            operator._running.clear()
        assert operator.poll(bpy.context)
