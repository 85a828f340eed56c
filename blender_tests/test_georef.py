"""Scene georeference: BlenderGIS keys and lat/lon, and imports of neighbouring extracts
lining up (read into the scene's frame by the native library: the add-on has no projection
code of its own)."""

import bpy
import numpy as np
import pytest
from mathutils import Vector

from conftest import SAMPLE_CITY, import_roads, write_osm
from road_grammar.core import georef
from road_grammar.core.names import SURFACE_KEY


def _grid(path, lat0, lon0, first_id, n=4, step=0.002):
    """An n x n street grid whose node (i, j) is at (lat0 + i*step, lon0 + j*step)."""
    nodes = {}
    for i in range(n):
        for j in range(n):
            nodes[first_id + i * n + j] = (lat0 + i * step, lon0 + j * step)
    ways = []
    for i in range(n):
        ways.append((first_id + i, [first_id + i * n + j for j in range(n)], {"highway": "residential"}))
        ways.append((first_id + n + i, [first_id + j * n + i for j in range(n)], {"highway": "tertiary"}))
    return write_osm(path, nodes, ways), nodes


def _world_xy(obj):
    co = np.empty(len(obj.data.vertices) * 3)
    obj.data.vertices.foreach_get("co", co)
    matrix = obj.matrix_world
    return np.array([(matrix @ Vector(p)).to_2d() for p in co.reshape(-1, 3)])


def _local_xy(obj):
    co = np.empty(len(obj.data.vertices) * 3)
    obj.data.vertices.foreach_get("co", co)
    return co.reshape(-1, 3)[:, :2]


def test_first_import_writes_every_key(tmp_path, ggg):
    path, _ = _grid(tmp_path / "grid.osm", 45.98, 8.93, 1)
    assert import_roads(path) == {'FINISHED'}
    graph = ggg.read_graph(str(path))
    lat, lon = graph.origin_latlon
    scene = bpy.context.scene
    assert scene["SRID"] == graph.crs and scene["SRID"].startswith("+proj=tmerc ")
    assert scene["crs x"] == 0.0 and scene["crs y"] == 0.0
    assert scene["lat"] == pytest.approx(lat) and scene["lon"] == pytest.approx(lon)
    assert scene["latitude"] == pytest.approx(lat) and scene["longitude"] == pytest.approx(lon)
    assert georef.origin(scene) == pytest.approx((lat, lon))
    assert bpy.context.active_object["crs"] == graph.crs


def test_no_projection_code_in_the_add_on():
    """One projection exists, PROJ's in the native library."""
    assert not hasattr(georef, "tmerc_forward") and not hasattr(georef, "proj_string")


def test_second_import_lines_up_with_the_first(tmp_path, ggg):
    # Two grids about 4 km apart that share one street corner (same OSM node, same place).
    first, first_nodes = _grid(tmp_path / "west.osm", 46.00, 8.90, 1)
    second, second_nodes = _grid(tmp_path / "east.osm", 46.006, 8.906, 100)
    shared_first, shared_second = 1 + 3 * 4 + 3, 100  # (46.006, 8.906) in both
    assert first_nodes[shared_first] == pytest.approx(second_nodes[shared_second])

    assert import_roads(first) == {'FINISHED'}
    scene = bpy.context.scene
    srid = scene["SRID"]
    west = bpy.context.active_object
    assert import_roads(second) == {'FINISHED'}
    east = bpy.context.active_object
    assert scene["SRID"] == srid, "a later import must keep the scene's georeference"
    # Read into the scene's frame: no object transform, the frame is the scene's.
    assert tuple(east.location) == (0.0, 0.0, 0.0) and east.rotation_euler.z == 0.0
    assert east["crs"] == srid
    assert (east["origin_lat"], east["origin_lon"]) == pytest.approx((west["origin_lat"], west["origin_lon"]))
    expected = ggg.read_graph(str(second), origin_latlon=(scene["lat"], scene["lon"]))
    np.testing.assert_allclose(_local_xy(east), expected.positions, atol=2e-3)

    west_xy = _world_xy(west)[list(ggg.read_graph(str(first)).vertex_osm_ids).index(shared_first)]
    east_xy = _world_xy(east)[list(ggg.read_graph(str(second)).vertex_osm_ids).index(shared_second)]
    assert east_xy == pytest.approx(west_xy, abs=0.01)
    assert np.linalg.norm(east_xy) > 100.0
    surface = next(c for c in east.children if c.get(SURFACE_KEY))
    assert surface.matrix_world == east.matrix_world


@pytest.mark.parametrize("keys", [("lat", "lon"), ("latitude", "longitude")])
def test_scene_origin_alone_sets_the_frame(tmp_path, ggg, keys):
    """A scene with only an origin (set by hand or a script) gets the frame centred there."""
    scene = bpy.context.scene
    scene[keys[0]], scene[keys[1]] = 46.001, 8.951
    path, _ = _grid(tmp_path / "grid.osm", 46.0, 8.95, 1)
    assert import_roads(path) == {'FINISHED'}
    expected = ggg.read_graph(str(path), origin_latlon=(46.001, 8.951))
    obj = bpy.context.active_object
    np.testing.assert_allclose(_local_xy(obj), expected.positions, atol=2e-3)
    assert scene["SRID"] == expected.crs
    assert scene["lat"] == 46.001 and scene["longitude"] == 8.951


def test_tmerc_with_offsets(tmp_path, ggg):
    """A transverse Mercator SRID with false easting and crs x/y: the object is moved."""
    scene = bpy.context.scene
    scene["SRID"] = "+proj=tmerc +lat_0=46 +lon_0=8.95 +k=1 +x_0=500000 +y_0=0 +ellps=WGS84 +units=m"
    scene["crs x"], scene["crs y"] = 500100.0, 200.0
    path, _ = _grid(tmp_path / "grid.osm", 46.0, 8.95, 1)
    assert import_roads(path) == {'FINISHED'}
    obj = bpy.context.active_object
    assert tuple(obj.location) == pytest.approx((-100.0, -200.0, 0.0))
    expected = ggg.read_graph(str(path), origin_latlon=(46.0, 8.95))
    np.testing.assert_allclose(_local_xy(obj), expected.positions, atol=2e-3)
    assert scene["crs x"] == 500100.0  # kept


def test_foreign_georeference_is_kept_with_a_warning(tmp_path, ggg):
    scene = bpy.context.scene
    scene["SRID"] = "EPSG:3857"
    scene["crs x"], scene["crs y"] = 996000.0, 5780000.0
    path, _ = _grid(tmp_path / "grid.osm", 46.0, 8.95, 1)
    assert import_roads(path) == {'FINISHED'}
    assert scene["SRID"] == "EPSG:3857" and scene["crs x"] == 996000.0
    assert tuple(bpy.context.active_object.location) == (0.0, 0.0, 0.0)
    target = georef.target(scene)
    assert target.origin is None and target.warning and "EPSG:3857" in target.warning


def test_parse_tmerc():
    assert georef.parse_tmerc("EPSG:4326") is None
    assert georef.parse_tmerc(None) is None
    assert georef.parse_tmerc("+proj=tmerc +lat_0=1 +lon_0=2 +k=1 +x_0=500000 +y_0=0 +ellps=WGS84 "
                              "+units=m") == (1.0, 2.0, 500000.0, 0.0)
    # UTM-like scale factors and other ellipsoids are not frames the library reads into.
    assert georef.parse_tmerc("+proj=tmerc +lat_0=1 +lon_0=2 +k=0.9996 +ellps=WGS84 +units=m") is None
    assert georef.parse_tmerc("+proj=tmerc +lat_0=1 +lon_0=2 +ellps=GRS80 +units=m") is None


def test_crs_string_is_the_native_one(ggg):
    graph = ggg.read_graph(str(SAMPLE_CITY)) if SAMPLE_CITY.is_file() else None
    if graph is None:
        pytest.skip("no sample city")
    assert georef.crs_string(ggg, *graph.origin_latlon) == graph.crs
