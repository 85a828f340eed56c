"""The measures of the infill benchmark (scripts/bench_infill.py) on small graphs written here:
sharp turns a km follow a street through its bends and not through its junctions, and the
list of missed targets says where the ring misses a target too. Needs no map data."""
import sys
from pathlib import Path

import numpy as np

SCRIPTS = Path(__file__).resolve().parents[3] / "scripts"
sys.path.insert(0, str(SCRIPTS))
import bench_infill  # noqa: E402

ggg = bench_infill.ggg


def graph(positions, edges):
    return ggg.Graph.from_arrays(np.array(positions, dtype=float), np.array(edges, dtype=np.int64))


def everything(g):
    return np.ones(g.edge_count, dtype=bool)


def test_a_straight_street_has_no_sharp_turn():
    g = graph([[0, 0], [100, 0], [200, 0], [300, 0]], [[0, 1], [1, 2], [2, 3]])
    assert bench_infill.sharp_turns_per_km(g, everything(g)) == 0.0


def test_a_street_that_turns_a_corner_at_a_bend_has_one():
    # 200 m of street turning 90 degrees at a vertex of two streets: one sharp turn in 0.2 km.
    g = graph([[0, 0], [100, 0], [100, 100]], [[0, 1], [1, 2]])
    assert abs(bench_infill.sharp_turns_per_km(g, everything(g)) - 5.0) < 1e-9
    # A gentle bend (30 degrees) is no sharp turn.
    g = graph([[0, 0], [100, 0], [100 + 100 * np.cos(np.radians(30)), 100 * np.sin(np.radians(30))]], [[0, 1], [1, 2]])
    assert bench_infill.sharp_turns_per_km(g, everything(g)) == 0.0


def test_a_junction_is_no_turn_even_where_the_kept_streets_make_it_look_like_a_bend():
    # A crossing at (100, 0): kept, its west and north streets meet at a right angle, but the
    # vertex is a junction of the whole graph, so the streets end there.
    g = graph([[0, 0], [100, 0], [200, 0], [100, 100], [100, -100]], [[0, 1], [1, 2], [1, 3], [1, 4]])
    keep = np.array([True, False, True, False])
    assert bench_infill.sharp_turns_per_km(g, keep) == 0.0
    # The same corner where only those two streets meet is a turn.
    g = graph([[0, 0], [100, 0], [100, 100]], [[0, 1], [1, 2]])
    assert bench_infill.sharp_turns_per_km(g, everything(g)) > 0.0


def run(**changes):
    row = {"fill": 1.0, "ring_fill": 1.1, "continued": 1.0, "joined": 1.0, "stars": 0.0, "right": 0.7, "real_right": 0.7,
           "ring_right": 0.7, "dead": 0.0, "real_dead": 0.0, "ring_dead": 0.0, "mean": 0.1, "ring_mean": 0.1, "crossings": 0}
    row.update(changes)
    return row


def test_missed_targets_say_whether_the_ring_misses_them_too():
    assert bench_infill.misses(run()) == []
    (fill,) = bench_infill.misses(run(fill=3.5, ring_fill=2.35))
    assert fill.startswith("fill 3.50") and fill.endswith("(the ring's too)")
    (fill,) = bench_infill.misses(run(fill=1.7, ring_fill=1.24))
    assert "ring's too" not in fill
    (right,) = bench_infill.misses(run(right=0.72, real_right=0.87, ring_right=0.71))
    assert right.endswith("(the ring's too)")
    assert len(bench_infill.misses(run(dead=0.06, crossings=2, mean=0.16))) == 3
    # Dead ends: the ring's share says whether another part of the city would miss too.
    (dead,) = bench_infill.misses(run(dead=0.23, real_dead=0.16, ring_dead=0.17))
    assert dead.startswith("dead ends 0.23 (real 0.16, ring 0.17)") and "ring's too" not in dead
    (dead,) = bench_infill.misses(run(dead=0.06, real_dead=0.0, ring_dead=0.14))
    assert dead.endswith("(the ring's too)")
