"""A file that cannot be imported: an error report, CANCELLED, and the scene unchanged."""

import random

import bpy
import pytest

from conftest import PARIS, import_roads, snapshot, write_osm


def _random_bytes(path, size=8192, seed=7):
    path.write_bytes(random.Random(seed).randbytes(size))
    return path


def _empty(path):
    path.write_bytes(b"")
    return path


def _no_highways(path):
    nodes = {1: (46.0, 8.95), 2: (46.0005, 8.95), 3: (46.0005, 8.9507), 4: (46.0, 8.9507)}
    ways = [(10, [1, 2, 3, 4, 1], {"building": "yes"}),
            (11, [1, 3], {"waterway": "stream", "name": "Rio"})]
    return write_osm(path, nodes, ways)


def _truncated_pbf(path):
    if not PARIS.is_file():
        pytest.skip("{} is absent (shared OSM extracts)".format(PARIS))
    data = PARIS.read_bytes()
    path.write_bytes(data[: len(data) // 2])
    return path


BAD_FILES = {
    "missing file": lambda tmp: tmp / "does_not_exist.osm.pbf",
    "folder": lambda tmp: tmp,
    "empty file": lambda tmp: _empty(tmp / "empty.osm"),
    "random bytes as .osm.pbf": lambda tmp: _random_bytes(tmp / "noise.osm.pbf"),
    "random bytes as .osm": lambda tmp: _random_bytes(tmp / "noise.osm"),
    "random bytes as .osm.bz2": lambda tmp: _random_bytes(tmp / "noise.osm.bz2"),
    "OSM XML without highways": lambda tmp: _no_highways(tmp / "buildings.osm"),
    "truncated PBF": lambda tmp: _truncated_pbf(tmp / "truncated.osm.pbf"),
}


def _assert_rejected(path, execute_results, **options):
    before = snapshot()
    with pytest.raises(RuntimeError) as error:
        import_roads(path, **options)
    message = str(error.value)
    assert message.startswith("Error:"), message
    assert execute_results == [{'CANCELLED'}]
    assert snapshot() == before, "a failed import changed the file"
    return message


@pytest.mark.parametrize("kind", sorted(BAD_FILES))
def test_bad_file_is_rejected(kind, tmp_path, execute_results, ggg):
    path = BAD_FILES[kind](tmp_path)
    message = _assert_rejected(path, execute_results)
    if path.is_file():
        assert path.name in message, "the error should name the file: " + message


def test_bad_file_in_georeferenced_scene_keeps_georeference(tmp_path, execute_results, ggg, paris):
    assert import_roads(paris) == {'FINISHED'}
    execute_results.clear()
    _assert_rejected(_random_bytes(tmp_path / "noise.osm.pbf"), execute_results)


def test_bad_highway_filter(tmp_path, execute_results, ggg, paris):
    message = _assert_rejected(paris, execute_results, highways='CUSTOM', highways_custom="Primary Road!")
    assert "highway" in message


def test_empty_custom_filter(execute_results, ggg, paris):
    message = _assert_rejected(paris, execute_results, highways='CUSTOM', highways_custom=" , ")
    assert "highway" in message


def test_filter_matching_nothing(execute_results, ggg, paris):
    _assert_rejected(paris, execute_results, highways='CUSTOM', highways_custom="bridleway_of_unicorns")


def test_no_bpy_data_leaks_after_many_failures(tmp_path, execute_results, ggg):
    path = _random_bytes(tmp_path / "noise.osm.pbf")
    before = snapshot()
    for _ in range(3):
        with pytest.raises(RuntimeError):
            import_roads(path)
    assert snapshot() == before
    assert len(bpy.data.meshes) == 0 and len(bpy.data.materials) == 0


def test_failure_while_building_leaves_nothing(monkeypatch, ggg, paris):
    """An unexpected error after the read (here: making the modifier) removes what was built."""
    from road_grammar.display import surface

    def broken_add_modifier(obj, group, mat):
        raise MemoryError("simulated failure while building the surface")

    monkeypatch.setattr(surface, "add_modifier", broken_add_modifier)
    before = snapshot()
    with pytest.raises(RuntimeError, match="simulated failure"):
        import_roads(paris)
    assert snapshot() == before
    assert len(bpy.data.meshes) == 0 and len(bpy.data.node_groups) == 0 and len(bpy.data.materials) == 0
