"""Finding the native module, and what the user is told when it cannot be used."""

import importlib.machinery
import os
import sys
from pathlib import Path

import bpy
import pytest

import road_grammar
from conftest import import_roads, snapshot
from road_grammar.core import native
from road_grammar.ui import roads as roads_ui


def test_module_loads(ggg):
    assert callable(ggg.read_graph)
    module, message = native.status()
    assert module is ggg and "ggg" in message


def test_zip_bundles_the_module(ggg):
    """With run.py --zip, the module must come from inside the unpacked add-on."""
    if "ROAD_GRAMMAR_TEST_ZIP" not in os.environ:
        pytest.skip("not testing a packaged zip (run with scripts/run_blender_tests.sh --zip ZIP)")
    assert "GGG_MODULE_DIR" not in os.environ
    assert Path(ggg.__file__).parent == Path(road_grammar.__file__).parent / "native"


@pytest.fixture
def isolated_search(monkeypatch, tmp_path):
    """An empty bundled folder and GGG_MODULE_DIR, and no ggg imported yet."""
    bundled = tmp_path / "bundled"
    build = tmp_path / "build"
    bundled.mkdir()
    build.mkdir()
    monkeypatch.delitem(sys.modules, "ggg", raising=False)
    monkeypatch.setattr(native, "BUNDLED_DIR", bundled)
    monkeypatch.setattr(native, "_module", None)
    monkeypatch.setattr(native, "_failure", None)
    monkeypatch.setenv(native.ENV_VAR, str(build))
    return bundled, build


def test_module_built_for_another_python(isolated_search):
    _, build = isolated_search
    other = "3{}".format(sys.version_info.minor + 1)
    (build / "ggg.cpython-{}-x86_64-linux-gnu.so".format(other)).write_bytes(b"\x7fELF not really")
    with pytest.raises(native.NativeModuleError) as error:
        native.load()
    message = str(error.value)
    running = "{}.{}".format(*sys.version_info[:2])
    assert "Python 3.{}".format(sys.version_info.minor + 1) in message
    assert "Blender runs Python {}".format(running) in message
    assert importlib.machinery.EXTENSION_SUFFIXES[0] in message
    assert "Rebuild" in message


def test_module_missing(isolated_search):
    bundled, build = isolated_search
    with pytest.raises(native.NativeModuleError) as error:
        native.load()
    message = str(error.value)
    assert str(bundled) in message and str(build) in message and native.ENV_VAR in message


def test_broken_module_file(isolated_search):
    bundled, _ = isolated_search
    (bundled / ("ggg" + importlib.machinery.EXTENSION_SUFFIXES[0])).write_bytes(b"not a shared library")
    with pytest.raises(native.NativeModuleError, match="Cannot load the native module"):
        native.load()


def test_failure_is_remembered_until_something_changes(isolated_search):
    _, build = isolated_search
    with pytest.raises(native.NativeModuleError):
        native.load()
    failure = native._failure
    with pytest.raises(native.NativeModuleError):
        native.load()
    assert native._failure is failure
    (build / "ggg.cpython-30-x86_64-linux-gnu.so").write_bytes(b"")
    with pytest.raises(native.NativeModuleError, match="another Python"):
        native.load()


def test_import_without_module_reports_and_changes_nothing(isolated_search, paris, execute_results):
    module, message = native.status()
    assert module is None and "not found" in message
    before = snapshot()
    with pytest.raises(RuntimeError, match="native module 'ggg' was not found"):
        import_roads(paris)
    assert execute_results == [{'CANCELLED'}]
    assert snapshot() == before


def test_register_unregister_round_trip():
    road_grammar.unregister()
    assert not hasattr(bpy.types, "ROADS_OT_import_osm")
    road_grammar.register()
    assert hasattr(bpy.types, "ROADS_OT_import_osm")
    entries = bpy.types.TOPBAR_MT_file_import._dyn_ui_initialize()
    assert entries.count(roads_ui.menu_import) == 1
