"""ggg.analyze and ggg.find_similar on a street grid: arrays in and out, errors, cancel."""
import numpy as np
import pytest

import ggg


def grid(n, spacing=100.0, angle=0.3):
    ij = np.array([(i, j) for j in range(n) for i in range(n)], float) * spacing
    c, s = np.cos(angle), np.sin(angle)
    positions = ij @ np.array([[c, s], [-s, c]])
    edges = []
    for j in range(n):
        for i in range(n):
            v = j * n + i
            if i + 1 < n:
                edges.append((v, v + 1))
            if j + 1 < n:
                edges.append((v, v + n))
    return ggg.Graph.from_arrays(positions, np.array(edges), (41.39, 2.16))


def squares(n):
    return {tuple(sorted((j * n + i, j * n + i + 1, (j + 1) * n + i, (j + 1) * n + i + 1)))
            for j in range(n - 1) for i in range(n - 1)}


def test_analyze_finds_every_square_block():
    n = 9
    a = ggg.analyze(grid(n), max_order=4)
    blocks = [iso for iso in a.isogroups if iso.order == 4 and iso.edge_count == 4]
    assert blocks, [repr(iso) for iso in a.isogroups]
    best = max(blocks, key=lambda iso: iso.frequency)
    occ = best.occurrences
    assert occ.dtype == np.int32 and occ.shape == (best.frequency, 4)
    assert {tuple(sorted(row)) for row in occ.tolist()} == squares(n)
    # The non-overlapping blocks share no vertex and there are (n-1)^2 / 4 of them at best.
    chosen = occ[best.non_overlapping]
    assert len(np.unique(chosen)) == chosen.size
    assert len(best.non_overlapping) == 16
    assert best.transforms.shape == (best.frequency, 4)
    assert best.pattern_positions.shape == (4, 2)
    gains = [iso.gain for iso in a.isogroups]
    assert gains == sorted(gains, reverse=True)


def test_find_similar_from_one_block():
    n = 7
    g = grid(n)
    iso = ggg.find_similar(g, [0, 1, n + 1, n])
    assert iso.occurrences[0].tolist() == [0, 1, n + 1, n]
    assert {tuple(sorted(row)) for row in iso.occurrences.tolist()} == squares(n)
    seeded = ggg.analyze(g, seed=np.array([0, 1, n + 1, n]), max_order=5)
    assert seeded.isogroups[0].frequency == (n - 1) ** 2


def test_bad_seeds_and_options_are_usage_errors():
    g = grid(4)
    with pytest.raises(ggg.UsageError, match="at least two"):
        ggg.find_similar(g, [3])
    with pytest.raises(ggg.UsageError, match="not connected"):
        ggg.find_similar(g, [0, 15])
    with pytest.raises(ggg.UsageError, match="not in the graph"):
        ggg.find_similar(g, [0, 99])
    with pytest.raises(ggg.UsageError, match="scale mode"):
        ggg.analyze(g, scale="huge")
    with pytest.raises(ggg.UsageError, match="grid"):
        ggg.analyze(g, grid=(0, 10))


def test_progress_and_cancel():
    g = grid(10)
    seen = []
    ggg.analyze(g, max_order=5, progress=lambda f, m: seen.append(f))
    assert seen and seen[-1] == 1.0 and seen == sorted(seen)
    with pytest.raises(ggg.Cancelled):
        ggg.analyze(g, max_order=5, progress=lambda f, m: f < 0.3)


def test_scale_modes_and_range():
    n = 6
    g = grid(n)
    seed = [0, 1, n + 1, n]
    # Every block of the grid has the seed's size: rigid and range agree with similarity.
    assert ggg.find_similar(g, seed, scale="rigid").frequency == (n - 1) ** 2
    assert ggg.find_similar(g, seed, scale="range", scale_range=(0.9, 1.1)).frequency == (n - 1) ** 2
    # Two square blocks, 100 m and 250 m, joined by a street.
    pos = np.array([[0, 0], [100, 0], [100, 100], [0, 100],
                    [400, 0], [650, 0], [650, 250], [400, 250]], float)
    edges = np.array([[0, 1], [1, 2], [2, 3], [0, 3], [4, 5], [5, 6], [6, 7], [4, 7], [1, 4]])
    two = ggg.Graph.from_arrays(pos, edges, (41.39, 2.16))
    assert ggg.find_similar(two, [0, 1, 2, 3]).frequency == 2
    assert ggg.find_similar(two, [0, 1, 2, 3], scale="rigid").frequency == 1
    assert ggg.find_similar(two, [0, 1, 2, 3], scale="range", scale_range=(0.8, 1.25)).frequency == 1
    assert ggg.find_similar(two, [0, 1, 2, 3], scale="range", scale_range=(0.5, 3.0)).frequency == 2
    with pytest.raises(ggg.UsageError):
        ggg.analyze(g, scale="range", scale_range=(2.0, 1.0))


def test_the_report_is_what_the_command_line_prints():
    """ggg.Analysis.report and `ggg analyze` give one report: the same fields and figures."""
    import json
    import os
    import subprocess
    from pathlib import Path
    cli = os.environ.get("GGG_CLI")
    if not cli:
        pytest.skip("GGG_CLI (the ggg command) is not set: run through ctest")
    sample = Path(__file__).resolve().parents[3] / "samples" / "sample_city.osm"
    graph = ggg.read_graph(str(sample))
    report = ggg.analyze(graph, max_order=5).report(graph, top=3, occurrence_osm_nodes=True, orders=True)
    printed = json.loads(subprocess.run([cli, "analyze", str(sample), "--max-order", "5", "--top", "3", "--occurrences",
                                         "--stats"], capture_output=True, text=True, check=True).stdout)
    for timing in ("seconds", "import_seconds", "peak_memory_mb"):
        printed.pop(timing)
    assert len(report["isogroups"]) == 3
    assert all(len(ids) == iso["order"] for iso in report["isogroups"] for ids in iso["occurrence_osm_nodes"])
    assert report["orders"][0]["order"] >= 2
    assert report == printed
