"""The import operator on real and generated OpenStreetMap data."""

import math

import bpy
import numpy as np
import pytest

from conftest import edge_attribute, evaluated_mesh_arrays, import_roads, road_objects
from road_grammar.operators import importer as import_ops
from road_grammar.ui import roads as roads_ui


def _check_import(path, ggg, **options):
    result = import_roads(path, **options)
    assert result == {'FINISHED'}
    highways = options.get("highways", 'DRIVABLE').lower()
    expected = ggg.read_graph(str(path), highways=highways)
    graph_obj, surface_obj = road_objects()
    mesh = graph_obj.data

    # The graph mesh is the graph: same counts, same vertex and edge order.
    assert len(mesh.vertices) == expected.vertex_count
    assert len(mesh.edges) == expected.edge_count
    assert len(mesh.polygons) == 0
    co = np.empty(len(mesh.vertices) * 3)
    mesh.vertices.foreach_get("co", co)
    co = co.reshape(-1, 3)
    np.testing.assert_allclose(co[:, :2], expected.positions, atol=2e-3)  # float32 over a few km
    assert np.all(co[:, 2] == 0.0)
    edges = np.empty(len(mesh.edges) * 2, dtype=np.int64)
    mesh.edges.foreach_get("vertices", edges)
    np.testing.assert_array_equal(edges.reshape(-1, 2), expected.edges)

    # Edge attributes.
    classes = list(ggg.highway_classes())
    highway = edge_attribute(mesh, "highway", np.int64)
    assert mesh.attributes["highway"].data_type == 'INT'
    np.testing.assert_array_equal(highway, expected.edge_highway)
    assert highway.min() >= 0 and highway.max() < len(classes)
    width = edge_attribute(mesh, "width")
    assert mesh.attributes["width"].data_type == 'FLOAT'
    assert np.all(np.isfinite(width)) and width.min() > 0.0 and width.max() < 100.0
    np.testing.assert_array_equal(edge_attribute(mesh, "rank", np.int64), expected.edge_rank)

    # Markers and metadata.
    assert graph_obj["road_graph"] == 1
    assert dict(graph_obj["highway_classes"]) == {name: code for code, name in enumerate(classes)}
    lat, lon = expected.origin_latlon
    assert graph_obj["origin_lat"] == pytest.approx(lat) and graph_obj["origin_lon"] == pytest.approx(lon)
    assert graph_obj["total_length_m"] == pytest.approx(expected.total_length_m)
    assert bpy.context.view_layer.objects.active == graph_obj

    # Scene georeference, as BlenderGIS keeps it.
    scene = bpy.context.scene
    assert scene["SRID"] == expected.crs == graph_obj["crs"]
    assert scene["SRID"].startswith("+proj=tmerc ")
    assert scene["crs x"] == 0.0 and scene["crs y"] == 0.0
    assert scene["latitude"] == pytest.approx(lat) and scene["longitude"] == pytest.approx(lon)
    assert scene["lat"] == pytest.approx(lat) and scene["lon"] == pytest.approx(lon)

    # Road surface: Geometry Nodes ribbons, flat in XY.
    assert surface_obj is not None and surface_obj.parent == graph_obj
    assert surface_obj.name == graph_obj.name + " Surface"
    modifiers = [m for m in surface_obj.modifiers if m.type == 'NODES']
    assert len(modifiers) == 1 and modifiers[0].node_group is not None
    surface_mesh = surface_obj.data
    assert len(surface_mesh.polygons) == 0
    surface_width = edge_attribute(surface_mesh, "width")
    assert set(np.unique(surface_width.astype(np.float32))) <= set(np.unique(width.astype(np.float32)))
    positions, normals, attributes = evaluated_mesh_arrays(surface_obj)
    assert len(normals) > 0, "the evaluated surface has no faces"
    assert np.all(np.abs(normals[:, 2]) > 0.999), "road ribbons are not flat"
    top = 0.02 * (max(ggg.highway_ranks()) - 1)  # the default layer step times the highest lift
    assert positions[:, 2].min() >= -1e-6 and positions[:, 2].max() <= top + 1e-4
    assert "rank" in attributes  # read by the material
    # Every surface segment knows its graph edge (kept when a grammar grows the graph).
    owner = edge_attribute(surface_mesh, "graph_edge", np.int64)
    assert owner.min() >= 0 and owner.max() == len(mesh.edges) - 1
    assert "symbol" not in mesh.attributes  # no nonterminals in an OSM import
    return expected, graph_obj, surface_obj


def test_import_sample_city(sample_city, ggg):
    _check_import(sample_city, ggg)


def test_import_sample_city_all_highways(sample_city, ggg):
    expected, graph_obj, _ = _check_import(sample_city, ggg, highways='ALL')
    classes = set(np.unique(expected.edge_highway))
    assert len(classes) > 5, "the sample city should show many highway classes"


def test_import_paris_marais(paris, ggg):
    _check_import(paris, ggg)


def test_import_options_reach_the_reader(paris, ggg):
    result = import_roads(paris, highways='CUSTOM', highways_custom="primary, secondary",
                          keep_shape_nodes=True, consolidate_m=5.0)
    assert result == {'FINISHED'}
    expected = ggg.read_graph(str(paris), highways="primary,secondary", keep_shape_nodes=True,
                              consolidate_m=5.0)
    graph_obj, _ = road_objects()
    assert len(graph_obj.data.vertices) == expected.vertex_count
    assert len(graph_obj.data.edges) == expected.edge_count
    classes = list(ggg.highway_classes())
    codes = set(edge_attribute(graph_obj.data, "highway", np.int64).tolist())
    assert codes <= {classes.index("primary"), classes.index("secondary")}
    assert graph_obj["import_options"]["highways"] == "primary,secondary"


def test_without_surface(paris, ggg):
    assert import_roads(paris, build_surface=False) == {'FINISHED'}
    graph_obj, surface_obj = road_objects()
    assert surface_obj is None
    assert not graph_obj.hide_render


def test_two_imports_share_node_group_and_material(paris, ggg):
    assert import_roads(paris) == {'FINISHED'}
    assert import_roads(paris) == {'FINISHED'}
    surfaces = [o for o in bpy.context.scene.objects if o.get("road_surface")]
    assert len(surfaces) == 2
    assert surfaces[0].modifiers[0].node_group == surfaces[1].modifiers[0].node_group
    assert len(bpy.data.node_groups) == 1 and len(bpy.data.materials) == 1
    assert sorted(o.name for o in surfaces) == ["paris_marais Surface", "paris_marais.001 Surface"]
    # Same origin: both at the scene origin, unrotated.
    for obj in bpy.context.scene.objects:
        if obj.get("road_graph"):
            assert tuple(obj.location) == (0.0, 0.0, 0.0) and obj.rotation_euler.z == 0.0


def test_undo_flag():
    """The operator is undoable: its type carries UNDO (test_undo.py runs a real undo)."""
    assert {'REGISTER', 'UNDO'} <= set(import_ops.ROADS_OT_import_osm.bl_options)


def test_menu_and_panel_registered():
    assert hasattr(bpy.types, "ROADS_OT_import_osm")
    assert hasattr(bpy.types, "VIEW3D_PT_roads")
    assert roads_ui.menu_import in bpy.types.TOPBAR_MT_file_import._dyn_ui_initialize()


def test_surface_area_matches_widths(paris, ggg):
    """Surface geometry follows the graph: ribbon area close to sum(width x length)."""
    assert import_roads(paris) == {'FINISHED'}
    graph_obj, surface_obj = road_objects()
    depsgraph = bpy.context.evaluated_depsgraph_get()
    evaluated = surface_obj.evaluated_get(depsgraph)
    mesh = evaluated.to_mesh()
    area = sum(p.area for p in mesh.polygons)
    evaluated.to_mesh_clear()
    widths = edge_attribute(surface_obj.data, "width")
    co = np.empty(len(surface_obj.data.vertices) * 3)
    surface_obj.data.vertices.foreach_get("co", co)
    co = co.reshape(-1, 3)
    segments = np.empty(len(surface_obj.data.edges) * 2, dtype=np.int64)
    surface_obj.data.edges.foreach_get("vertices", segments)
    segments = segments.reshape(-1, 2)
    lengths = np.linalg.norm(co[segments[:, 1]] - co[segments[:, 0]], axis=1)
    assert lengths.sum() == pytest.approx(graph_obj["total_length_m"], rel=1e-4)
    expected_area = float((widths * lengths).sum())
    # Mitred joints add or remove a little at bends; the area must match within a few percent.
    assert area == pytest.approx(expected_area, rel=0.05)
    assert not math.isclose(area, 0.0)


def test_progress_callback_is_given_to_the_reader(paris, ggg, monkeypatch, capsys):
    calls = []
    original = ggg.read_graph

    def recording_read_graph(path, **kwargs):
        progress = kwargs["progress"]
        assert callable(progress)

        def spy(fraction, message):
            answer = progress(fraction, message)
            calls.append((fraction, message, answer))
            return answer

        kwargs["progress"] = spy
        return original(path, **kwargs)

    monkeypatch.setattr(ggg, "read_graph", recording_read_graph)
    assert import_roads(paris) == {'FINISHED'}
    assert calls and calls[-1][0] == pytest.approx(1.0)
    assert all(answer is not False for _, _, answer in calls), "the add-on must not cancel the read"
    assert "Importing roads: done (100%)" in capsys.readouterr().out
