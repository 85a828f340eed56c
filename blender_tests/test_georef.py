"""Scene georeference: BlenderGIS keys, and imports of neighbouring extracts lining up."""

import math

import bpy
import numpy as np
import pytest
from mathutils import Vector

from conftest import import_roads, write_osm
from road_grammar import georef, importer


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


def test_tmerc_matches_the_native_projection(tmp_path, ggg):
    path, nodes = _grid(tmp_path / "grid.osm", 45.98, 8.93, 1, n=6, step=0.01)
    graph = ggg.read_graph(str(path))
    lat0, lon0 = graph.origin_latlon
    frame = georef.parse_tmerc(georef.proj_string(lat0, lon0))
    assert frame == pytest.approx((lat0, lon0, 1.0, 0.0, 0.0))
    for vertex, osm_id in enumerate(graph.vertex_osm_ids):
        x, y = georef.tmerc_forward(*nodes[int(osm_id)], frame)
        assert graph.positions[vertex] == pytest.approx((x, y), abs=1e-3)


def test_second_import_lines_up_with_the_first(tmp_path, ggg):
    # Two grids about 4 km apart that share one street corner (same OSM node, same place).
    first, first_nodes = _grid(tmp_path / "west.osm", 46.00, 8.90, 1)
    second, second_nodes = _grid(tmp_path / "east.osm", 46.006, 8.906, 100)
    shared_first, shared_second = 1 + 3 * 4 + 3, 100  # (46.006, 8.906) in both
    assert first_nodes[shared_first] == pytest.approx(second_nodes[shared_second])

    assert import_roads(first) == {'FINISHED'}
    srid = bpy.context.scene["SRID"]
    west = bpy.context.active_object
    assert import_roads(second) == {'FINISHED'}
    east = bpy.context.active_object
    assert bpy.context.scene["SRID"] == srid, "a later import must keep the scene's georeference"
    assert east.location.length > 100.0
    assert 0.0 < abs(east.rotation_euler.z) < math.radians(1.0)  # meridian convergence

    west_xy = _world_xy(west)[list(ggg.read_graph(str(first)).vertex_osm_ids).index(shared_first)]
    east_xy = _world_xy(east)[list(ggg.read_graph(str(second)).vertex_osm_ids).index(shared_second)]
    assert east_xy == pytest.approx(west_xy, abs=0.01)
    surface = next(c for c in east.children if c.get(importer.SURFACE_KEY))
    assert surface.matrix_world == east.matrix_world


def test_foreign_georeference_is_kept_with_a_warning(tmp_path, ggg):
    scene = bpy.context.scene
    scene["SRID"] = "EPSG:3857"
    scene["crs x"], scene["crs y"] = 996000.0, 5780000.0
    path, _ = _grid(tmp_path / "grid.osm", 46.0, 8.95, 1)
    assert import_roads(path) == {'FINISHED'}
    assert scene["SRID"] == "EPSG:3857" and scene["crs x"] == 996000.0
    assert tuple(bpy.context.active_object.location) == (0.0, 0.0, 0.0)
    placement = georef.placement(scene, 46.0, 8.95)
    assert placement.warning and "EPSG:3857" in placement.warning


def test_parse_tmerc():
    assert georef.parse_tmerc("EPSG:4326") is None
    assert georef.parse_tmerc(None) is None
    assert georef.parse_tmerc("+proj=tmerc +lat_0=1 +lon_0=2 +k=0.9996 +x_0=500000 +y_0=0 +ellps=WGS84 "
                              "+units=m") == (1.0, 2.0, 0.9996, 500000.0, 0.0)
    assert georef.parse_tmerc("+proj=tmerc +lat_0=1 +lon_0=2 +ellps=GRS80 +units=m") is None


def test_utm_reference_point():
    # A point in Paris in UTM zone 31N (EPSG:32631): PROJ gives 452482.533 E, 5411717.177 N.
    x, y = georef.tmerc_forward(48.8566, 2.3522, (0.0, 3.0, 0.9996, 500000.0, 0.0))
    assert (x, y) == pytest.approx((452482.533, 5411717.177), abs=0.01)
