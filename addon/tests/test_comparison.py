"""core.comparison: the rows of the Compare panel and the report line, from a ggg.compare
dict (a made-up one and a real one); its tables know every member the library returns and
say what docs/cli.md says of each."""

import json
import re

import numpy as np
import pytest

from road_grammar.core import comparison

from conftest import REPO

SAMPLE_CITY = REPO / "samples" / "sample_city.osm"

FAKE = {
    "a": {"blocks": 193, "circuity": 1.37, "dead_end_share": 0.094, "degree2_share": 0.069, "edges": 510,
          "junctions": 267, "mean_degree": 3.2, "median_block_area_m2": 7600.4, "median_edge_length_m": 85.3,
          "orientation_entropy": 2.52, "orientation_order": 0.73, "right_angle_share": 0.82, "star_share": 0.0063,
          "crossing_share": 0.41, "through_share": 0.97, "vertices": 319},
    "b": {"blocks": 0, "circuity": None, "dead_end_share": 0.158, "degree2_share": 0.032, "edges": 1286,
          "junctions": 154, "mean_degree": 3.01, "median_block_area_m2": 12345.6, "median_edge_length_m": 80.7,
          "orientation_entropy": 2.76, "orientation_order": 0.61, "right_angle_share": 0.76, "star_share": 0.0,
          "crossing_share": 0.236, "through_share": 0.95, "vertices": 190},
    "distances": {"block_area": 0.41, "degree": 0.128, "edge_length": 0.207, "junction_angle": 0.125,
                  "mean": 0.2116, "orientation": 0.104},
}


def test_rows_of_a_made_up_result():
    rows = comparison.measure_rows(FAKE)
    assert [row[0] for row in rows] == list(comparison.MEASURE_KEYS)
    by_key = {key: (label, a, b) for key, label, a, b, _meaning in rows}
    assert by_key["dead_end_share"] == ("Dead ends", "9.4%", "15.8%")
    assert by_key["star_share"] == ("Star junctions (5+)", "0.6%", "0.0%")
    assert by_key["crossing_share"] == ("Crossings (4 streets)", "41.0%", "23.6%")
    assert by_key["right_angle_share"][1:] == ("82.0%", "76.0%")
    assert by_key["circuity"] == ("Circuity", "1.37", comparison.NOTHING)
    assert by_key["median_edge_length_m"][1:] == ("85.3 m", "80.7 m")
    assert by_key["median_block_area_m2"][1:] == ("7,600 m\u00b2", "12,346 m\u00b2")
    assert by_key["edges"][1:] == ("510", "1,286")
    assert by_key["mean_degree"][1:] == ("3.20", "3.01")
    assert by_key["orientation_order"][1:] == ("0.73", "0.61")

    distances = comparison.distance_rows(FAKE)
    assert [(key, label, text) for key, label, text, _meaning in distances] == [
        ("degree", "Degree", "0.128"), ("edge_length", "Edge length", "0.207"),
        ("orientation", "Orientation", "0.104"), ("block_area", "Block area", "0.410"),
        ("mean", "Mean", "0.212"), ("junction_angle", "Junction angles", "0.125")]


def test_summary_of_a_made_up_result():
    line = comparison.summary("grown", "town", FAKE)
    assert line == ("Compared grown with town: mean distance 0.21 (degree 0.13, edge length 0.21, orientation 0.10, "
                    "block area 0.41); junction angles 0.12; dead ends 9.4% / 15.8%, degree 2 6.9% / 3.2%, "
                    "star junctions 0.6% / 0.0%, crossings 41.0% / 23.6%, right angles 82.0% / 76.0%, through streets 97.0% / 95.0%; "
                    "circuity 1.37 / \u2013")


def test_a_member_the_tables_do_not_know_is_shown_last():
    result = json.loads(json.dumps(FAKE))
    result["a"]["new_share"], result["b"]["new_share"] = 0.5, 0.25
    result["distances"]["new_distance"] = 0.3
    rows = comparison.measure_rows(result)
    assert rows[-1][:4] == ("new_share", "New share", "0.50", "0.25")
    assert comparison.distance_rows(result)[-1][:3] == ("new_distance", "New distance", "0.300")
    # A member only one side has: the other shows nothing.
    del result["b"]["new_share"]
    assert comparison.measure_rows(result)[-1][2:4] == ("0.50", comparison.NOTHING)


def test_stored_text_round_trip():
    text = comparison.stored_text(FAKE)
    assert comparison.read_stored(text) == FAKE
    for bad in ("", "not json", "[1, 2]", json.dumps({"a": {}, "b": {}})):
        assert comparison.read_stored(bad) is None


# --- the library's own result ------------------------------------------------------------

def small_grid(ggg, n, spacing, turn=0.0):
    """An n x n street grid, ``spacing`` metres apart, turned by ``turn`` radians."""
    xs, ys = np.meshgrid(np.arange(n) * spacing, np.arange(n) * spacing)
    points = np.column_stack((xs.ravel(), ys.ravel()))
    c, s = np.cos(turn), np.sin(turn)
    points = points @ np.array([[c, s], [-s, c]])
    edges = [(i * n + j, i * n + j + 1) for i in range(n) for j in range(n - 1)]
    edges += [(i * n + j, (i + 1) * n + j) for i in range(n - 1) for j in range(n)]
    return ggg.Graph.from_arrays(np.asarray(points, dtype=np.float64), np.asarray(edges, dtype=np.int64))


def test_the_tables_know_every_member_the_library_returns(ggg):
    result = ggg.compare(small_grid(ggg, 4, 100.0), small_grid(ggg, 5, 80.0, 0.3))
    assert set(result) == {"a", "b", "distances"}
    # A new member of the library fails here until the tables (and their order) know it.
    assert sorted(result["distances"]) == sorted(comparison.DISTANCE_KEYS)
    assert sorted(result["a"]) == sorted(comparison.MEASURE_KEYS)
    assert sorted(result["b"]) == sorted(comparison.MEASURE_KEYS)
    assert len(set(comparison.MEASURE_KEYS)) == len(comparison.MEASURE_KEYS)
    assert set(comparison.MEAN_OF) < set(comparison.DISTANCE_KEYS)


def test_rows_and_summary_of_a_real_comparison(ggg):
    a, b = small_grid(ggg, 4, 100.0), small_grid(ggg, 5, 80.0, 0.3)
    result = ggg.compare(a, b)
    rows = comparison.measure_rows(result)
    assert [row[0] for row in rows] == list(comparison.MEASURE_KEYS)
    by_key = {key: (a_text, b_text) for key, _label, a_text, b_text, _meaning in rows}
    assert by_key["vertices"] == ("16", "25") and by_key["edges"] == ("24", "40")
    assert by_key["blocks"] == ("9", "16")
    assert by_key["median_edge_length_m"] == ("100.0 m", "80.0 m")
    assert by_key["median_block_area_m2"] == ("10,000 m\u00b2", "6,400 m\u00b2")
    assert by_key["right_angle_share"] == tuple("{:.1f}%".format(100.0 * result[side]["right_angle_share"])
                                                for side in "ab")
    assert by_key["dead_end_share"] == ("0.0%", "0.0%")
    assert by_key["star_share"] == ("0.0%", "0.0%")
    # 4 x 4 vertices: 4 crossings of 12 junctions; 5 x 5: 9 of 21.
    assert by_key["crossing_share"] == ("33.3%", "42.9%")
    for key, _label, a_text, b_text, _meaning in rows:
        assert a_text == comparison.value_text(result["a"][key], dict((r[0], r[2]) for r in comparison.MEASURES)[key])
        assert b_text != comparison.NOTHING or result["b"][key] is None
    distances = {key: text for key, _label, text, _meaning in comparison.distance_rows(result)}
    assert distances == {key: "{:.3f}".format(value) for key, value in result["distances"].items()}
    line = comparison.summary("A", "B", result)
    assert line.startswith("Compared A with B: mean distance {:.2f} (degree {:.2f}, edge length {:.2f}".format(
        result["distances"]["mean"], result["distances"]["degree"], result["distances"]["edge_length"]))
    assert "right angles {} / {};".format(*by_key["right_angle_share"]) not in line
    assert "right angles {} / {}, through".format(*by_key["right_angle_share"]) in line
    assert "circuity {:.2f} / {:.2f}".format(result["a"]["circuity"], result["b"]["circuity"]) in line
    assert comparison.read_stored(comparison.stored_text(result)) == result


def test_the_same_network_is_at_distance_zero(ggg):
    if not SAMPLE_CITY.is_file():
        pytest.skip("{} is absent".format(SAMPLE_CITY))
    town = ggg.read_graph(str(SAMPLE_CITY))
    result = ggg.compare(town, town)
    assert all(text == "0.000" for _key, _label, text, _meaning in comparison.distance_rows(result))
    assert all(a == b for _key, _label, a, b, _meaning in comparison.measure_rows(result))


# --- the words of docs/cli.md ------------------------------------------------------------

def cli_compare_table():
    """{member: (meaning, to a planner)} of the table of docs/cli.md's `ggg compare`."""
    text = (REPO / "docs" / "cli.md").read_text()
    section = text.split("## `ggg compare`", 1)[1].split("\n## ", 1)[0]
    members = {}
    for line in section.splitlines():
        cells = [cell.strip() for cell in line.strip().strip("|").split("|")]
        if len(cells) != 3 or not cells[0].startswith("`"):
            continue
        for name in re.findall(r"`([^`]+)`", cells[0]):
            members[name] = tuple(cell.replace("`", "") for cell in cells[1:])
    return members


def test_labels_say_what_the_cli_docs_say():
    members = cli_compare_table()
    ours = {"distances." + key: meaning for key, _label, _short, meaning in comparison.DISTANCES}
    ours.update({key: meaning for key, _label, _kind, _short, meaning in comparison.MEASURES})
    assert set(ours) == set(members)
    for name, meaning in ours.items():
        documented, to_a_planner = members[name]
        assert meaning == (to_a_planner or documented), name
