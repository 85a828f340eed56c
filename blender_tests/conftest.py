"""Fixtures for the tests that run inside Blender (see run.py)."""

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path
from types import SimpleNamespace
from xml.sax.saxutils import quoteattr

import bpy
import numpy as np
import pytest

REPO = Path(__file__).resolve().parent.parent
SAMPLE_CITY = REPO / "samples" / "sample_city.osm"
SHARED_DIR = Path(os.environ.get("GGG_SHARED_DIR", REPO.parent / "shared"))
PARIS = SHARED_DIR / "osm" / "paris_marais.osm.pbf"
HERE = Path(__file__).resolve().parent

# The street grid of the analyzer's tests (write_grid): 5 x 5 streets, 100 m blocks (16
# squares), with two dead-end spurs that belong to no square: one 60 m east of the middle of
# the east side, and a curved footway (two shape nodes) ending 50 m south-west of a corner.
SPACING = 100.0
SIZE = 5
LAT0, LON0 = 46.0, 8.95
M_PER_DEG_LAT = 111_195.0

# The add-on is enabled by run.py before pytest starts.
import road_grammar  # noqa: E402
from road_grammar.core import native  # noqa: E402,F401
from road_grammar.core.names import GRAPH_KEY, SURFACE_KEY  # noqa: E402,F401
from road_grammar.operators import importer as import_ops  # noqa: E402,F401
from road_grammar.data import preferences  # noqa: E402,F401

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
def town(sample_city, ggg):
    """The imported sample town's graph object (active, Object Mode)."""
    assert import_roads(sample_city) == {'FINISHED'}
    obj = bpy.context.active_object
    assert obj.get("road_graph") and len(obj.data.edges) > 100
    return obj


@pytest.fixture
def grid(tmp_path, ggg):
    """The imported street grid (write_grid)'s graph object (active, Object Mode)."""
    assert import_roads(write_grid(tmp_path / "grid.osm"), highways='ALL') == {'FINISHED'}
    obj = bpy.context.active_object
    assert len(obj.data.vertices) == SIZE * SIZE + 2 and len(obj.data.edges) == 2 * SIZE * (SIZE - 1) + 2
    return obj


@pytest.fixture
def reports(capsys):
    """The (type, message) reports printed so far (background Blender prints them)."""
    kinds = {"Info": 'INFO', "Warning": 'WARNING', "Error": 'ERROR'}
    seen = []

    def read():
        for line in capsys.readouterr().out.splitlines():
            kind, _, message = line.partition(": ")
            if kind in kinds:
                seen.append((kinds[kind], message))
        return seen

    return read


def record_executes(monkeypatch, *classes):
    """The values the execute() of the operator ``classes`` returned, in order.

    bpy.ops raises RuntimeError when an operator reports an error and drops its return
    value; wrapping execute on the class shows that it was {'CANCELLED'}."""
    results = []

    def recorder(original):
        def recording_execute(self, context):
            result = original(self, context)
            results.append(result)
            return result
        return recording_execute

    for cls in classes:
        monkeypatch.setattr(cls, "execute", recorder(cls.execute))
    return results


def cancel_at_first_progress(monkeypatch, job_class):
    """Make the native jobs of ``job_class`` (a jobs.NativeJob) cancel at their first progress
    call; the (fraction, message) of every progress call."""
    calls = []
    original = job_class.__call__

    def cancelling(self, fraction, message):
        calls.append((fraction, message))
        original(self, fraction, message)
        self.cancel()  # as Esc does: the next answer to the library is "stop"
        return self.keep_going()

    monkeypatch.setattr(job_class, "__call__", cancelling)
    return calls


@pytest.fixture
def execute_results(monkeypatch):
    """The values the import operator's execute() returned, in order."""
    return record_executes(monkeypatch, import_ops.ROADS_OT_import_osm)


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
    graphs = [o for o in bpy.context.scene.objects if o.get(GRAPH_KEY)]
    surfaces = [o for o in bpy.context.scene.objects if o.get(SURFACE_KEY)]
    assert len(graphs) == 1 and len(surfaces) <= 1
    return graphs[0], (surfaces[0] if surfaces else None)


def activate(obj, *others):
    """``obj`` active and selected, with ``others``; nothing else selected."""
    for o in bpy.context.view_layer.objects:
        o.select_set(o == obj or o in others)
    bpy.context.view_layer.objects.active = obj


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


def _latlon(x, y):
    lon_scale = M_PER_DEG_LAT * np.cos(np.radians(LAT0))
    return LAT0 + y / M_PER_DEG_LAT, LON0 + x / lon_scale


def write_grid(path):
    """The street grid (SIZE x SIZE streets SPACING apart, and the two spurs) as OSM XML."""
    nodes = {}
    for j in range(SIZE):
        for i in range(SIZE):
            nodes[1 + j * SIZE + i] = _latlon(i * SPACING, j * SPACING)
    nodes[100] = _latlon((SIZE - 1) * SPACING + 60.0, 2 * SPACING)
    nodes[101] = _latlon(-35.0, -35.0)
    nodes[102], nodes[103] = _latlon(-5.0, -20.0), _latlon(-15.0, -33.0)
    ways = []
    for j in range(SIZE):
        ways.append((1000 + j, [1 + j * SIZE + i for i in range(SIZE)], {"highway": "residential"}))
    for i in range(SIZE):
        ways.append((2000 + i, [1 + j * SIZE + i for j in range(SIZE)], {"highway": "residential"}))
    ways.append((3000, [1 + 2 * SIZE + SIZE - 1, 100], {"highway": "service"}))
    ways.append((3001, [1, 102, 103, 101], {"highway": "footway"}))
    return write_osm(path, nodes, ways)


class PanelLayout:
    """Stands in for a UILayout: records labels and the operator buttons (idname and the
    properties set on them), accepts everything else."""

    def __init__(self, labels, buttons=None):
        self._labels = labels
        self._buttons = [] if buttons is None else buttons

    def label(self, text="", **_kwargs):
        self._labels.append(text)

    def operator(self, idname, **_kwargs):
        properties = {}
        self._buttons.append((idname, properties))
        return _Button(properties)

    def __getattr__(self, name):
        return lambda *args, **kwargs: PanelLayout(self._labels, self._buttons)


class _Button:
    def __init__(self, properties):
        object.__setattr__(self, "_properties", properties)

    def __setattr__(self, name, value):
        self._properties[name] = value


def draw_panel(panel):
    """The labels the panel class ``panel`` draws, one a line."""
    labels = []
    panel.draw(SimpleNamespace(layout=PanelLayout(labels)), bpy.context)
    return "\n".join(labels)


def run_analysis_session(ggg, tmp_path, input_path, mode, *extra_flags):
    """Run analysis_session.py in a windowed Blender under Xvfb on ``input_path``; its JSON
    result (skipped without xvfb-run)."""
    xvfb_run = shutil.which("xvfb-run")
    if xvfb_run is None:
        pytest.skip("xvfb-run is not installed (apt-get install xvfb xauth): undo and modal operators need a "
                    "Blender window, and `blender -b` has no undo stack")
    output = tmp_path / "session.json"
    env = dict(os.environ)
    env["GGG_MODULE_DIR"] = str(Path(ggg.__file__).parent)
    command = [xvfb_run, "-a", bpy.app.binary_path, "--factory-startup", *extra_flags, "--python-exit-code", "1",
               "--python", str(HERE / "analysis_session.py"), "--",
               str(Path(road_grammar.__file__).parent.parent), str(input_path), str(output), mode]
    completed = subprocess.run(command, env=env, stdin=subprocess.DEVNULL, capture_output=True, text=True,
                               timeout=300)
    assert output.is_file(), "the windowed Blender wrote nothing:\n" + completed.stdout[-3000:] + \
        completed.stderr[-3000:]
    result = json.loads(output.read_text())
    assert "error" not in result, result.get("error")
    return result


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
