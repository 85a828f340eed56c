"""Undo of an import, of a grow and of a Learn, in a real Blender window.

`blender -b` keeps no undo stack (bpy.ops.ed.undo's poll fails: "Undo disabled at
startup"), so this test starts a second Blender with a window under Xvfb
(undo_session.py) and reads back what it saw. It is skipped, saying why, where
xvfb-run is not installed; test_import.py checks the operator's UNDO flag and
test_bad_input.py that failed imports leave the file unchanged either way.
"""

import json
import os
import shutil
import subprocess
from pathlib import Path

import bpy
import pytest

import road_grammar

HERE = Path(__file__).resolve().parent


def _session(ggg, tmp_path, input_path, mode):
    """Run undo_session.py in a windowed Blender under Xvfb; its JSON result."""
    xvfb_run = shutil.which("xvfb-run")
    if xvfb_run is None:
        pytest.skip("xvfb-run is not installed (apt-get install xvfb xauth): undo needs a Blender "
                    "window, and `blender -b` has no undo stack")
    output = tmp_path / "undo.json"
    env = dict(os.environ)
    env["GGG_MODULE_DIR"] = str(Path(ggg.__file__).parent)
    command = [xvfb_run, "-a", bpy.app.binary_path, "--factory-startup", "--python-exit-code", "1",
               "--python", str(HERE / "undo_session.py"), "--",
               str(Path(road_grammar.__file__).parent.parent), str(input_path), str(output), mode]
    completed = subprocess.run(command, env=env, stdin=subprocess.DEVNULL, capture_output=True,
                               text=True, timeout=300)
    assert output.is_file(), "the windowed Blender wrote nothing:\n" + completed.stdout[-3000:] + \
        completed.stderr[-3000:]
    result = json.loads(output.read_text())
    assert "error" not in result, result.get("error")
    return result


def test_undo_restores_the_scene(paris, ggg, tmp_path):
    result = _session(ggg, tmp_path, paris, "import")
    assert result["import"] == ['FINISHED']
    before, imported = result["before"], result["imported"]
    assert len(imported["objects"]) == len(before["objects"]) + 2
    assert "SRID" in imported["scene keys"] and "SRID" not in before["scene keys"]
    assert result["undo"] == ['FINISHED']
    assert result["undone"] == before
    assert result["redo"] == ['FINISHED']
    assert result["redone"] == imported


def test_undo_of_grow_restores_the_mesh(ggg, tmp_path):
    grammar_path = HERE.parent / "samples" / "sierpinski.grammar.json"
    result = _session(ggg, tmp_path, grammar_path, "grow")
    assert result["load"] == ['FINISHED'] and result["axiom"] == ['FINISHED']
    assert result["grow"] == ['FINISHED']
    before, grown = result["before"], result["imported"]
    assert before["meshes held"]["sierpinski"][:2] == [3, 3]
    assert grown["meshes held"]["sierpinski"][:2] == [15, 27]
    assert grown["meshes held"]["sierpinski Surface"][:2] == [54, 27]
    assert result["undo"] == ['FINISHED']
    assert result["undone"] == before
    assert result["redo"] == ['FINISHED']
    assert result["redone"] == grown


def test_undo_of_learn_removes_the_grammar(sample_city, ggg, tmp_path):
    result = _session(ggg, tmp_path, sample_city, "learn")
    assert result["load"] == ['FINISHED'] and result["learn"] == ['FINISHED']
    before, learned = result["before"], result["imported"]
    assert before["texts"] == [] and before["scene grammar"] is None and before["learned"] == {"sample_city": ""}
    assert learned["texts"] == ["sample_city.grammar.json"]
    assert learned["scene grammar"] == "sample_city.grammar.json"
    assert '"mode": "lossless"' in learned["learned"]["sample_city"]
    assert "sample_city Rules" in learned["objects"] and "sample_city Rules" not in before["objects"]
    assert result["undo"] == ['FINISHED']
    assert result["undone"] == before
    assert result["redo"] == ['FINISHED']
    assert result["redone"] == learned
