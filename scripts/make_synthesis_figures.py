#!/usr/bin/env python3
"""Draws the synthesis figures of docs/synthesis.md with the ggg module.

    /usr/bin/python3 scripts/make_synthesis_figures.py [--out-dir docs/figures]

Needs numpy and matplotlib (Debian: python3-numpy, python3-matplotlib), the built module `ggg`
($GGG_MODULE_DIR, else build/python) and ../shared/osm beside the project (the extracts are
(c) OpenStreetMap contributors, ODbL).

Writes
  synthesis_replacement.png  the most frequent blocks of Barcelona's Eixample replaced by a round
                             plaza (the paper's Figure 1)
  synthesis_stitch.png       Barcelona's Eixample and the Marais in Paris side by side, and the gap
                             between them grown with the grammar of each (the paper's Figure 18)
  synthesis_infill.png       the infill test (scripts/bench_infill.py): a hole cut out of three
                             cities, its real streets beside the ones grown back (seed 1)
  synthesis_beside.png       a district drawn beside Washington and beside Barcelona's Eixample,
                             where no street of the city reaches, grown from the street laid to it
"""
import argparse
import os
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, os.environ.get("GGG_MODULE_DIR") or str(REPO / "build" / "python"))
OSM = REPO.parent / "shared" / "osm"
CREDIT = "Map data (c) OpenStreetMap contributors, ODbL"
PNG_METADATA = {"Software": None}

try:
    import ggg
    import numpy as np
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import LineCollection

    sys.path.insert(0, str(REPO / "scripts"))
    import bench_infill  # the knife cut of the infill test
except ImportError as e:
    sys.exit(f"error: {e}; build the ggg module and install python3-numpy and python3-matplotlib")


def draw(ax, graph, first_edge=0, last_edge=None, colour="#222222", lw=0.8):
    edges = graph.edges[first_edge:last_edge]
    ax.add_collection(LineCollection(graph.positions[edges], colors=colour, linewidths=lw))


def draw_lines(ax, graph, first_edge=0, last_edge=None, colour="#222222", lw=0.8):
    """The edges' polylines (curved streets drawn curved)."""
    offsets, points = graph.edge_geometry()
    last = graph.edge_count if last_edge is None else last_edge
    lines = [points[offsets[e]:offsets[e + 1]] for e in range(first_edge, last)]
    ax.add_collection(LineCollection(lines, colors=colour, linewidths=lw))


def frame(ax, lo, hi, title):
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_aspect("equal")
    ax.set_xticks([])
    ax.set_yticks([])
    ax.set_title(title, fontsize=10)


def replacement_figure(out):
    city = ggg.read_graph(str(OSM / "barcelona_eixample.osm"), highways="all")
    analysis = ggg.analyze(city, max_order=8)
    blocks = [iso for iso in analysis.isogroups if iso.edge_count == iso.order >= 4]
    block = max(blocks, key=lambda iso: len(iso.non_overlapping))
    n = 16
    angles = np.linspace(0, 2 * np.pi, n, endpoint=False)
    ring = np.c_[np.cos(angles), np.sin(angles)]
    plaza = np.vstack([ring, 0.45 * ring[::4]])
    edges = [(i, (i + 1) % n) for i in range(n)] + [(n + j, (n + j + 1) % 4 + n) for j in range(4)] + \
            [(4 * j, n + j) for j in range(4)]
    replaced, report = ggg.replace_isogroup(city, block, plaza, np.array(edges))
    centre = np.median(city.positions, axis=0)
    lo, hi = centre - 700, centre + 700
    fig, axes = plt.subplots(1, 2, figsize=(12, 6.4))
    draw(axes[0], city)
    occ = block.occurrences[block.non_overlapping]
    for o in occ:
        ring_xy = city.positions[o]
        axes[0].fill(*ring_xy[np.argsort(np.arctan2(*(ring_xy - ring_xy.mean(0)).T[::-1]))].T, color="#f4a261", alpha=0.6, lw=0)
    frame(axes[0], lo, hi, "the most frequent block ({} of {} copies chosen)".format(len(occ), block.frequency))
    kept = replaced.edge_count - 0
    draw(axes[1], replaced)
    frame(axes[1], lo, hi, "each replaced by a plaza, joined to the junctions around ({} streets)".format(report["joined_streets"]))
    fig.text(0.99, 0.01, CREDIT, ha="right", fontsize=7, color="#666666")
    fig.tight_layout()
    fig.savefig(out, dpi=110, metadata=PNG_METADATA)
    plt.close(fig)


def stitch_figure(out):
    st = bench_infill.stitch(seed=1)
    west, both, step1, step2, step3 = st["west"], st["both"], st["step1"], st["step2"], st["step3"]
    facing, reached, r1, r2, hierarchy = st["facing"], st["reached"], st["report_west"], st["report_east"], st["hierarchy"]
    gap_west, gap_east = st["gap_west"], st["gap_east"]
    print("stitch: {} of the {} streets of either city that reach the gap continue into it".format(reached, len(facing)))
    ranks = np.array(ggg.highway_ranks())
    main_rank = ranks[ggg.highway_classes().index("tertiary")]
    fig, ax = plt.subplots(figsize=(13, 5.6))
    for first, last, colour in ((0, west.edge_count, "#c0392b"), (west.edge_count, both.edge_count, "#2471a3")):
        main = ranks[step3.edge_highway[first:last]] <= main_rank
        edges = step3.edges[first:last]
        ax.add_collection(LineCollection(step3.positions[edges[~main]], colors=colour, linewidths=0.8))
        ax.add_collection(LineCollection(step3.positions[edges[main]], colors=colour, linewidths=2.0))
    draw_lines(ax, step3, both.edge_count, step1.edge_count, "#e59866", lw=1.4)
    draw_lines(ax, step3, step1.edge_count, step2.edge_count, "#7fb3d5", lw=1.4)
    draw_lines(ax, step3, step2.edge_count, None, "#7fb3d5", lw=1.4)  # (second halves of split streets)
    changed = np.flatnonzero(step3.edge_highway[both.edge_count:step2.edge_count] !=
                             step2.edge_highway[both.edge_count:]) + both.edge_count
    connectors = np.arange(step2.edge_count, step3.edge_count)
    continued = np.concatenate([changed, connectors[ranks[step3.edge_highway[connectors]] <= main_rank]])
    ax.add_collection(LineCollection(step3.positions[step3.edges[continued]], colors="#1e8449", linewidths=2.6))
    for gap in (gap_west, gap_east):
        ax.plot(*np.vstack([gap, gap[:1]]).T, color="#999999", ls="--", lw=0.8)
    frame(ax, (-650, -650), (2650, 650), "Barcelona (red) and Paris (blue), the gap grown from the streets of each "
          "({} of {} continued, {} streets traced on, {} placed);\nmain roads thick, continued across the gap in green "
          "({} joined)".format(
              reached, len(facing), r1["traced_streets"] + r2["traced_streets"],
              "1 rule" if r1["placements"] + r2["placements"] == 1 else "{} rules".format(r1["placements"] + r2["placements"]),
              hierarchy["routes"] + hierarchy["connectors"]))
    fig.text(0.99, 0.01, CREDIT, ha="right", fontsize=7, color="#666666")
    fig.tight_layout()
    fig.savefig(out, dpi=110, metadata=PNG_METADATA)
    plt.close(fig)


def infill_figure(out):
    cities = [("paris_marais.osm.pbf", "the Marais, Paris"), ("columbus_oh.osm.pbf", "Columbus, Ohio"),
              ("monaco.osm.pbf", "Monaco")]
    fig, axes = plt.subplots(len(cities), 2, figsize=(11, 5.6 * len(cities)))
    for row, (name, title) in zip(axes, cities):
        graph = ggg.read_graph(str(OSM / name))
        hole = bench_infill.hole_of(graph)
        a, b = np.array(hole[:2]), np.array(hole[2:])
        side = hole[2] - hole[0]
        rest, _, _ = bench_infill.cut_hole(graph, hole)
        grammar, _ = ggg.learn(rest)
        corners = np.array([[a[0], a[1]], [b[0], a[1]], [b[0], b[1]], [a[0], b[1]]])
        grown, report = ggg.grow_region(rest, grammar, corners, seed=1)
        real = bench_infill.crosses_hole(graph, hole)
        view_lo, view_hi = a - 0.25 * side, b + 0.25 * side
        offsets, points = graph.edge_geometry()
        row[0].add_collection(LineCollection([points[offsets[e]:offsets[e + 1]] for e in np.flatnonzero(~real)],
                                             colors="#aaaaaa", linewidths=0.6))
        row[0].add_collection(LineCollection([points[offsets[e]:offsets[e + 1]] for e in np.flatnonzero(real)],
                                             colors="#222222", linewidths=0.9))
        draw_lines(row[1], grown, 0, rest.edge_count, "#aaaaaa", 0.6)
        draw_lines(row[1], grown, rest.edge_count, None, "#c0392b", 0.9)
        for ax in row:
            ax.plot(*np.vstack([corners, corners[:1]]).T, color="#2471a3", ls="--", lw=0.8)
        frame(row[0], view_lo, view_hi, "{}: the real streets of the hole ({:,})".format(title, int(real.sum())))
        frame(row[1], view_lo, view_hi, "grown back from the rest ({:,} streets; {:,} joined across, {:,} traced on)".format(
            grown.edge_count - rest.edge_count, report["traced_across"], report["traced_seeds"]))
    fig.text(0.99, 0.005, CREDIT, ha="right", fontsize=7, color="#666666")
    fig.tight_layout()
    fig.savefig(out, dpi=90, metadata=PNG_METADATA)
    plt.close(fig)


# Regions drawn beside a city, where none of its streets reaches (the test
# Growth.ADistrictBesideTheCityIsReachedByAStreetAndGrownAsDenseAsTheCity grows the same).
BESIDE = [("washington_dc.osm.pbf", "Washington, D.C.", (5733, -1100), (8000, 1100)),
          ("barcelona_eixample.osm", "Barcelona's Eixample", (1900, 100), (2900, 1100))]


def beside_figure(out):
    fig, axes = plt.subplots(1, len(BESIDE), figsize=(6.5 * len(BESIDE), 6.2))
    for ax, (name, title, lo, hi) in zip(axes, BESIDE):
        graph = ggg.read_graph(str(OSM / name))
        grammar, _ = ggg.learn(graph)
        corners = np.array([[lo[0], lo[1]], [hi[0], lo[1]], [hi[0], hi[1]], [lo[0], hi[1]]], dtype=float)
        grown, report = ggg.grow_region(graph, grammar, corners, seed=1)
        draw_lines(ax, grown, 0, graph.edge_count, "#aaaaaa", 0.6)
        draw_lines(ax, grown, graph.edge_count, None, "#c0392b", 0.9)
        ax.plot(*np.vstack([corners, corners[:1]]).T, color="#2471a3", ls="--", lw=0.8)
        side = max(hi[0] - lo[0], hi[1] - lo[1])
        frame(ax, (lo[0] - 0.9 * side, lo[1] - 0.25 * side), (hi[0] + 0.1 * side, hi[1] + 0.25 * side),
              "{}: a district beside it ({:,} new streets)".format(title, grown.edge_count - graph.edge_count))
    fig.text(0.99, 0.005, CREDIT, ha="right", fontsize=7, color="#666666")
    fig.tight_layout()
    fig.savefig(out, dpi=90, metadata=PNG_METADATA)
    plt.close(fig)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--out-dir", default=str(REPO / "docs" / "figures"))
    args = parser.parse_args()
    if not OSM.is_dir():
        sys.exit("error: {} is absent: the synthesis figures need the real extracts".format(OSM))
    out = Path(args.out_dir)
    out.mkdir(parents=True, exist_ok=True)
    replacement_figure(out / "synthesis_replacement.png")
    stitch_figure(out / "synthesis_stitch.png")
    infill_figure(out / "synthesis_infill.png")
    beside_figure(out / "synthesis_beside.png")
    print("wrote", *(out / f for f in ("synthesis_replacement.png", "synthesis_stitch.png", "synthesis_infill.png",
                                       "synthesis_beside.png")))


if __name__ == "__main__":
    main()
