#!/usr/bin/env python3
"""Draws the figures of docs/learning.md from grammars learned by the ggg module.

    /usr/bin/python3 scripts/make_learning_figures.py [--out-dir docs/figures] [--osm FILE]

Needs numpy and matplotlib (Debian: python3-numpy, python3-matplotlib) and the built Python
module `ggg` ($GGG_MODULE_DIR, else build/python of this repository). The input is the
bundled sample town unless --osm names another file (the docs use Paris Marais from
../shared/osm, (c) OpenStreetMap contributors, ODbL).

Writes
  learning_levels.png      the streets and the graph encoded to each level, coloured by rule
                           (the paper's Figure 13)
  learning_complete.png    the same for complete encoding (--complete), down to one vertex
  learning_grid.png        paper mode decoded with a 12 x 10 and a 24 x 20 expansion grid,
                           and lossless mode, against the input (the paper's Figure 11)
"""
import argparse
import os
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, os.environ.get("GGG_MODULE_DIR") or str(REPO / "build" / "python"))

try:
    import ggg
except ImportError as e:
    sys.exit(f"error: cannot import the ggg module ({e}); build it first, or set GGG_MODULE_DIR")
try:
    import numpy as np
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import LineCollection
except ImportError as e:
    sys.exit(f"error: {e}; install numpy and matplotlib (Debian: apt-get install python3-numpy python3-matplotlib)")

PNG_METADATA = {"Software": None}
STREET = "#b8b8b8"
CREDIT = "Map data (c) OpenStreetMap contributors, ODbL"


def plural(n, word):
    return "{} {}{}".format(n, word, "" if n == 1 else "s")


def rule_colours(count):
    cmap = plt.get_cmap("tab20")
    return [cmap(i % 20) for i in range(count + 1)]


def draw_graph(ax, graph, colours=None, lw=0.8, zorder=1):
    p = graph.positions
    segments = p[graph.edges]
    ax.add_collection(LineCollection(segments, colors=colours if colours is not None else "#222222", linewidths=lw, zorder=zorder))


def frame_axes(ax, graph, title):
    p = graph.positions
    pad = 0.03 * max(np.ptp(p[:, 0]), np.ptp(p[:, 1]))
    ax.set_xlim(p[:, 0].min() - pad, p[:, 0].max() + pad)
    ax.set_ylim(p[:, 1].min() - pad, p[:, 1].max() + pad)
    ax.set_aspect("equal")
    ax.set_xticks([])
    ax.set_yticks([])
    ax.set_title(title, fontsize=10)


def levels_figure(graph, out, credit, complete=False):
    grammar, stats = ggg.learn(graph, complete=complete)
    streets = ggg.decode(grammar)
    colours = rule_colours(len(grammar.symbols))
    levels = list(range(0, grammar.levels + 1))
    if len(levels) > 4:  # the streets, the first level, one between and the axiom
        levels = [0, 1, (grammar.levels + 1) // 2, grammar.levels]
    fig, axes = plt.subplots(1, len(levels), figsize=(5 * len(levels), 5.2))
    axes = np.atleast_1d(axes)
    for ax, level in zip(axes, levels):
        encoded, image = ggg.encoded_graph(grammar, level)
        symbols = encoded.vertex_symbols
        # A street is coloured by the rule standing for it at this level (both ends under
        # one nonterminal); the others stay grey, and the level's own edges are drawn over.
        a, b = image[streets.edges[:, 0]], image[streets.edges[:, 1]]
        inside = (a == b) & (symbols[a] > 0)
        street_colours = [colours[symbols[x]] if ok else STREET for x, ok in zip(a, inside)]
        draw_graph(ax, streets, street_colours, lw=1.2)
        if level > 0:
            draw_graph(ax, encoded, "#222222", lw=0.5, zorder=2)
            nt = np.flatnonzero(symbols)
            ax.scatter(*encoded.positions[nt].T, s=9, c=[colours[s] for s in symbols[nt]], edgecolors="#222222",
                       linewidths=0.4, zorder=3)
        title = "streets ({} vertices)".format(streets.vertex_count) if level == 0 else \
            "level {}: {}, {}".format(level, plural(encoded.vertex_count, "vertex").replace("vertexs", "vertices"),
                                      plural(int((symbols > 0).sum()), "nonterminal"))
        frame_axes(ax, streets, title)
    axiom = stats["axiom"]["vertices"]
    fig.suptitle("{} rules, {} level{} of hierarchy ({} mode{}), axiom of {} vert{}".format(
        stats["rules"], stats["levels"], "" if stats["levels"] == 1 else "s", stats["mode"],
        ", complete" if complete else "", axiom, "ex" if axiom == 1 else "ices"), fontsize=11)
    if credit:
        fig.text(0.99, 0.01, credit, ha="right", fontsize=7, color="#666666")
    fig.tight_layout()
    fig.savefig(out, dpi=110, metadata=PNG_METADATA)
    plt.close(fig)


def grid_figure(graph, out, credit):
    runs = [("paper, grid 12 x 10", dict(grid=(12, 10))), ("paper, grid 24 x 20", dict(grid=(24, 20))),
            ("lossless", dict(lossless=True))]
    fig, axes = plt.subplots(1, len(runs), figsize=(5 * len(runs), 5.2))
    for ax, (name, options) in zip(axes, runs):
        grammar, stats = ggg.learn(graph, **options)
        decoded = ggg.decode(grammar)
        draw_graph(ax, graph, STREET, lw=2.0)
        draw_graph(ax, decoded, "#c0392b", lw=0.7, zorder=2)
        rt = stats["roundtrip"]
        frame_axes(ax, graph, "{}: mean error {:.2g} m, max {:.2g} m".format(name, rt["mean_displacement_m"], rt["max_displacement_m"]))
    fig.suptitle("decoded (red) over the input (grey)", fontsize=11)
    if credit:
        fig.text(0.99, 0.01, credit, ha="right", fontsize=7, color="#666666")
    fig.tight_layout()
    fig.savefig(out, dpi=110, metadata=PNG_METADATA)
    plt.close(fig)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--out-dir", default=str(REPO / "docs" / "figures"))
    parser.add_argument("--osm", help="input road graph (default: the bundled sample town)")
    args = parser.parse_args()
    path = args.osm or str(REPO / "samples" / "sample_city.osm")
    credit = CREDIT if args.osm else ""
    try:
        graph = ggg.read_graph(path, highways="all")
    except ggg.Error as e:
        sys.exit("error: {}".format(e))
    out = Path(args.out_dir)
    out.mkdir(parents=True, exist_ok=True)
    levels_figure(graph, out / "learning_levels.png", credit)
    levels_figure(graph, out / "learning_complete.png", credit, complete=True)
    grid_figure(graph, out / "learning_grid.png", credit)
    print("wrote {}, {} and {}".format(out / "learning_levels.png", out / "learning_complete.png", out / "learning_grid.png"))


if __name__ == "__main__":
    main()
