"""core.analysis (an analysis as it is stored), core.flythrough and core.levels."""

import json
from types import SimpleNamespace

import numpy as np
import pytest

from road_grammar.core import flythrough
from road_grammar.core.analysis import (NON_OVERLAPPING, OCCURRENCES, PATTERN_EDGES, StoredAnalysis, options_json,
                                        same_occurrences)
from road_grammar.core.levels import LevelView


def isogroup(order, occurrences, non_overlapping, pattern_edges, parent=-1):
    return SimpleNamespace(order=order, edge_count=len(pattern_edges), frequency=len(occurrences),
                           occurrences=np.asarray(occurrences), non_overlapping=np.asarray(non_overlapping),
                           pattern_edges=np.asarray(pattern_edges), gain=1.5, score=2.0, size_m=50.0, aspect=0.9,
                           leaves=0, irregularity_deg=3.0, parent=parent, selection_exact=True,
                           selection_method="exact")


def test_stored_analysis():
    groups = [isogroup(2, [[0, 1], [2, 3], [1, 2]], [0, 1], [[0, 1]]),
              isogroup(3, [[0, 1, 2], [1, 2, 3]], [0], [[0, 1], [1, 2]], parent=0),
              isogroup(2, [[5, 6]], [0], [[0, 1]])]
    analysis = SimpleNamespace(detected=7, stopped_by_budget=False)
    stored = StoredAnalysis(analysis, groups, max_stored=2, overview_count=1)
    assert stored.count == 2 and stored.listed == 3 and stored.detected == 7 and stored.max_order == 3
    assert stored.names == ["order 2", "order 3"]
    assert list(stored.columns["rank"][1]) == [1, 2] and list(stored.columns["parent"][1]) == [0, 1]
    assert list(stored.columns["color_slot"][1]) == [1, 0]
    assert list(stored.columns["occurrence_start"][1]) == [0, 6]
    assert stored.arrays[OCCURRENCES].tolist() == [0, 1, 2, 3, 1, 2, 0, 1, 2, 1, 2, 3]
    assert stored.arrays[NON_OVERLAPPING].tolist() == [0, 1, 0] and stored.arrays[PATTERN_EDGES].dtype == np.int32
    assert same_occurrences(groups[1], np.array([[0, 1, 2], [1, 2, 3]]), np.array([0]), np.array([[0, 1], [1, 2]]))
    assert not same_occurrences(groups[1], np.array([[0, 1, 2], [1, 2, 4]]), np.array([0]),
                                np.array([[0, 1], [1, 2]]))


def test_options_json():
    text = options_json({"grid": (12, 10), "seed": np.array([3, 4]), "cut": np.float64(0.8), "full": False})
    assert json.loads(text) == {"grid": [12, 10], "seed": [3, 4], "cut": 0.8, "full": False}


def network():
    # A 3 x 3 grid of 100 m blocks; the middle column is a main road (rank 3).
    positions = np.array([[x, y] for y in (0, 100, 200) for x in (0, 100, 200)], dtype=float)
    edges = [[r * 3 + c, r * 3 + c + 1] for r in range(3) for c in range(2)] + \
            [[r * 3 + c, (r + 1) * 3 + c] for r in range(2) for c in range(3)]
    edges = np.array(edges)
    offsets = np.arange(0, 2 * len(edges) + 1, 2)
    points = positions[edges].reshape(-1, 2)
    ranks = np.where((positions[edges[:, 0], 0] == 100) & (positions[edges[:, 1], 0] == 100), 3, 7)
    return flythrough.Network(positions, edges, offsets, points, ranks)


def test_shortest_path_and_track():
    roads = network()
    steps = roads.shortest_path(0, 8)
    line = roads.path_points(steps)
    assert len(steps) == 4 and line[0].tolist() == [0, 0] and line[-1].tolist() == [200, 200]
    with pytest.raises(flythrough.PathError):
        roads.shortest_path(0, 0)
    with pytest.raises(flythrough.PathError):
        roads.shortest_path(0, 99)
    locations, targets, length = flythrough.camera_track(line, 50, 2.0, 30.0, 1.6, 25.0)
    assert locations.shape == (50, 3) and targets.shape == (50, 3) and length == pytest.approx(400.0, rel=0.05)
    assert np.allclose(locations[:, 2], 2.0)
    assert flythrough.max_turn_per_frame(locations, targets) < 20.0


def test_tour_is_seeded():
    roads = network()
    assert roads.tour(600.0, 3) == roads.tour(600.0, 3)


class Encoded:
    """A grammar of two rules; level 1 puts the streets 0-1 and 1-2 into one instance of rule 2."""

    rules = [{"symbol": 1, "name": "R1"}, {"symbol": 2, "name": "R2"}]

    def encoded_graph(self, parsed, level):
        level_graph = SimpleNamespace(vertex_symbols=[2, 0], positions=[[5.0, 0.0], [20.0, 0.0]])
        return level_graph, [0, 0, 0, 1]


def test_level_view():
    streets = SimpleNamespace(positions=[[0, 0], [10, 0], [10, 10], [20, 0]], edges=[[0, 1], [1, 2], [2, 3]],
                              edge_highway=[1, 1, 2])
    ground = LevelView(Encoded(), Encoded, 0, streets)
    assert ground.edge_rule.tolist() == [0, 0, 0] and len(ground.marker_rule) == 0
    view = LevelView(Encoded(), Encoded, 1, streets)
    assert view.edge_rule.tolist() == [2, 2, 0] and view.marker_rule.tolist() == [2]
    assert view.edge_slots().tolist() == [2, 2, 0] and view.edge_slots(highlight=1).tolist() == [0, 0, 0]
    assert view.marker_slots().tolist() == [2] and view.counts() == {2: (1, 2)}
