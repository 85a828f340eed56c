"""core.polylines, core.polygons and core.topology: arrays of road graphs."""

import numpy as np
import pytest

from road_grammar.core import polygons, polylines, topology


def test_ramp():
    assert polylines.ramp([2, 0, 3]).tolist() == [0, 1, 0, 1, 2]
    assert polylines.ramp([]).tolist() == []


def test_polylines_round_trip():
    positions = np.array([[0, 0], [10, 0], [10, 10]], dtype=float)
    edges = np.array([[0, 1], [1, 2]])
    # Edge 0 has no shape points (straight), edge 1 a bend.
    offsets = np.array([0, 0, 3])
    points = np.array([[10, 0], [12, 5], [10, 10]], dtype=float)
    full_offsets, full_points = polylines.complete_polylines(offsets, points, positions, edges)
    assert full_offsets.tolist() == [0, 2, 5]
    assert full_points[:2].tolist() == [[0, 0], [10, 0]]
    seg_points, segments, owner = polylines.polyline_segments(offsets, points, positions, edges)
    assert owner.tolist() == [0, 1, 1] and segments.dtype == np.int32
    back_offsets, back_points = polylines.segment_polylines(seg_points, segments, owner, 2)
    assert back_offsets.tolist() == full_offsets.tolist()
    np.testing.assert_array_equal(back_points, full_points)


def test_closed_loops_and_areas():
    square = [[0, 1], [1, 2], [2, 3], [3, 0]]
    loops = polygons.closed_loops(square + [[4, 5], [5, 6], [6, 4]])
    assert sorted(len(loop) for loop in loops) == [3, 4]
    with pytest.raises(polygons.RegionError, match="2 open ends"):
        polygons.closed_loops([[0, 1], [1, 2]])
    with pytest.raises(polygons.RegionError, match="branches"):
        polygons.closed_loops(square + [[0, 2], [2, 4], [4, 0]])
    ring = np.array([[0, 0], [2, 0], [2, 2], [0, 2]], dtype=float)
    assert polygons.signed_area(ring) == pytest.approx(4.0)
    assert polygons.signed_area(ring[::-1]) == pytest.approx(-4.0)
    assert polygons.contains(ring, [[1, 1], [3, 1], [-0.5, 0.5]]).tolist() == [True, False, False]
    # (A corner equal to the one before it goes, the first one too when the ring ends on it.)
    assert polygons.clean([[0, 0], [0, 0], [1, 0], [1, 1], [0, 0]]).tolist() == [[1, 0], [1, 1], [0, 0]]


def test_seed_problem():
    edges = [[0, 1], [1, 2], [3, 4]]
    assert "Select the vertices" in topology.seed_problem(edges, [])
    assert "Only one vertex" in topology.seed_problem(edges, [1])
    assert "No street joins" in topology.seed_problem(edges, [0, 3])
    assert "not connected" in topology.seed_problem(edges, [0, 1, 3, 4])
    assert topology.seed_problem(edges, [0, 1, 2]) is None


def test_checksums():
    edges = np.array([[0, 1], [1, 2]])
    assert topology.topology_checksum(3, edges) == topology.topology_checksum(3, edges.copy())
    assert topology.topology_checksum(3, edges) != topology.topology_checksum(4, edges)
    assert topology.topology_checksum(3, edges).startswith("3:2:")
    assert topology.positions_digest(np.zeros((2, 2))) != topology.positions_digest(np.ones((2, 2)))


def test_edge_lookup():
    lookup = topology.EdgeLookup([[0, 1], [2, 1], [2, 3]], 4)
    assert lookup.edge_ids([1, 1], [0, 2]).tolist() == [0, 1]
    with pytest.raises(KeyError):
        lookup.edge_ids([0], [3])
    occurrences = np.array([[0, 1, 2], [3, 2, 1]])
    assert lookup.occurrence_edges(occurrences, [[0, 1], [1, 2]]).tolist() == [[0, 1], [2, 1]]


def test_kept_edges_and_carried():
    old_edges = [[0, 1], [1, 2]]
    # New vertices: 0 is old 2, 1 is old 1, 2 is placed.
    kept = topology.kept_edges(old_edges, [2, 1, -1], [[1, 0], [1, 2]])
    assert kept.tolist() == [1, -1]
    assert topology.carried(np.array([5.0, 7.0]), np.array([1, -1, 0])).tolist() == [7.0, 0.0, 5.0]


def test_replaced_vertices():
    """A replacement removes the vertices of its occurrences that no street from outside
    their own occurrence reaches; the junctions stay."""
    # Two squares side by side (0 1 2 / 3 4 5) and a spur 2-6; the left square replaced:
    # 1 and 4 are reached from outside it (1-2, 4-5), 0 and 3 are not.
    edges = [[0, 1], [1, 2], [3, 4], [4, 5], [0, 3], [1, 4], [2, 5], [2, 6]]
    removed = topology.replaced_vertices(7, edges, [[0, 1, 4, 3]])
    assert removed.dtype == bool and np.flatnonzero(removed).tolist() == [0, 3]
    # A street between two replaced occurrences (1-2 of the path 0-1-2-3) keeps both its ends.
    path = [[0, 1], [1, 2], [2, 3]]
    assert np.flatnonzero(topology.replaced_vertices(4, path, [[0, 1], [3, 2]])).tolist() == [0, 3]
    # An occurrence that no street leaves goes whole; no occurrence removes nothing.
    ring = [[0, 1], [1, 2], [2, 3], [3, 0]]
    assert topology.replaced_vertices(4, ring, [[0, 1, 2, 3]]).all()
    assert not topology.replaced_vertices(4, ring, np.zeros((0, 4), dtype=np.int64)).any()
