"""Fly-through: keyframes on every frame, a smooth camera, shortest paths between the picked
vertices, and clear errors for bad picks."""

import math

import bpy
import numpy as np
import pytest

from conftest import import_roads, snapshot, write_osm
from road_grammar.core import flythrough
from road_grammar.data import mesh as mesh_build
from road_grammar.operators import city as city_ops

MAX_TURN_DEG = 3.0  # per frame at 24 fps


@pytest.fixture
def results(monkeypatch):
    seen = []
    original = city_ops.ROADS_OT_flythrough.execute

    def recording(self, context):
        result = original(self, context)
        seen.append(result)
        return result

    monkeypatch.setattr(city_ops.ROADS_OT_flythrough, "execute", recording)
    return seen


@pytest.fixture
def town(sample_city, ggg):
    assert import_roads(sample_city, highways='ALL') == {'FINISHED'}
    return bpy.context.active_object


def _camera_track(camera, scene):
    """(locations, view directions) of every frame, from the evaluated animation."""
    locations, directions = [], []
    for frame in range(scene.frame_start, scene.frame_end + 1):
        scene.frame_set(frame)
        matrix = camera.matrix_world
        locations.append(tuple(matrix.translation))
        view = matrix.to_3x3().col[2]
        directions.append((-view.x, -view.y, -view.z))
    return np.array(locations), np.array(directions)


def _max_turn(directions):
    cos = np.clip(np.sum(directions[1:] * directions[:-1], axis=1), -1.0, 1.0)
    return math.degrees(float(np.arccos(cos).max()))


@pytest.mark.parametrize("height", ['STREET', 'DRONE'])
def test_tour_is_keyframed_and_smooth(town, height):
    scene = bpy.context.scene
    scene.render.fps = 24
    assert bpy.ops.roads.flythrough(mode='TOUR', height=height, duration_s=6.0, seed=5) == {'FINISHED'}
    camera = scene.camera
    assert camera.get("road_graph_name") == town.name
    fcurves = camera.animation_data.action.fcurves
    assert sorted((c.data_path, c.array_index) for c in fcurves) == \
        [("location", i) for i in range(3)] + [("rotation_euler", i) for i in range(3)]
    assert all(len(c.keyframe_points) == 144 for c in fcurves)
    assert scene.frame_end - scene.frame_start + 1 == 144
    locations, directions = _camera_track(camera, scene)
    expected_height = city_ops.HEIGHTS[height][0]
    np.testing.assert_allclose(locations[:, 2], expected_height, atol=1e-4)
    assert _max_turn(directions) < MAX_TURN_DEG
    assert _max_heading_change(locations) < 2 * MAX_TURN_DEG
    steps = np.linalg.norm(np.diff(locations, axis=0), axis=1)
    assert steps.max() < 1.05 * steps.mean() + 1e-6  # constant speed
    assert camera["path_length_m"] > 0.5 * city_ops.HEIGHTS[height][3] * 6.0


def _max_heading_change(locations):
    """Largest change (degrees) of the direction of motion between consecutive frames."""
    steps = np.diff(np.asarray(locations)[:, :2], axis=0)
    heading = np.unwrap(np.arctan2(steps[:, 1], steps[:, 0]))
    return math.degrees(float(np.abs(np.diff(heading)).max()))


def test_smoothing_is_what_makes_it_smooth():
    # A right-angle corner: without smoothing the camera turns on the spot; with it, it
    # drives an arc, and the view (30 m ahead) turns gently either way.
    line = np.array([[0.0, 0.0], [200.0, 0.0], [200.0, 200.0]])
    # 400 m at street pace (11 m/s, 24 fps), the camera looking 30 m ahead at eye height.
    frames = int(400 / 11 * 24)
    sharp = flythrough.camera_track(line, frames, 2.0, 30.0, 1.6, smoothing=0.0)
    smooth = flythrough.camera_track(line, frames, 2.0, 30.0, 1.6, smoothing=25.0)
    assert _max_heading_change(sharp[0]) > 30.0
    assert _max_heading_change(smooth[0]) < MAX_TURN_DEG
    assert math.degrees(flythrough.max_turn_per_frame(*smooth[:2])) < MAX_TURN_DEG


def _select(obj, vertices):
    flags = np.zeros(len(obj.data.vertices), dtype=bool)
    flags[list(vertices)] = True
    obj.data.vertices.foreach_set("select", flags)
    obj.data.edges.foreach_set("select", np.zeros(len(obj.data.edges), dtype=bool))


def test_shortest_path_between_the_selected_vertices(town):
    positions = mesh_build.positions_xy(town.data)
    a = int(np.argmin(positions[:, 0] + positions[:, 1]))  # south-west
    b = int(np.argmax(positions[:, 0] - positions[:, 1]))  # south-east
    _select(town, (a, b))
    bpy.ops.object.mode_set(mode='EDIT')
    assert bpy.ops.roads.flythrough(mode='PATH', height='STREET', duration_s=60.0) == {'FINISHED'}
    bpy.ops.object.mode_set(mode='OBJECT')
    scene = bpy.context.scene
    locations, directions = _camera_track(scene.camera, scene)
    # From the vertex picked first (without a pick order: the lower index) to the other.
    first, last = sorted((a, b))
    assert np.hypot(*(locations[0, :2] - positions[first])) < 0.5
    assert np.hypot(*(locations[-1, :2] - positions[last])) < 0.5
    straight = np.hypot(*(positions[b] - positions[a]))
    assert scene.camera["path_length_m"] >= straight
    assert _max_turn(directions) < 2 * MAX_TURN_DEG  # 1.5 km in a minute: faster than a car
    # A second fly-through replaces the first camera.
    assert bpy.ops.roads.flythrough(mode='PATH', start=b, end=a, duration_s=2.0) == {'FINISHED'}
    assert len([o for o in bpy.data.objects if o.get("road_city_part") == "flythrough"]) == 1


@pytest.mark.parametrize("pick, message", [
    ((), "Select exactly two vertices"),
    ((0,), "Select exactly two vertices"),
    ((0, 1, 2), "Select exactly two vertices"),
])
def test_bad_selection_is_an_error(town, results, pick, message):
    _select(town, pick)
    before = snapshot()
    with pytest.raises(RuntimeError, match=message):
        bpy.ops.roads.flythrough(mode='PATH')
    assert results == [{'CANCELLED'}]
    assert snapshot() == before


def test_identical_vertices_and_unconnected_vertices_are_errors(tmp_path, results, ggg):
    nodes = {1: (46.0, 8.95), 2: (46.001, 8.95), 3: (46.003, 8.96), 4: (46.004, 8.961)}
    ways = [(10, [1, 2], {"highway": "residential"}), (11, [3, 4], {"highway": "residential"})]
    assert import_roads(write_osm(tmp_path / "two.osm", nodes, ways)) == {'FINISHED'}
    before = snapshot()
    with pytest.raises(RuntimeError, match="same vertex"):
        bpy.ops.roads.flythrough(mode='PATH', start=1, end=1)
    positions = mesh_build.positions_xy(bpy.context.active_object.data)
    far = int(np.argmax(positions[:, 1]))
    with pytest.raises(RuntimeError, match="no road connects"):
        bpy.ops.roads.flythrough(mode='PATH', start=int(np.argmin(positions[:, 1])), end=far)
    with pytest.raises(RuntimeError, match="not in the road graph"):
        bpy.ops.roads.flythrough(mode='PATH', start=0, end=99)
    assert results == [{'CANCELLED'}] * 3
    assert snapshot() == before


def test_no_road_graph_is_an_error(results, ggg):
    with pytest.raises(RuntimeError, match="No road graph is active"):
        bpy.ops.roads.flythrough()
    assert results == [{'CANCELLED'}]


def test_animation_renders_to_an_mp4(town, tmp_path):
    scene = bpy.context.scene
    scene.render.fps = 24
    assert bpy.ops.roads.build_city() == {'FINISHED'}
    assert bpy.ops.roads.flythrough(mode='TOUR', height='DRONE', duration_s=0.5, seed=1) == {'FINISHED'}
    assert scene.frame_end - scene.frame_start + 1 == 12
    assert bpy.ops.roads.render_city(animation=True, engine='BLENDER_EEVEE', resolution_x=32, resolution_y=32,
                                     samples=1, directory=str(tmp_path)) == {'FINISHED'}
    movie = tmp_path / "flythrough.mp4"
    data = movie.read_bytes()
    assert data[4:8] == b"ftyp" and len(data) > 1000  # an MP4 (ISO media) file with frames in it
    assert scene.render.image_settings.file_format == 'FFMPEG' and scene.render.ffmpeg.codec == 'H264'
    clip = bpy.data.movieclips.load(str(movie))
    assert clip.frame_duration == 12 and tuple(clip.size) == (32, 32)
