"""Build City on the sample town: the objects it makes agree with the native plan, nothing
is built on a road, a rebuild replaces the city, bad input is refused, undo restores the
scene, and a render of it is a picture of a city under a sky."""

import bpy
import numpy as np
import pytest

from conftest import import_roads, snapshot, write_osm
from road_grammar.core.names import CITY_KEY, CITY_PART_KEY
from road_grammar.data import graph_edit
from road_grammar.display import city
from road_grammar.display.nodes import input_sockets
from road_grammar.operators import city as city_ops

TINY = dict(engine='BLENDER_EEVEE', resolution_x=80, resolution_y=48, samples=1)


@pytest.fixture
def results(monkeypatch):
    """What the city operators' execute() returned (bpy.ops raises on an error report)."""
    seen = []

    def recorder(original):
        # Exactly (self, context): Blender checks the signature of an operator's execute.
        def recording(self, context):
            result = original(self, context)
            seen.append(result)
            return result
        return recording

    for cls in (city_ops.ROADS_OT_build_city, city_ops.ROADS_OT_flythrough, city_ops.ROADS_OT_render_city):
        monkeypatch.setattr(cls, "execute", recorder(cls.execute))
    return seen


@pytest.fixture
def town(sample_city, ggg):
    assert import_roads(sample_city, highways='ALL') == {'FINISHED'}
    return bpy.context.active_object


def _parts(collection):
    return {obj[CITY_PART_KEY]: obj for obj in collection.objects}


def _evaluated_positions(obj):
    evaluated = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
    mesh = evaluated.to_mesh()
    try:
        co = np.empty(len(mesh.vertices) * 3)
        mesh.vertices.foreach_get("co", co)
        return co.reshape(-1, 3), len(mesh.polygons)
    finally:
        evaluated.to_mesh_clear()


def _segment_distances(points, starts, ends):
    """Distance of each point to the nearest segment (starts[i], ends[i])."""
    best = np.full(len(points), np.inf)
    d = ends - starts
    length2 = np.maximum(np.sum(d * d, axis=1), 1e-12)
    for chunk in range(0, len(points), 2000):
        p = points[chunk:chunk + 2000, None, :]
        t = np.clip(np.sum((p - starts) * d, axis=2) / length2, 0.0, 1.0)
        nearest = starts + t[..., None] * d
        best[chunk:chunk + 2000] = np.sqrt(np.min(np.sum((p - nearest) ** 2, axis=2), axis=1))
    return best


def test_build_city_makes_the_planned_objects(town, ggg):
    assert bpy.ops.roads.build_city(seed=3) == {'FINISHED'}
    collection = city.find_collection(town)
    assert collection is not None and collection.name == "sample_city City"
    parts = _parts(collection)
    assert set(parts) == {"ground", "roads", "blocks", "yards", "buildings", "sun", "view"}

    columns = graph_edit.MeshGraph(town)
    graph = columns.graph(ggg)
    widths = ggg.road_widths(graph)
    plan = ggg.city_layout(graph, half_widths=widths / 2.0, sidewalk_m=3.0, seed=3)
    faces = ggg.planar_faces(graph)
    assert len(plan["faces"]["face_area"]) == len(faces["face_area"]) == collection["faces"]
    assert len(faces["face_area"]) > 50
    # One block outline per kerb polygon, one building per lot, one road face per piece.
    assert len(parts["blocks"].data.polygons) == len(plan["block_face"]) == collection["blocks"]
    assert len(parts["buildings"].data.polygons) == len(plan["building_face"]) == collection["buildings"]
    assert len(parts["roads"].data.polygons) == len(plan["road_edge"]) == collection["road_pieces"]
    # A rectangle per polyline segment, a disc per vertex with roads.
    offsets, points = graph.edge_geometry()
    segments = np.hypot(*np.diff(points, axis=0).T) > 1e-6
    segments[offsets[1:-1] - 1] = False  # no segment between two edges' polylines
    assert np.count_nonzero(plan["road_piece"] == 0) == np.count_nonzero(segments)
    assert np.count_nonzero(plan["road_piece"] == 2) == len(np.unique(graph.edges))
    # Every face with room for buildings has some; none has buildings without a block.
    with_buildings = set(plan["building_face"].tolist())
    assert with_buildings <= set(plan["block_face"].tolist())
    assert len(with_buildings) > 0.5 * len(faces["face_area"])

    # The buildings stand on their lots, between 1 and 60 floors high, never on a road:
    # each footprint corner is at least half the road's width plus the sidewalk from it.
    positions, polygons = _evaluated_positions(parts["buildings"])
    assert polygons > 4 * collection["buildings"]  # roof + at least 4 walls each
    height = positions[:, 2] - city.YARD_Z
    floor = ggg.option_defaults()["city"]["floor_height_m"]
    assert height.max() > 3.0 and height.max() < 60 * floor + 2.0
    offsets, points = graph.edge_geometry()
    owner = np.repeat(np.arange(graph.edge_count), np.diff(offsets))
    last = np.r_[offsets[1:] - 1]
    starts_index = np.setdiff1d(np.arange(len(points)), last)
    starts, ends = points[starts_index], points[starts_index + 1]
    seg_half = widths[owner[starts_index]] / 2.0
    footprint = plan["building_points"]
    clearance = np.full(len(footprint), np.inf)
    for h in np.unique(seg_half):
        pick = seg_half == h
        clearance = np.minimum(clearance, _segment_distances(footprint, starts[pick], ends[pick]) - h)
    assert clearance.min() >= 3.0 - 0.05, "a building stands on a road or its sidewalk"

    # Blocks are raised to the kerb; the roads stay below it.
    block_positions, _ = _evaluated_positions(parts["blocks"])
    assert block_positions[:, 2].max() == pytest.approx(city.KERB_Z, abs=1e-4)
    road_z = np.empty(len(parts["roads"].data.vertices) * 3)
    parts["roads"].data.vertices.foreach_get("co", road_z)
    assert road_z[2::3].max() < city.KERB_Z
    assert bpy.context.scene.camera is not None and bpy.context.scene.world is not None

    # The overview camera holds the whole town between its clipping planes, and keeps their
    # ratio short: with 1 to 2,000 the cm-thin parks flickered through the ground of a grown town.
    view = parts["view"]
    to_camera = view.matrix_world.inverted() @ parts["blocks"].matrix_world
    depth = np.array([-(to_camera @ v.co).z for v in parts["blocks"].data.vertices])
    assert view.data.clip_start < depth.min() and depth.max() < view.data.clip_end
    assert view.data.clip_end / view.data.clip_start <= 40.0


def test_rebuild_replaces_the_city_and_the_seed_changes_heights(town):
    assert bpy.ops.roads.build_city(seed=1) == {'FINISHED'}
    first = _evaluated_positions(_parts(city.find_collection(town))["buildings"])[0]
    objects = len(bpy.data.objects)
    assert bpy.ops.roads.build_city(seed=1) == {'FINISHED'}
    assert len([c for c in bpy.data.collections if c.get(CITY_KEY)]) == 1
    assert len(bpy.data.objects) == objects
    np.testing.assert_array_equal(_evaluated_positions(_parts(city.find_collection(town))["buildings"])[0], first)
    assert bpy.ops.roads.build_city(seed=2) == {'FINISHED'}
    second = _evaluated_positions(_parts(city.find_collection(town))["buildings"])[0]
    assert len(second) != len(first) or not np.allclose(second, first)


def test_height_scale_is_non_destructive(town):
    assert bpy.ops.roads.build_city() == {'FINISHED'}
    buildings = _parts(city.find_collection(town))["buildings"]
    top = _evaluated_positions(buildings)[0][:, 2].max()
    modifier = buildings.modifiers[city.EXTRUDE_GROUP_NAME]
    scale = next(s for s in input_sockets(modifier.node_group) if s.name == "Height Scale")
    modifier[scale.identifier] = 2.0
    buildings.data.update()
    assert _evaluated_positions(buildings)[0][:, 2].max() - city.YARD_Z == pytest.approx(2.0 * (top - city.YARD_Z),
                                                                                           rel=1e-4)


def test_no_road_graph_is_an_error(results, ggg):
    before = snapshot()
    with pytest.raises(RuntimeError, match="No road graph is active"):
        bpy.ops.roads.build_city()
    assert results == [{'CANCELLED'}]
    assert snapshot() == before


def test_graph_without_blocks_is_an_error(tmp_path, results, ggg):
    # A star of streets and a lone road: no road encloses anything.
    nodes = {1: (46.0, 8.95), 2: (46.001, 8.95), 3: (46.0, 8.952), 4: (45.999, 8.9495), 5: (46.003, 8.96),
             6: (46.004, 8.961)}
    ways = [(10, [1, 2], {"highway": "residential"}), (11, [1, 3], {"highway": "residential"}),
            (12, [1, 4], {"highway": "primary"}), (13, [5, 6], {"highway": "service"})]
    assert import_roads(write_osm(tmp_path / "star.osm", nodes, ways)) == {'FINISHED'}
    before = snapshot()
    with pytest.raises(RuntimeError, match="no city blocks"):
        bpy.ops.roads.build_city()
    assert results == [{'CANCELLED'}]
    assert snapshot() == before


def _pixels(path):
    image = bpy.data.images.load(str(path))
    try:
        width, height = image.size
        pixels = np.empty(width * height * 4, dtype=np.float32)
        image.pixels.foreach_get(pixels)
        return pixels.reshape(height, width, 4)[::-1, :, :3]  # top row first
    finally:
        bpy.data.images.remove(image)


def test_render_shows_a_city_under_a_sky(town, tmp_path, ggg):
    from mathutils import Vector

    assert bpy.ops.roads.build_city() == {'FINISHED'}
    # Stand at eye height at the start of the longest straight stretch of road and look
    # along it: sky above the street, asphalt below.
    offsets, points = graph_edit.MeshGraph(town).graph(ggg).edge_geometry()
    steps = np.diff(points, axis=0)
    length = np.hypot(*steps.T)
    length[offsets[1:-1] - 1] = 0.0
    k = int(np.argmax(length))
    eye = Vector((points[k, 0], points[k, 1], 1.7))
    ahead = Vector((points[k + 1, 0], points[k + 1, 1], 1.7))
    camera = bpy.data.objects.new("Eye", bpy.data.cameras.new("Eye"))
    bpy.context.scene.collection.objects.link(camera)
    camera.location = town.matrix_world @ eye
    camera.rotation_euler = ((town.matrix_world @ ahead) - camera.location).to_track_quat('-Z', 'Y').to_euler()
    camera.data.lens = 24.0
    camera.data.clip_start = 0.3
    bpy.context.scene.camera = camera
    assert bpy.ops.roads.render_city(directory=str(tmp_path), **TINY) == {'FINISHED'}
    rgb = _pixels(tmp_path / "city.png")
    assert rgb.shape == (48, 80, 3)
    assert rgb.std() > 0.05, "the picture is blank"
    sky, street = rgb[:8, 34:46].reshape(-1, 3), rgb[-8:, 34:46].reshape(-1, 3)
    assert sky[:, 2].mean() > sky[:, 0].mean() + 0.03, "no blue sky above the street"
    assert street.mean() < sky.mean() - 0.2, "no dark road below the sky"


def test_render_refuses_a_scene_without_camera(results, tmp_path):
    with pytest.raises(RuntimeError, match="no camera"):
        bpy.ops.roads.render_city(directory=str(tmp_path), **TINY)
    assert results == [{'CANCELLED'}]


def test_undo_of_build_city_restores_the_scene(sample_city, ggg, tmp_path):
    from test_undo import _session

    result = _session(ggg, tmp_path, sample_city, "city")
    assert result["load"] == ['FINISHED'] and result["city"] == ['FINISHED']
    before, built = result["before"], result["imported"]
    assert "sample_city City" in built["collections"] and "sample_city City" not in before["collections"]
    assert len(built["objects"]) == len(before["objects"]) + 7
    assert "sample_city Buildings" in built["meshes held"]
    assert result["undo"] == ['FINISHED']
    assert result["undone"] == before
    assert result["redo"] == ['FINISHED']
    assert result["redone"] == built
