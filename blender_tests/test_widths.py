"""Road widths: width tag, else lanes x lane width, else the class default (preferences)."""

import bpy
import numpy as np
import pytest

from conftest import edge_attribute, evaluated_mesh_arrays, import_roads, road_objects, write_osm
from road_grammar.core.polylines import polyline_segments
from road_grammar.display.nodes import input_sockets
from road_grammar.data import preferences as addon_preferences

LAT, LON = 46.0, 8.95
STEP = 0.001  # degrees between the test roads (about 110 m north-south)


def _parallel_roads(path, tagged):
    """One straight east-west road per entry of ``tagged`` (a list of tag dicts), 100 m long."""
    nodes, ways = {}, []
    for i, tags in enumerate(tagged):
        a, b = 2 * i + 1, 2 * i + 2
        nodes[a] = (LAT + i * STEP, LON)
        nodes[b] = (LAT + i * STEP, LON + 0.0013)
        ways.append((100 + i, [a, b], tags))
    return write_osm(path, nodes, ways)


def test_road_widths_rule(ggg):
    """The library's rule, as the add-on calls it: tag, else lanes, else the class's width."""
    classes = list(ggg.highway_classes())
    positions = np.array([[0.0, 0.0], [100.0, 0.0], [0.0, 50.0], [100.0, 50.0], [0.0, 100.0], [100.0, 100.0]])
    graph = ggg.Graph.from_arrays(positions, np.array([[0, 1], [2, 3], [4, 5]]),
                                  edge_highway=np.array([classes.index(c) for c in ("primary", "residential", "path")]),
                                  edge_width=np.array([7.5, np.nan, np.nan]), edge_lanes=np.array([4, 2, 0]))
    table = [10.0] * len(classes)
    table[classes.index("path")] = 2.5
    np.testing.assert_allclose(ggg.road_widths(graph, class_widths=table, lane_width=3.0), [7.5, 6.0, 2.5])
    np.testing.assert_allclose(ggg.road_widths(graph)[2], ggg.default_widths()["path"])


def test_widths_in_the_imported_meshes(tmp_path, ggg, prefs):
    path = _parallel_roads(tmp_path / "roads.osm", [
        {"highway": "residential", "width": "7.5"},
        {"highway": "residential", "lanes": "2"},
        {"highway": "residential"},
        {"highway": "primary"},
    ])
    defaults = ggg.default_widths()
    assert import_roads(path) == {'FINISHED'}
    graph_obj, surface_obj = road_objects()
    graph = ggg.read_graph(str(path))
    order = np.argsort(graph.positions[graph.edges[:, 0], 1])  # roads from south to north
    widths = edge_attribute(graph_obj.data, "width")[order]
    np.testing.assert_allclose(widths, [7.5, 2 * 3.25, defaults["residential"], defaults["primary"]],
                               rtol=1e-6)
    assert defaults["primary"] > defaults["residential"]

    # Each ribbon is as wide as its road: half the width on each side of the centre line.
    positions, _, _ = evaluated_mesh_arrays(surface_obj)
    centre_y = np.sort(np.unique(np.round(graph.positions[:, 1], 3)))
    for y, width in zip(centre_y, widths):
        near = positions[np.abs(positions[:, 1] - y) < 20.0]
        assert near[:, 1].max() - near[:, 1].min() == pytest.approx(width, abs=1e-3)


def test_preferences_change_widths(tmp_path, ggg, prefs):
    path = _parallel_roads(tmp_path / "roads.osm", [
        {"highway": "residential", "lanes": "3"},
        {"highway": "residential"},
    ])
    addon_preferences.ensure_class_widths(prefs, ggg)
    prefs.class_widths["residential"].width = 9.0
    prefs.lane_width = 3.0
    assert import_roads(path) == {'FINISHED'}
    graph_obj, _ = road_objects()
    widths = sorted(edge_attribute(graph_obj.data, "width").tolist())
    assert widths == pytest.approx([9.0, 9.0])  # 3 lanes x 3.0 m and the residential default


def test_preferences_filled_from_native_defaults(ggg, prefs):
    prefs.class_widths.clear()
    prefs.filled_for = ""
    assert bpy.ops.roads.reset_widths() == {'FINISHED'}
    assert [item.name for item in prefs.class_widths] == list(ggg.highway_classes())
    for item in prefs.class_widths:
        assert item.width == pytest.approx(ggg.default_widths()[item.name])
    assert prefs.lane_width == pytest.approx(3.25)


def test_width_scale_input_is_non_destructive(tmp_path, ggg):
    path = _parallel_roads(tmp_path / "roads.osm", [{"highway": "residential", "width": "6"}])
    assert import_roads(path) == {'FINISHED'}
    _, surface_obj = road_objects()
    modifier = surface_obj.modifiers[0]
    scale = next(s for s in input_sockets(modifier.node_group) if s.name == "Width Scale")
    modifier[scale.identifier] = 2.0
    surface_obj.data.update()
    positions, _, _ = evaluated_mesh_arrays(surface_obj)
    assert positions[:, 1].max() - positions[:, 1].min() == pytest.approx(12.0, abs=1e-3)


def test_polyline_segments():
    offsets = np.array([0, 3, 3, 5])  # edge 1 has no points: the straight segment
    points = np.array([[0, 0], [1, 0], [2, 0], [5, 5], [6, 6]], dtype=float)
    positions = np.array([[0, 0], [2, 0], [9, 9], [5, 5], [6, 6]], dtype=float)
    edges = np.array([[0, 1], [1, 2], [3, 4]])
    out_points, segments, owner = polyline_segments(offsets, points, positions, edges)
    np.testing.assert_array_equal(owner, [0, 0, 1, 2])
    np.testing.assert_allclose(out_points[segments[:, 0]], [[0, 0], [1, 0], [2, 0], [5, 5]])
    np.testing.assert_allclose(out_points[segments[:, 1]], [[1, 0], [2, 0], [9, 9], [6, 6]])
