"""planar_faces and city_layout through the Python module."""

from pathlib import Path

import numpy as np
import pytest

import ggg

REPO = Path(__file__).resolve().parents[3]
SAMPLE = REPO / "samples" / "sample_city.osm"


def grid(n, step=100.0):
    positions = np.array([[i * step, j * step] for j in range(n) for i in range(n)], dtype=float)
    edges = [(i + n * j, i + 1 + n * j) for j in range(n) for i in range(n - 1)]
    edges += [(i + n * j, i + n * (j + 1)) for j in range(n - 1) for i in range(n)]
    return ggg.Graph.from_arrays(positions, np.array(edges), (46.0, 8.95))


def test_planar_faces_of_a_grid():
    faces = ggg.planar_faces(grid(4))
    assert len(faces["face_area"]) == 9
    np.testing.assert_allclose(faces["face_area"], 10000.0)
    assert faces["ring_offsets"].shape == (10,) and faces["points"].shape == (36, 2)
    assert faces["components"] == 1 and faces["outer_dropped"] == 1 and faces["genus"] == 0
    with_outer = ggg.planar_faces(grid(4), keep_outer=True)
    assert with_outer["face_area"].min() == pytest.approx(-90000.0)


def test_planar_faces_of_the_sample_town():
    g = ggg.read_graph(str(SAMPLE), highways="all")
    faces = ggg.planar_faces(g)
    assert len(faces["face_area"]) > 50
    assert (faces["face_area"] > 0).all()
    # Rings sum to the face areas (dead ends cut out add nothing).
    o, p = faces["ring_offsets"], faces["points"]
    ring_area = [0.5 * np.sum(p[a:b, 0] * np.roll(p[a:b, 1], -1) - np.roll(p[a:b, 0], -1) * p[a:b, 1])
                 for a, b in zip(o[:-1], o[1:])]
    per_face = np.bincount(faces["ring_face"], weights=ring_area, minlength=len(faces["face_area"]))
    np.testing.assert_allclose(per_face, faces["face_area"], rtol=1e-9)
    # Dead ends inside blocks are counted on their block; those outside on the dropped outer face.
    assert 0 < faces["face_dangling"].sum() < faces["dangling_edges"]


def test_city_layout_keeps_buildings_off_the_roads():
    g = grid(3)
    half = np.full(g.edge_count, 5.0)
    layout = ggg.city_layout(g, half_widths=half, sidewalk_m=3.0, seed=4)
    assert len(layout["faces"]["face_area"]) == 4
    assert len(layout["block_face"]) == 4
    assert len(layout["building_face"]) > 8
    points = layout["building_points"]
    # Every footprint corner is at least half a road width plus the sidewalk from the centre lines.
    distance = np.minimum(np.abs(points[:, 0, None] - [0, 100, 200]).min(axis=1),
                          np.abs(points[:, 1, None] - [0, 100, 200]).min(axis=1))
    assert distance.min() >= 8.0 - 1e-3
    # The same seed gives the same plan; another seed another one.
    again = ggg.city_layout(g, half_widths=half, sidewalk_m=3.0, seed=4)
    np.testing.assert_array_equal(again["building_points"], points)
    other = ggg.city_layout(g, half_widths=half, sidewalk_m=3.0, seed=5)
    assert len(other["building_points"]) != len(points) or not np.array_equal(other["building_points"], points)


def test_city_layout_refuses_bad_widths():
    g = grid(3)
    with pytest.raises(ggg.UsageError, match="half_widths"):
        ggg.city_layout(g, half_widths=np.ones(3))
    with pytest.raises(ggg.InputError, match="half_widths"):
        ggg.city_layout(g, half_widths=np.full(g.edge_count, -1.0))
    with pytest.raises(ggg.UsageError, match="options"):
        ggg.city_layout(g, lot_min_m=30.0, lot_max_m=10.0)


def test_city_layout_progress_can_cancel():
    g = ggg.read_graph(str(SAMPLE), highways="all")
    with pytest.raises(ggg.Cancelled):
        ggg.city_layout(g, progress=lambda f, m: False)
