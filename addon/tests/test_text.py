"""core.text: counts and messages."""

import numpy as np

from road_grammar.core import text


def test_plural():
    assert text.plural(1, "rule") == "1 rule"
    assert text.plural(0, "rule") == "0 rules"
    assert text.plural(3, "vertex") == "3 vertices"
    assert text.plural(2, "placed vertex") == "2 placed vertices"
    assert text.plural(1200, "street") == "1,200 streets"
    assert text.plural(np.int64(2), "edge") == "2 edges"


def test_tries_and_rejections():
    assert text.tries(1) == "1 try" and text.tries(2500) == "2,500 tries"
    report = {"rejected_outside": 12, "rejected_crossing": 3, "rejected_crowded": 4000}
    assert text.rejections(report) == "12 outside, 3 crossing, 4,000 crowded"
    report.update(rejected_off_grid=2, rejected_small_block=1)
    assert text.rejections(report) == "12 outside, 3 crossing, 4,000 crowded, 2 off the grid, 1 closing a sliver"


def test_compact():
    assert [text.compact(n) for n in (950, 9999, 12_345, 456_000, 1_234_567)] == \
        ["950", "9999", "12.3k", "456k", "1.2M"]


def test_wrap():
    assert text.wrap("") == []
    assert text.wrap("one two three", width=7) == ["one two", "three"]
    assert text.wrap("a verylongword b", width=4) == ["a", "verylongword", "b"]
    lines = text.wrap("The native module 'ggg' was not found (looked in /a/b/c and on sys.path).", width=28)
    assert all(len(line) <= 28 for line in lines) and " ".join(lines).startswith("The native module")


def test_learned_summary():
    stats = {"mode": "paper", "rules": 3, "levels": 2, "instances": 40, "axiom": {"vertices": 10, "edges": 1},
             "bytes": {"original": 5000, "encoded": 1200},
             "roundtrip": {"edges_equal": True, "max_displacement_m": 0.25, "mean_displacement_m": 0.01}}
    line = text.learned_summary("town", stats, 1.5)
    assert line.startswith("Learned a grammar of town (paper) in 1.50 s: 3 rules, 2 levels, 40 instances")
    assert "axiom 10 vertices, 1 edge" in line and "5,000 -> 1,200 bytes" in line and "same edges" in line
    stats["roundtrip"] = {"edges_equal": False, "missing_edges": 2, "extra_edges": 1}
    assert "2 edges missing, 1 extra" in text.learned_summary("town", stats, 1.0)


def test_size_lines():
    stats = {"bytes": {"original": 5000, "encoded": 4000, "original_cbor": 2500, "encoded_cbor": 1900},
             "per_level": [{"level": 1, "rules": 3, "bytes_saved": 12_345}, {"level": 2, "rules": 1, "bytes_saved": -40}]}
    assert text.size_lines(stats) == ["JSON: 5,000 \u2192 4,000 bytes (0.80\u00d7)", "CBOR: 2,500 \u2192 1,900 bytes (0.76\u00d7)",
                                      "Pass 1: 3 rules, saves 12.3k bytes", "Pass 2: 1 rule, costs 40 bytes"]
    assert text.size_lines({}) == []
    stats["bytes"]["parts_cbor"] = {"original": {"positions": 1400, "edges": 1050, "header": 50},
                                    "encoded": {"axiom_positions": 970, "links": 380, "residuals": 0, "header": 350,
                                                "rules": 200}}
    assert text.size_lines(stats)[2:4] == ["Graph CBOR: positions 1400, edges 1050, header 50",
                                           "Grammar CBOR: axiom positions 970, links 380, header 350, rules 200"]
