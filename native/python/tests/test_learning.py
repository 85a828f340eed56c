"""ggg.learn, ggg.decode and ggg.encoded_graph: a jittered street grid learned in both modes."""
import json
from pathlib import Path

import numpy as np
import pytest

import ggg

SAMPLE_CITY = Path(__file__).resolve().parents[3] / "samples" / "sample_city.osm"


def grid(n, spacing=100.0, jitter=1.0, seed=1):
    rng = np.random.default_rng(seed)
    ij = np.array([(i, j) for j in range(n) for i in range(n)], float) * spacing
    positions = ij + rng.normal(0.0, jitter, ij.shape)
    edges = []
    for j in range(n):
        for i in range(n):
            v = j * n + i
            if i + 1 < n:
                edges.append((v, v + 1))
            if j + 1 < n:
                edges.append((v, v + n))
    return ggg.Graph.from_arrays(positions, np.array(edges), (41.39, 2.16), edge_highway=np.full(len(edges), 6))


def same_streets(a, b, tolerance):
    """Every vertex of b within `tolerance` of its own vertex of a, and the same edges."""
    d = np.linalg.norm(a.positions[:, None, :] - b.positions[None, :, :], axis=2)
    match = d.argmin(axis=0)
    assert d[match, np.arange(len(match))].max() <= tolerance
    assert len(set(match.tolist())) == a.vertex_count
    edges_a = {tuple(sorted(e)) for e in a.edges.tolist()}
    edges_b = {tuple(sorted((int(match[u]), int(match[v])))) for u, v in b.edges.tolist()}
    return edges_a == edges_b


@pytest.mark.parametrize("lossless", [False, True])
def test_learn_and_decode_a_grid(lossless):
    # Lossless, a rule pays where its residuals are cheaper than the positions they replace:
    # on a grid jittered by 20 cm, not by 1 m (docs/learning.md#size).
    g = grid(16, jitter=0.2 if lossless else 1.0)
    grammar, stats = ggg.learn(g, lossless=lossless)
    assert grammar.learned and grammar.mode == ("lossless" if lossless else "paper")
    assert stats["input"] == {"vertices": g.vertex_count, "edges": g.edge_count}
    assert stats["rules"] == len(grammar.rules) > 0
    assert stats["levels"] == grammar.levels >= 1
    assert all(r["uses"] >= 2 and r["level"] >= 1 for r in grammar.rules)
    assert stats["roundtrip"]["edges_equal"]
    decoded = ggg.decode(grammar)
    assert decoded.vertex_count == g.vertex_count and decoded.edge_count == g.edge_count
    if lossless:
        exact = 0.7072 * 0.01  # lossless to the 1 cm quantum
        assert stats["roundtrip"]["max_displacement_m"] <= exact
        assert same_streets(g, decoded, exact)
    else:
        assert 0 < stats["roundtrip"]["mean_displacement_m"] < 10.0
        assert same_streets(g, decoded, stats["roundtrip"]["max_displacement_m"] + 1e-9)
    # Written and read back, the grammar decodes to the same streets.
    again = ggg.decode(ggg.parse_grammar(grammar.to_json()))
    assert np.array_equal(again.positions, decoded.positions)
    assert np.array_equal(again.edges, decoded.edges)


def test_encoded_graph_of_each_level():
    grammar, _ = ggg.learn(grid(16))
    streets = ggg.decode(grammar)
    top, image = ggg.encoded_graph(grammar, grammar.levels)
    assert image.dtype == np.int32 and image.shape == (streets.vertex_count,)
    assert top.vertex_count < streets.vertex_count
    symbols = top.vertex_symbols
    nonterminals = np.flatnonzero(symbols)
    assert len(nonterminals) > 0
    # Each nonterminal stands for as many streets' vertices as its rule has terminals (or more).
    counts = np.bincount(image, minlength=top.vertex_count)
    assert (counts[nonterminals] >= 2).all()
    assert (counts[symbols == 0] == 1).all()
    bottom, identity = ggg.encoded_graph(grammar, 0)
    assert bottom.vertex_count == streets.vertex_count
    assert np.array_equal(identity, np.arange(streets.vertex_count))
    with pytest.raises(ggg.UsageError):
        ggg.encoded_graph(grammar, grammar.levels + 1)


def test_learning_the_sample_town():
    g = ggg.read_graph(str(SAMPLE_CITY), highways="all")
    grammar, stats = ggg.learn(g, lossless=True)
    assert stats["roundtrip"]["edges_equal"] and stats["roundtrip"]["classes_equal"]
    json.dumps(stats)  # plain Python values


def test_progress_cancel_and_errors():
    g = grid(10)
    seen = []
    ggg.learn(g, progress=lambda f, m: seen.append((f, m)))
    assert seen and seen[-1][0] == 1.0 and any(m.startswith("level 1") for _, m in seen)
    with pytest.raises(ggg.Cancelled):
        ggg.learn(g, progress=lambda f, m: False)

    def boom(f, m):
        raise KeyError("from the callback")

    with pytest.raises(KeyError):
        ggg.learn(g, progress=boom)
    lonely = ggg.Graph.from_arrays(np.zeros((1, 2)), np.zeros((0, 2), dtype=np.int32))
    with pytest.raises(ggg.InputError):
        ggg.learn(lonely)
    with pytest.raises(ggg.UsageError):
        ggg.learn(g, levels=-1)
    hand_written = ggg.parse_grammar(json.dumps({
        "format": "ggg-grammar", "version": 1, "rules": [],
        "axiom": {"vertices": [{"position": [0, 0]}], "edges": []}}))
    assert not hand_written.learned
    with pytest.raises(ggg.GrammarError):
        ggg.decode(hand_written)


def test_compare_networks():
    a = grid(10)
    same = ggg.compare(a, a)
    assert same["distances"]["mean"] == 0.0
    assert set(same["distances"]) == {"degree", "edge_length", "orientation", "block_area", "mean", "junction_angle"}
    structure = same["a"]
    assert structure["dead_end_share"] == pytest.approx(0.0) and structure["star_share"] == 0.0
    assert structure["junctions"] > 0 and structure["right_angle_share"] > 0.8 and structure["through_share"] == 1.0
    assert 1.0 < structure["circuity"] < 2 ** 0.5
    coarse = ggg.compare(a, grid(10, spacing=250.0))
    assert coarse["distances"]["edge_length"] == 1.0 and coarse["distances"]["block_area"] == 1.0
    assert coarse["a"]["orientation_order"] > 0.9 and coarse["a"]["blocks"] == 81


def test_learning_from_a_users_piece():
    g = grid(10)
    grammar, stats = ggg.learn(g, seed=np.array([0, 1, 11, 10]), lossless=True)
    first = grammar.rules[0]
    assert (first["vertices"], first["edges"]) == (4, 4) and first["uses"] >= 20
    assert stats["per_level"][0]["rules"] == 1 and stats["roundtrip"]["edges_equal"]
    with pytest.raises(ggg.UsageError):
        ggg.learn(g, seed=np.array([0, 10 ** 6]))
