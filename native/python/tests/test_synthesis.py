"""ggg.grow_region and ggg.replace_isogroup on a street grid: arrays in and out, budgets, errors."""
from pathlib import Path

import numpy as np
import pytest

import ggg
from test_learning import grid


def inside(ring, p):
    x, y = p
    hit = False
    for (x1, y1), (x2, y2) in zip(ring, np.roll(ring, 1, axis=0)):
        if (y1 > y) != (y2 > y) and x < (x2 - x1) * (y - y1) / (y2 - y1) + x1:
            hit = not hit
    return hit


def test_grow_east_of_a_grid():
    g = grid(8)  # 0 .. 700 m
    grammar, _ = ggg.learn(g)
    region = np.array([[720.0, -50.0], [1500.0, -50.0], [1500.0, 750.0], [720.0, 750.0]])
    grown, report = ggg.grow_region(g, grammar, region, seed=4)
    # The grid's streets that end at its east edge are traced on into the region.
    assert report["traced_seeds"] >= 6 and report["traced_streets"] > 20
    assert grown.vertex_count == g.vertex_count + report["added_vertices"]
    assert np.array_equal(grown.positions[:g.vertex_count], g.positions)
    assert np.array_equal(grown.edges[:g.edge_count], g.edges)
    assert all(inside(region, p) for p in grown.positions[g.vertex_count:])
    again, _ = ggg.grow_region(g, grammar, region, seed=4)
    assert np.array_equal(again.positions, grown.positions)
    rules, report = ggg.grow_region(g, grammar, region, seed=4, trace_streets=False)
    assert report["traced_streets"] == 0 and report["placements"] > 0 and report["border_connections"] > 0
    small, report = ggg.grow_region(g, grammar, region, seed=4, max_placements=3, trace_streets=False)
    assert report["placements"] == 3 and report["stopped_by_budget"]
    with pytest.raises(ggg.UsageError):
        ggg.grow_region(g, grammar, np.zeros((2, 2)))
    with pytest.raises(ggg.Cancelled):
        ggg.grow_region(g, grammar, region, progress=lambda f, m: False)


def test_replace_squares_by_plazas():
    g = grid(9, jitter=0.0)
    best = [iso for iso in ggg.analyze(g, max_order=4).isogroups if iso.order == 4 and iso.edge_count == 4][0]
    angles = np.linspace(0, 2 * np.pi, 8, endpoint=False)
    ring = np.c_[np.cos(angles), np.sin(angles)] * 3.0  # any size: fitted to the square
    edges = np.array([(i, (i + 1) % 8) for i in range(8)])
    out, report = ggg.replace_isogroup(g, best, ring, edges)
    m = len(best.non_overlapping)
    assert report["replaced"] == m == 16
    # The squares' corners where other streets meet stay, each joined to its plaza.
    assert out.vertex_count == g.vertex_count - report["removed_vertices"] + 8 * m
    assert out.edge_count == g.edge_count - 4 * m + 8 * m + report["joined_streets"]
    assert report["joined_streets"] == 4 * m - report["removed_vertices"] and report["intersections"] == 0
    one, report = ggg.replace_isogroup(g, best, ring, edges, occurrences=np.array([best.non_overlapping[0]]))
    assert report["replaced"] == 1 and one.vertex_count == g.vertex_count - report["removed_vertices"] + 8
    with pytest.raises(ggg.UsageError):
        ggg.replace_isogroup(g, best, ring, np.array([[0, 99]]))
    with pytest.raises(ggg.UsageError):
        ggg.replace_isogroup(g, best, ring, edges, occurrences=np.array([0, 0]))


def test_continue_hierarchy_joins_facing_main_roads():
    """Two secondary roads facing each other across a grown north-south street: a straight
    secondary joins them, and the grown street gets an intersection where it is crossed."""
    classes = ggg.highway_classes()
    secondary, residential = classes.index("secondary"), classes.index("residential")
    positions = np.array([[-200, 200], [0, 200], [800, 200], [600, 200],   # the two roads
                          [0, 300], [600, 100], [300, 0], [300, 400]], float)  # grown
    edges = np.array([[0, 1], [2, 3], [1, 4], [3, 5], [6, 7]])
    highway = np.array([secondary, secondary, residential, residential, residential])
    g = ggg.Graph.from_arrays(positions, edges, edge_highway=highway)
    out, report = ggg.continue_hierarchy(g, 2)
    assert report == {"main_roads": 2, "routes": 0, "raised_streets": 0, "connectors": 1,
                      "connector_streets": 2, "intersections": 1, "extensions": 0}
    assert out.vertex_count == 9 and out.edge_count == 8
    np.testing.assert_allclose(out.positions[8], [300.0, 200.0])
    assert np.array_equal(out.edges[:2], edges[:2]) and np.array_equal(out.edge_highway[:5], highway)
    assert (out.edge_highway[6:] == secondary).all() and out.edge_highway[5] == residential
    assert np.count_nonzero((out.edges == 8).any(axis=1)) == 4
    assert np.array_equal(g.edges, edges)  # the input is not changed
    with pytest.raises(ggg.UsageError):
        ggg.continue_hierarchy(g, 9)
    with pytest.raises(ggg.UsageError):
        ggg.continue_hierarchy(g, 2, max_detour=0.5)


# A dead end closed at the end onto a grown street ahead makes a T-junction there. A grown
# street may leave the region to join a street of the base, so the junction was once made
# outside the region (23 m west of it, east of the sample town with a rule placed by hand).
def test_dead_ends_are_closed_inside_the_region():
    sample = Path(__file__).resolve().parents[3] / "samples" / "sample_city.osm"
    town = ggg.read_graph(str(sample), highways="drivable")
    grammar, _ = ggg.learn(town)
    region = np.array([[700.0, -600.0], [1500.0, -600.0], [1500.0, 600.0], [700.0, 600.0]])
    placed = (grammar.rules[0]["symbol"], 1100.0, 0.0, 80.0, 20.0)
    for seed in (1, 2, 3):
        for placements in ([], [placed]):
            grown, report = ggg.grow_region(town, grammar, region, seed=seed, placements=placements)
            new = grown.positions[town.vertex_count:]
            assert ((new[:, 0] >= 700.0 - 1e-6) & (new[:, 0] <= 1500.0 + 1e-6) & (np.abs(new[:, 1]) <= 600.0 + 1e-6)).all(), (seed, report)
