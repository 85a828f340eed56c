"""Fixtures for the tests that run inside Blender (see run.py)."""

import os
import sys
from pathlib import Path
from xml.sax.saxutils import quoteattr

import bpy
import numpy as np
import pytest

REPO = Path(__file__).resolve().parent.parent
SAMPLE_CITY = REPO / "samples" / "sample_city.osm"
SHARED_DIR = Path(os.environ.get("GGG_SHARED_DIR", REPO.parent / "shared"))
PARIS = SHARED_DIR / "osm" / "paris_marais.osm.pbf"

# The add-on is enabled by run.py before pytest starts.
import road_grammar  # noqa: E402
from road_grammar import importer, native, operators, preferences  # noqa: E402,F401

DATA_COLLECTIONS = ("objects", "meshes", "materials", "node_groups", "collections", "curves",
                    "cameras", "lights", "images", "texts")


@pytest.fixture(scope="session")
def ggg():
    """The native module; a test that needs it fails (not skips) when it does not load."""
    try:
        return native.load()
    except native.NativeModuleError as ex:
        pytest.fail("the native module is required: {}".format(ex), pytrace=False)


@pytest.fixture(autouse=True)
def empty_scene():
    """Every test starts from an empty file (the add-on and its preferences stay)."""
    bpy.ops.wm.read_homefile(use_empty=True)
    yield bpy.context.scene


@pytest.fixture
def prefs():
    """The add-on preferences, restored after the test."""
    p = preferences.get(bpy.context)
    lane_width = p.lane_width
    widths = {item.name: item.width for item in p.class_widths}
    yield p
    p.lane_width = lane_width
    p.class_widths.clear()
    for name, width in widths.items():
        item = p.class_widths.add()
        item.name, item.width = name, width
    p.filled_for = ""


@pytest.fixture
def sample_city():
    if not SAMPLE_CITY.is_file():
        pytest.skip("{} is absent: generate it with `python3 samples/make_sample_city.py`".format(SAMPLE_CITY))
    return SAMPLE_CITY


@pytest.fixture
def paris():
    if not PARIS.is_file():
        pytest.skip("{} is absent: the shared OSM extracts (../shared/osm, or $GGG_SHARED_DIR) "
                    "are not on this machine".format(PARIS))
    return PARIS


@pytest.fixture
def execute_results(monkeypatch):
    """The values the import operator's execute() returned, in order.

    bpy.ops raises RuntimeError when an operator reports an error and drops its return
    value; wrapping execute on the class shows that it was {'CANCELLED'}."""
    results = []
    original = operators.ROADS_OT_import_osm.execute

    def recording_execute(self, context):
        result = original(self, context)
        results.append(result)
        return result

    monkeypatch.setattr(operators.ROADS_OT_import_osm, "execute", recording_execute)
    return results


def snapshot():
    """Names of every datablock of the kinds an import could create, and the scene's keys."""
    state = {kind: sorted(getattr(bpy.data, kind).keys()) for kind in DATA_COLLECTIONS}
    state["scene keys"] = sorted(bpy.context.scene.keys())
    state["scene objects"] = sorted(o.name for o in bpy.context.scene.objects)
    return state


def import_roads(path, **options):
    return bpy.ops.roads.import_osm(filepath=str(path), **options)


def road_objects():
    """(graph object, surface object) of the only import in the scene."""
    graphs = [o for o in bpy.context.scene.objects if o.get(importer.GRAPH_KEY)]
    surfaces = [o for o in bpy.context.scene.objects if o.get(importer.SURFACE_KEY)]
    assert len(graphs) == 1 and len(surfaces) <= 1
    return graphs[0], (surfaces[0] if surfaces else None)


def edge_attribute(mesh, name, dtype=np.float64):
    attribute = mesh.attributes[name]
    assert attribute.domain == 'EDGE'
    values = np.empty(len(attribute.data), dtype=dtype)
    attribute.data.foreach_get("value", values)
    return values


def evaluated_mesh_arrays(obj):
    """(vertex positions (N, 3), polygon normals (F, 3)) of the evaluated object, local space."""
    depsgraph = bpy.context.evaluated_depsgraph_get()
    evaluated = obj.evaluated_get(depsgraph)
    mesh = evaluated.to_mesh()
    try:
        co = np.empty(len(mesh.vertices) * 3, dtype=np.float64)
        mesh.vertices.foreach_get("co", co)
        normals = np.empty(len(mesh.polygons) * 3, dtype=np.float64)
        mesh.polygons.foreach_get("normal", normals)
        attributes = {a.name: a.data_type for a in mesh.attributes}
    finally:
        evaluated.to_mesh_clear()
    return co.reshape(-1, 3), normals.reshape(-1, 3), attributes


def write_osm(path, nodes, ways):
    """A small OSM XML file: nodes {id: (lat, lon)}, ways [(id, [node ids], {tag: value})]."""
    lines = ["<?xml version='1.0' encoding='UTF-8'?>", "<osm version='0.6' generator='blender_tests'>"]
    for node_id, (lat, lon) in nodes.items():
        lines.append("  <node id='{}' version='1' lat='{:.8f}' lon='{:.8f}'/>".format(node_id, lat, lon))
    for way_id, refs, tags in ways:
        lines.append("  <way id='{}' version='1'>".format(way_id))
        lines.extend("    <nd ref='{}'/>".format(ref) for ref in refs)
        lines.extend("    <tag k={} v={}/>".format(quoteattr(k), quoteattr(v)) for k, v in tags.items())
        lines.append("  </way>")
    lines.append("</osm>")
    Path(path).write_text("\n".join(lines) + "\n", encoding="utf-8")
    return Path(path)


def pytest_report_header(config):
    try:
        module = native.load()
        where = "ggg {} from {}".format(getattr(module, "__version__", "?"), module.__file__)
    except native.NativeModuleError as ex:
        where = "ggg not loadable: {}".format(ex)
    return ["Blender {} (Python {})".format(bpy.app.version_string, sys.version.split()[0]),
            "add-on {} from {}".format(".".join(map(str, road_grammar.bl_info["version"])),
                                       Path(road_grammar.__file__).parent),
            where]
