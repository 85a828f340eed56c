"""What the CLI refuses, the Python module refuses too, as a ValueError that names the argument;
bounded readers, budgets, a damaged grammar and safe concurrent writes."""

import json
import math
import os
import subprocess
import sys
import threading
from pathlib import Path

import numpy as np
import pytest

import ggg

REPO = Path(__file__).resolve().parents[3]
SAMPLE = REPO / "samples" / "sample_city.osm"


@pytest.fixture(scope="module")
def town():
    return ggg.read_graph(str(SAMPLE))


@pytest.fixture(scope="module")
def town_grammar(town):
    grammar, _stats = ggg.learn(town)
    return grammar


def test_usage_error_is_a_value_error():
    assert issubclass(ggg.UsageError, ValueError) and issubclass(ggg.UsageError, ggg.Error)


@pytest.mark.parametrize("argument, value", [
    ("min_aspect", math.nan), ("min_irregularity", math.nan), ("tolerance", math.nan), ("cut", math.inf),
    ("min_leaves", -1), ("recount", -3), ("min_count", 0), ("max_seconds", math.nan), ("max_memory_mb", -1.0),
])
def test_analyze_refuses_values_that_mean_nothing(town, argument, value):
    with pytest.raises(ValueError, match="^" + argument):
        ggg.analyze(town, max_order=3, **{argument: value})


@pytest.mark.parametrize("argument, value", [
    ("min_aspect", math.nan), ("max_shape_error", math.nan), ("min_leaves", -1), ("levels", -2),
])
def test_learn_refuses_values_that_mean_nothing(town, argument, value):
    with pytest.raises(ValueError, match="^" + argument):
        ggg.learn(town, **{argument: value})


REGION = np.array([[800.0, -300.0], [1300.0, -300.0], [1300.0, 300.0], [800.0, 300.0]])


@pytest.mark.parametrize("argument, value", [
    ("seed", 2 ** 64), ("seed", -1), ("max_placements", 0), ("max_vertices", -5), ("patience", -1),
    ("border_m", math.nan), ("border_m", math.inf), ("prune_stubs", -1.0), ("size_jitter", 1.0), ("trace_streets", "yes"),
    ("snap", "near"),
])
def test_grow_region_refuses_values_that_mean_nothing(town, town_grammar, argument, value):
    with pytest.raises(ValueError, match="^" + argument):
        ggg.grow_region(town, town_grammar, REGION, **{argument: value})


def test_grow_region_names_its_options_for_an_unknown_one(town, town_grammar):
    with pytest.raises(ValueError, match="no option 'max_placement'.*max_placements"):
        ggg.grow_region(town, town_grammar, REGION, max_placement=5)
    assert set(ggg.option_defaults()["growth"]) >= {"seed", "max_placements", "prune_stubs", "trace_streets"}
    assert "prune_stubs = 0.75" in ggg.grow_region.__doc__


def test_grow_region_takes_the_largest_seed_and_refuses_a_region_without_area_crossed_or_far(town, town_grammar):
    grown, report = ggg.grow_region(town, town_grammar, REGION, seed=2 ** 64 - 1, max_placements=5)
    assert grown.vertex_count >= town.vertex_count
    line = np.array([[800.0, 0.0], [1000.0, 100.0], [1200.0, 200.0]])
    with pytest.raises(ValueError, match="no area"):
        ggg.grow_region(town, town_grammar, line)
    bow_tie = np.array([[800.0, 0.0], [1000.0, 200.0], [1000.0, 0.0], [800.0, 200.0]])
    with pytest.raises(ValueError, match=r"crosses itself \(its sides from corners 1 and 3 meet\)"):
        ggg.grow_region(town, town_grammar, bow_tie)
    with pytest.raises(ValueError, match=r"the region is 10\d km from the streets of the base \(at most 20 km\)"):
        ggg.grow_region(town, town_grammar, REGION + [101000.0, 0.0])
    with pytest.raises(ValueError, match="tolerance"):
        ggg.derive(ggg.read_grammar(str(REPO / "samples" / "sierpinski.grammar.json")), tolerance=math.nan)


def test_until_nothing_repeats_ends_at_its_budget(town):
    a = ggg.analyze(town, max_order=0, max_seconds=2.0)
    assert a.stopped_by_budget and len(a.isogroups) > 10
    grammar, stats = ggg.learn(town, max_order=0, max_seconds=3.0, lossless=True)
    assert stats["stopped_by_budget"] and stats["roundtrip"]["edges_equal"]
    assert ggg.decode(grammar).edge_count == town.edge_count


def test_a_damaged_grammar_does_not_decode(town, tmp_path):
    grammar, _stats = ggg.learn(town)
    path = tmp_path / "town.grammar.json"
    grammar.write(str(path))
    doc = json.loads(path.read_text())
    # The first nonterminal moved 10 km (positions are delta-coded quanta of 1 cm: the next
    # stays). The packed form places the axiom's columns: x first, nonterminals third.
    assert doc["version"] == 6 and doc["encoding"][3] == -26  # the quantum's code: 0.01 m
    x, nonterminals = doc["axiom"][0], doc["axiom"][2]
    at = nonterminals[0]
    far = 1_000_000
    x[at] += far
    x[at + 1] -= far
    damaged = ggg.parse_grammar(json.dumps(doc), "damaged")
    with pytest.raises(ggg.GrammarError, match="does not decode to what it encodes"):
        ggg.decode(damaged)


def test_readers_are_bounded(tmp_path):
    deep = tmp_path / "deep.geojson"
    deep.write_text('{"type":"GeometryCollection","geometries":[' * 30000)
    with pytest.raises(ggg.InputError, match="nested more than 64 deep"):
        ggg.read_graph(str(deep))
    zero = tmp_path / "zero.ggraph"
    zero.symlink_to("/dev/zero")
    with pytest.raises(ggg.InputError, match="more than 256 MiB came from this character device"):
        ggg.read_graph(str(zero))
    far = tmp_path / "far.osm"
    far.write_text('<?xml version="1.0"?><osm version="0.6"><node id="7" lat="1e300" lon="8"/>'
                   '<node id="8" lat="46" lon="8"/><way id="1"><nd ref="7"/><nd ref="8"/>'
                   '<tag k="highway" v="residential"/></way></osm>')
    with pytest.raises(ggg.InputError, match="node 7: latitude '1e300' is out of range"):
        ggg.read_graph(str(far))


def test_concurrent_writes_to_one_path_all_succeed(town, tmp_path):
    target = tmp_path / "town.ggraph"
    errors = []

    def write():
        try:
            for _ in range(10):
                town.write(str(target))
        except ggg.Error as error:  # pragma: no cover - the failure the test looks for
            errors.append(error)

    threads = [threading.Thread(target=write) for _ in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert errors == []
    assert sorted(p.name for p in tmp_path.iterdir()) == ["town.ggraph"]
    assert ggg.read_graph(str(target)).edge_count == town.edge_count


def test_a_write_that_fails_half_way_keeps_the_previous_file(town, tmp_path):
    target = tmp_path / "town.geojson"
    target.write_text("previous")
    # In a child process with a file size limit of 16 KiB, as on a full disk.
    script = (
        "import resource, signal, sys, ggg\n"
        "signal.signal(signal.SIGXFSZ, signal.SIG_IGN)\n"
        "resource.setrlimit(resource.RLIMIT_FSIZE, (16384, 16384))\n"
        "g = ggg.read_graph(sys.argv[1])\n"
        "try:\n"
        "    g.write(sys.argv[2])\n"
        "except ggg.InputError as e:\n"
        "    print(e); sys.exit(3)\n"
    )
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path))
    result = subprocess.run([sys.executable, "-c", script, str(SAMPLE), str(target)], capture_output=True, text=True,
                            env=env, check=False)
    assert result.returncode == 3, result.stderr
    assert "write failed" in result.stdout
    assert target.read_text() == "previous"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["town.geojson"]
    with pytest.raises(ValueError, match="symbolic link"):
        link = tmp_path / "link.geojson"
        link.symlink_to(target)
        town.write(str(link))
    assert target.read_text() == "previous"
