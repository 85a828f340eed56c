"""core.columns and core.growth with the native module: cutting a graph down, appending what
growth added, joining two graphs, and the rules placed by hand."""

from pathlib import Path

import numpy as np
import pytest

from road_grammar.core.columns import GraphColumns, joined, more_rewrite_slots, more_rewrites_from_slots
from road_grammar.core.growth import fitted, grow_into_region, placed_rules
from road_grammar.core.jobs import StepsJob
from road_grammar.core.topology import replaced_vertices

REPO = Path(__file__).resolve().parent.parent.parent


def columns(positions, edges, symbols=None, frames=None, highway=None):
    out = GraphColumns()
    out.positions = np.asarray(positions, dtype=np.float64)
    out.edges = np.asarray(edges, dtype=np.int64).reshape(-1, 2)
    n, m = len(out.positions), len(out.edges)
    out.symbols = np.zeros(n, dtype=np.int64) if symbols is None else np.asarray(symbols, dtype=np.int64)
    ab = np.tile([1.0, 0.0], (n, 1)) if frames is None else np.asarray(frames, dtype=np.float64)
    out.frames = np.column_stack((ab, out.positions))
    out.frame_missing = np.zeros(n, dtype=bool)
    out.highway = None if highway is None else np.asarray(highway, dtype=np.int64)
    out.columns = {"width": np.full(m, np.nan), "lanes": np.zeros(m, dtype=np.int64)}
    out.refused = {}
    out.names = ["street {}".format(e) for e in range(m)]
    out.geometry = None
    out.edge_attributes = {"mark": ('INT', np.arange(m))}
    out.point_attributes = {}
    out.vertex_flags = {"select": np.zeros(n, dtype=bool), "hide": np.zeros(n, dtype=bool)}
    out.edge_flags = {"select": np.ones(m, dtype=bool), "hide": np.zeros(m, dtype=bool)}
    out.origin_latlon = (0.0, 0.0)
    return out


SQUARE = [[0, 0], [100, 0], [100, 100], [0, 100]]
RING = [[0, 1], [1, 2], [2, 3], [3, 0]]


def test_graph_columns(ggg):
    square = columns(SQUARE + [[50, 50]], RING, symbols=[0, 0, 0, 0, 1])
    assert square.nonterminal_count == 1
    graph = square.graph(ggg)
    assert graph.vertex_count == 5 and graph.edge_count == 4
    assert list(graph.edge_names) == square.names


def test_induced_subgraph_and_with_grown(ggg):
    graph = columns(SQUARE + [[50, 50]], RING + [[0, 4]]).graph(ggg)
    keep = np.array([True, True, True, True, False])
    sub, vertex_ids, edge_ids = ggg.induced_subgraph(graph, keep)
    assert sub.vertex_count == 4 and vertex_ids.tolist() == [0, 1, 2, 3] and edge_ids.tolist() == [0, 1, 2, 3]
    assert list(sub.edge_names) == ["street 0", "street 1", "street 2", "street 3"]
    # "Growth": one more vertex joined to vertex 2.
    grown = ggg.Graph.from_arrays(np.vstack((np.asarray(sub.positions), [[150, 150]])),
                                  np.vstack((np.asarray(sub.edges), [[2, 4]])),
                                  edge_names=list(sub.edge_names) + ["grown"])
    result, source = ggg.with_grown(graph, keep, vertex_ids, edge_ids, grown)
    assert result.vertex_count == 5 and result.edge_count == 5
    assert source.tolist() == [0, 1, 2, 3, -1]
    assert np.asarray(result.edges)[-1].tolist() == [2, 4]
    assert list(result.edge_names) == ["street 0", "street 1", "street 2", "street 3", "grown"]
    with pytest.raises(ggg.Error, match="keep"):
        ggg.induced_subgraph(graph, np.ones(3, dtype=bool))
    with pytest.raises(ggg.Error, match="not kept"):
        ggg.with_grown(graph, np.array([True, False, True, True, True]), vertex_ids, edge_ids, grown)


def test_joined(ggg):
    first = columns(SQUARE, RING)
    second = columns(SQUARE, RING, symbols=[0, 2, 0, 0], frames=[[1, 0], [0, 2], [1, 0], [1, 0]])
    second.names = None
    second.edge_attributes = {}
    move = np.eye(4)
    move[:2, :2] = [[0, -1], [1, 0]]  # a quarter turn
    move[:2, 3] = [1000, 0]
    both = joined(ggg, first, second, move)
    assert len(both.positions) == 8 and both.edges[4:].tolist() == [[4, 5], [5, 6], [6, 7], [7, 4]]
    assert both.positions[5].tolist() == [1000, 100]
    assert both.frames[5, :2].tolist() == [-2, 0]  # turned with the graph
    assert both.names == first.names + [""] * 4
    assert both.edge_attributes["mark"][1].tolist() == [0, 1, 2, 3, 0, 0, 0, 0]
    assert both.geometry[0].tolist() == [0, 2, 4, 6, 8, 10, 12, 14, 16]
    assert both.graph(ggg).vertex_count == 8


SIERPINSKI = REPO / "samples" / "sierpinski.grammar.json"


def test_more_rewrites_through_slots_and_back(ggg):
    """The rewrites a shared corner carries besides its own go into per-vertex slots (the
    mesh's symbol_k, frame_a_k, frame_b_k) and come back as the same Graph.more_rewrites."""
    two, _ = ggg.derive(ggg.read_grammar(str(SIERPINSKI)), steps=2)
    vertices, symbols, frames = two.more_rewrites
    slots = more_rewrite_slots(two.vertex_count, two.more_rewrites)
    assert len(slots) == 1 and np.count_nonzero(slots[0][0]) == len(vertices) == 12
    back = more_rewrites_from_slots(slots, np.asarray(two.positions), np.asarray(two.vertex_symbols))
    np.testing.assert_array_equal(back[0], vertices)
    np.testing.assert_array_equal(back[1], symbols)
    np.testing.assert_allclose(back[2], frames, atol=1e-6)
    # A slot on a vertex that is not a nonterminal (a symbol cleared by hand) is dropped.
    cleared = np.asarray(two.vertex_symbols).copy()
    cleared[vertices[0]] = 0
    assert len(more_rewrites_from_slots(slots, np.asarray(two.positions), cleared)[0]) == 11
    assert more_rewrites_from_slots([], np.zeros((0, 2)), np.zeros(0)) is None


def test_joined_carries_more_rewrites(ggg):
    """Stitch Cities: the second graph's shared corners keep their rewrites, turned with it."""
    two, _ = ggg.derive(ggg.read_grammar(str(SIERPINSKI)), steps=1)
    part = columns(two.positions, two.edges, symbols=two.vertex_symbols, frames=np.asarray(two.vertex_frames)[:, :2])
    part.more_rewrites = two.more_rewrites
    move = np.eye(4)
    move[:2, :2] = [[0, -1], [1, 0]]
    move[:2, 3] = [5000, 0]
    both = joined(ggg, columns(SQUARE, RING), part, move)
    vertices, _, frames = both.more_rewrites
    assert (vertices == np.asarray(two.more_rewrites[0]) + 4).all()
    np.testing.assert_allclose(frames[:, :2], np.asarray(two.more_rewrites[2])[:, :2] @ np.array([[0, -1], [1, 0]]).T)
    np.testing.assert_allclose(frames[:, 2:], both.positions[vertices])
    graph = both.graph(ggg)
    assert len(graph.more_rewrites[0]) == 3


class Parsed:
    rules = [{"symbol": 1}, {"symbol": 3}]


def test_placed_rules():
    graph = columns(SQUARE + [[50, 50], [20, 20], [70, 70]], RING, symbols=[0, 0, 0, 0, 1, 2, 3],
                    frames=[[1, 0]] * 4 + [[0, 40], [1, 0], [3, 4]])
    graph.frame_missing[6] = True
    vertices, placements = placed_rules(graph, Parsed)
    assert vertices == [4, 6]  # symbol 2 has no rule
    assert placements[0] == pytest.approx((1, 50.0, 50.0, 40.0, 90.0))
    assert placements[1][3] == 0.0  # no frame of its own: the rule's learned size
    assert placed_rules(graph, Parsed, [False] * 6 + [True])[0] == [6]


def test_fitted():
    assert fitted({"hand_placements": []}) == []
    assert fitted({"hand_placements": ["placed", "outside", "placed", "crowded"]}) == [True, False, True, False]


def _sample_town(ggg):
    """(GraphColumns of the sample town, its learned grammar, a rectangle east of it)."""
    path = REPO / "samples" / "sample_city.osm"
    if not path.is_file():
        pytest.skip("{} is absent".format(path))
    graph = ggg.read_graph(str(path))
    town = columns(np.asarray(graph.positions), np.asarray(graph.edges),
                   highway=np.asarray(graph.edge_highway))
    grammar, _stats = ggg.learn(graph)
    return town, grammar, np.array([[700.0, -600.0], [1500.0, -600.0], [1500.0, 600.0], [700.0, 600.0]])


def test_grow_into_region_in_a_job(ggg):
    """The growth of Grow into Region, run as a job, is ggg.grow_region on the town's streets,
    with the town's vertices and edges first; the job's progress goes from 0 to 1."""
    town, grammar, region = _sample_town(ggg)
    def work(job):
        return grow_into_region(job, ggg, town, grammar, region, [], [], seed=1, max_placements=200,
                                max_vertices=200000, patience=150)

    job = StepsJob(ggg, work)
    job.start()
    job.join()
    assert job.error is None and job.fraction == 1.0 and job.calls > 3
    grown = job.result
    direct, report = ggg.grow_region(town.graph(ggg), grammar, region, seed=1)
    assert grown.report["added_vertices"] == report["added_vertices"] > 0 and grown.used == []
    np.testing.assert_allclose(np.asarray(grown.result.positions), np.asarray(direct.positions))
    np.testing.assert_array_equal(np.asarray(grown.result.edges), np.asarray(direct.edges))
    assert grown.source.tolist() == list(range(len(town.positions))) + [-1] * report["added_vertices"]


def test_grow_into_region_cancelled(ggg):
    """Cancelled while the library grows: ggg.Cancelled, no result."""
    town, grammar, region = _sample_town(ggg)

    class CancelInGrowth(StepsJob):
        def __call__(self, fraction, message):
            if message in ("placing rules", "tracing streets"):
                self.cancel()
            return super().__call__(fraction, message)

    job = CancelInGrowth(ggg, lambda job: grow_into_region(job, ggg, town, grammar, region, [], [], seed=1,
                                                           max_placements=200, max_vertices=200000, patience=150))
    job.start()
    job.join()
    assert isinstance(job.error, ggg.Cancelled) and job.result is None


def test_replaced_vertices_are_those_the_library_removes(ggg):
    """Replace maps the vertices of ggg.replace_isogroup's result back to the graph's with
    core.topology.replaced_vertices: the kept ones come first, in their order, at their
    places; the occurrences' junctions among them."""
    path = REPO / "samples" / "sample_city.osm"
    if not path.is_file():
        pytest.skip("{} is absent".format(path))
    graph = ggg.read_graph(str(path))
    best = ggg.analyze(graph).isogroups[0]
    t = np.linspace(0.0, 2.0 * np.pi, 12, endpoint=False)
    ring = np.column_stack((np.cos(t), np.sin(t)))
    out, report = ggg.replace_isogroup(graph, best, ring, [(k, (k + 1) % 12) for k in range(12)])
    chosen = np.asarray(best.occurrences)[best.non_overlapping]
    removed = replaced_vertices(graph.vertex_count, graph.edges, chosen)
    kept = np.flatnonzero(~removed)
    assert 0 < removed.sum() == report["removed_vertices"] < chosen.size  # some junctions stay
    assert out.vertex_count == len(kept) + report["added_vertices"]
    np.testing.assert_array_equal(np.asarray(out.positions)[:len(kept)], np.asarray(graph.positions)[kept])
