"""The Python module outside Blender: arrays across the boundary, errors, progress."""

import os
from pathlib import Path

import numpy as np
import pytest

import ggg

REPO = Path(__file__).resolve().parents[3]
SAMPLE = REPO / "samples" / "sample_city.osm"
SIERPINSKI = REPO / "samples" / "sierpinski.grammar.json"


def triangle(**columns):
    positions = np.array([[0.0, 0.0], [100.0, 0.0], [50.0, 80.0]])
    edges = np.array([[0, 1], [1, 2], [2, 0]])
    return ggg.Graph.from_arrays(positions, edges, (46.0, 8.95), **columns)


def test_read_graph_gives_numpy_columns():
    g = ggg.read_graph(str(SAMPLE), highways="all")
    assert g.positions.shape == (g.vertex_count, 2) and g.positions.dtype == np.float64
    assert g.edges.shape == (g.edge_count, 2) and g.edges.dtype == np.int32
    offsets, points = g.edge_geometry()
    assert offsets.shape == (g.edge_count + 1,) and offsets[-1] == len(points)
    assert np.allclose(points[offsets[:-1]], g.positions[g.edges[:, 0]])
    names = ggg.highway_classes()
    assert {names[c] for c in g.edge_highway} >= {"residential", "primary", "motorway"}
    assert g.info()["edges"] == g.edge_count


def test_from_arrays_round_trips_every_column():
    g = ggg.read_graph(str(SAMPLE), highways="all")
    back = ggg.Graph.from_arrays(
        g.positions, g.edges, g.origin_latlon, g.vertex_symbols, g.vertex_frames, g.vertex_osm_ids,
        g.edge_highway, g.edge_width, g.edge_lanes, g.edge_oneway, g.edge_way_ids, g.edge_names, g.edge_geometry())
    assert np.array_equal(back.edge_geometry()[1], g.edge_geometry()[1])
    assert np.allclose(back.edge_width, g.edge_width, equal_nan=True)
    assert back.edge_names == g.edge_names
    assert back.total_length_m == pytest.approx(g.total_length_m)


@pytest.mark.parametrize("edges, message", [
    ([[0, 0]], "itself"),
    ([[0, 1], [1, 0]], "repeats an edge"),
    ([[0, 5]], "out of range"),
])
def test_from_arrays_refuses_what_files_refuse(edges, message):
    with pytest.raises(ggg.InputError, match=message):
        ggg.Graph.from_arrays(np.zeros((2, 2)) + [[0, 0], [1, 0]], np.array(edges))


def test_from_arrays_checks_values():
    with pytest.raises(ggg.InputError, match="origin_latlon"):
        ggg.Graph.from_arrays(np.array([[0.0, 0], [1, 0]]), np.array([[0, 1]]), (float("nan"), 0.0))
    with pytest.raises(ggg.InputError, match="symbol"):
        triangle(vertex_symbols=np.array([2**32 + 1, 0, 0], dtype=np.int64))
    offsets = np.array([0, 2, 4, 6])
    points = np.array([[0, 0], [100, 0], [100, 0], [50, 80], [50, 80], [np.nan, 0]], dtype=float)
    with pytest.raises(ggg.InputError, match="not finite"):
        triangle(edge_geometry=(offsets, points))


def test_progress_is_reported_and_can_cancel():
    seen = []
    ggg.read_graph(str(SAMPLE), progress=lambda f, m: seen.append((f, m)))
    assert seen[0][0] == 0.0 and seen[-1][0] == 1.0
    with pytest.raises(ggg.Cancelled):
        ggg.read_graph(str(SAMPLE), progress=lambda f, m: 0)
    ggg.read_graph(str(SAMPLE), progress=lambda f, m: "yes")  # any true value goes on


def test_an_exception_in_the_callback_comes_back_as_itself():
    def boom(fraction, message):
        raise KeyError("from the callback")
    with pytest.raises(KeyError, match="from the callback"):
        ggg.read_graph(str(SAMPLE), progress=boom)


def test_errors_are_typed():
    with pytest.raises(ggg.InputError, match="no such file"):
        ggg.read_graph("/nonexistent/city.osm.pbf")
    with pytest.raises(ggg.UsageError, match="unknown highway class"):
        ggg.read_graph(str(SAMPLE), highways="primay")
    with pytest.raises(ggg.GrammarError, match="missing \"axiom\""):
        ggg.parse_grammar('{"format":"ggg-grammar","version":1,"rules":[]}', "g.json")
    assert issubclass(ggg.InputError, ggg.Error) and issubclass(ggg.Error, Exception)


def test_derive_reports_sources_and_keeps_the_input():
    grammar = ggg.read_grammar(str(SIERPINSKI))
    axiom = grammar.axiom_graph()
    graph, report = ggg.derive(grammar, axiom, steps=3)
    assert (report["vertices"], report["steps"]) == (42, 3)
    assert axiom.vertex_count == 3  # not changed
    assert report["source_vertex"].shape == (42,) and (report["source_vertex"] == -1).all()
    again, _ = ggg.derive(grammar, steps=3)
    assert np.array_equal(again.positions, graph.positions)


def test_a_corner_two_triangles_share_is_one_vertex_with_both_rewrites():
    grammar = ggg.read_grammar(str(SIERPINSKI))
    two, _ = ggg.derive(grammar, steps=2)
    vertices, symbols, frames = two.more_rewrites
    # 27 corners at 15 places: 12 places hold a second triangle's corner.
    assert (two.vertex_count, len(vertices)) == (15, 12)
    assert (symbols == 1).all() and np.allclose(frames[:, 2:], two.positions[vertices])
    assert len({tuple(p) for p in np.round(two.positions, 6)}) == two.vertex_count
    # The columns carry them: a graph rebuilt from its arrays derives on as the original does.
    rebuilt = ggg.Graph.from_arrays(two.positions, two.edges, vertex_symbols=two.vertex_symbols,
                                    vertex_frames=two.vertex_frames, more_rewrites=two.more_rewrites)
    three, _ = ggg.derive(grammar, rebuilt, steps=1)
    direct, _ = ggg.derive(grammar, steps=3)
    assert np.array_equal(three.positions, direct.positions) and np.array_equal(three.edges, direct.edges)
    with pytest.raises(ggg.InputError, match="is not a nonterminal"):
        ggg.Graph.from_arrays(np.zeros((1, 2)), np.zeros((0, 2)), more_rewrites=([0], [1], [[1.0, 0.0, 0.0, 0.0]]))
