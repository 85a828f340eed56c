#!/usr/bin/env python3
"""Draws the figures of docs/forward-modelling.md from derivations made by the ggg module.

    /usr/bin/python3 scripts/make_figures.py [--out-dir docs/figures]

Needs numpy and matplotlib (Debian: python3-numpy, python3-matplotlib) and the built Python
module `ggg`: it is looked for in $GGG_MODULE_DIR, then in build/python of this repository.

Writes
  sierpinski.png         samples/sierpinski.grammar.json derived for 1 to 5 steps
  relaxed-embedding.png  the cases of the paper's Figure 5: one rule, three frames of d
"""
import argparse
import json
import math
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
    from matplotlib.patches import Circle
except ImportError as e:
    sys.exit(f"error: {e}; install numpy and matplotlib (Debian: apt-get install python3-numpy python3-matplotlib)")

FRAME_COLOUR = "#d62728"
EDGE_COLOUR = "#222222"
EXPECTED_COLOUR = "#9a9a9a"
# PNG files without the matplotlib version, so that a rerun gives the same bytes.
PNG_METADATA = {"Software": None}


def draw_edges(ax, positions, edges, **style):
    for u, v in edges:
        ax.plot(*positions[[u, v]].T, color=style.get("color", EDGE_COLOUR), lw=style.get("lw", 1.0),
                ls=style.get("ls", "-"), solid_capstyle="round", zorder=style.get("zorder", 1))


def draw_frames(ax, positions, frames, length):
    """Red arrows along the x axis of each frame (a, b, tx, ty), `length` times the frame's scale."""
    a, b = frames[:, 0], frames[:, 1]
    ax.quiver(positions[:, 0], positions[:, 1], a * length, b * length, angles="xy", scale_units="xy", scale=1,
              color=FRAME_COLOUR, width=0.006, headwidth=4, headlength=5, headaxislength=4.5, zorder=3)


def sierpinski(out_dir: Path) -> Path:
    grammar = ggg.read_grammar(str(REPO / "samples" / "sierpinski.grammar.json"))
    steps = range(1, 6)
    fig, axes = plt.subplots(1, len(steps), figsize=(4.0 * len(steps), 4.4))
    for ax, n in zip(axes, steps):
        graph, report = ggg.derive(grammar, steps=n)
        if report["steps"] != n:
            raise SystemExit(f"error: the Sierpinski grammar stopped after {report['steps']} of {n} steps")
        positions = graph.positions
        draw_edges(ax, positions, graph.edges, lw=1.4 if n < 4 else 0.8)
        ax.scatter(*positions.T, s=14 if n < 4 else 3, color=EDGE_COLOUR, zorder=2)
        if n <= 2:
            nonterminal = graph.vertex_symbols != 0
            draw_frames(ax, positions[nonterminal], graph.vertex_frames[nonterminal], 0.3)
        places = len({(round(x, 6), round(y, 6)) for x, y in positions})
        ax.set_title(f"step {n}\n{report['vertices']} vertices, {report['edges']} edges, {places} places", fontsize=11)
        ax.set_aspect("equal")
        ax.set_xlim(-560, 560)
        ax.set_ylim(-350, 640)
        ax.axis("off")
    fig.tight_layout()
    path = out_dir / "sierpinski.png"
    fig.savefig(path, dpi=110, bbox_inches="tight", pad_inches=0.15, metadata=PNG_METADATA)
    plt.close(fig)
    return path


# The paper's Figure 5 with the geometry of the test Rule.Figure5RelaxedEmbeddingDependsOnTheFrame:
# d at the origin is rewritten into one terminal vertex whose embedding points lie one unit
# along +x and -x of d's frame; the host vertices a, b, c sit on the unit circle at -45, 45, 135 degrees.
FIGURE5_GRAMMAR = {
    "format": "ggg-grammar",
    "version": 1,
    "name": "figure-5",
    "symbols": ["D"],
    "rules": [{"symbol": "D", "vertices": [{"position": [0, 0], "embedding": [[1, 0], [-1, 0]]}], "edges": []}],
    "axiom": {"vertices": [{"position": [0, 0], "symbol": "D"}]},
}
FIGURE5_TOLERANCE = 0.1
HOST_NAMES = ["d", "a", "b", "c"]
HOST_ANGLES = [-45.0, 45.0, 135.0]


def host_graph(rotation_deg: float):
    points = [(0.0, 0.0)] + [(math.cos(math.radians(t)), math.sin(math.radians(t))) for t in HOST_ANGLES]
    r = math.radians(rotation_deg)
    frames = [[math.cos(r), math.sin(r), 0.0, 0.0]] + [[1.0, 0.0, x, y] for x, y in points[1:]]
    return ggg.Graph.from_arrays(np.array(points), np.array([[0, 1], [0, 2], [0, 3]]),
                                 vertex_symbols=np.array([1, 0, 0, 0]), vertex_frames=np.array(frames))


def label_vertices(ax, positions, names, colour=EDGE_COLOUR):
    for (x, y), name in zip(positions, names):
        norm = math.hypot(x, y)
        dx, dy = (x / norm, y / norm) if norm > 1e-9 else (-0.55, -0.55)
        ax.annotate(name, (x, y), xytext=(x + 0.2 * dx, y + 0.2 * dy), ha="center", va="center", fontsize=12,
                    color=colour, fontstyle="italic")


def setup_panel(ax, title):
    ax.set_title(title, fontsize=11)
    ax.set_aspect("equal")
    ax.set_xlim(-1.45, 1.45)
    ax.set_ylim(-1.45, 1.45)
    ax.axis("off")


def relaxed_embedding(out_dir: Path) -> Path:
    grammar = ggg.parse_grammar(json.dumps(FIGURE5_GRAMMAR), "figure-5")
    cases = [(0.0, "iii) d's frame: identity"), (45.0, "iv) d's frame: rotated +45°"), (-45.0, "v) d's frame: rotated −45°")]
    fig, axes = plt.subplots(1, 5, figsize=(17.5, 4.2))

    # i) the host: d (nonterminal D) joined to a, b, c; the red arrows are the three frames of d.
    host = host_graph(0.0)
    ax = axes[0]
    draw_edges(ax, host.positions, host.edges)
    ax.scatter(*host.positions[1:].T, s=30, color=EDGE_COLOUR, zorder=2)
    ax.scatter(0, 0, s=90, marker="s", color="white", edgecolor=EDGE_COLOUR, zorder=2)
    frames = np.array([[math.cos(math.radians(r)), math.sin(math.radians(r)), 0, 0] for r, _ in cases])
    draw_frames(ax, np.zeros((3, 2)), frames, 0.55)
    label_vertices(ax, host.positions, HOST_NAMES)
    setup_panel(ax, "i) host graph; frames of d")

    # ii) the rule D -> one terminal vertex with embedding points at (1, 0) and (-1, 0).
    ax = axes[1]
    expected = np.array([[1.0, 0.0], [-1.0, 0.0]])
    for p in expected:
        ax.plot([0, p[0]], [0, p[1]], color=EXPECTED_COLOUR, ls="--", lw=1.0, zorder=1)
    ax.scatter(*expected.T, s=60, facecolor="white", edgecolor=EXPECTED_COLOUR, zorder=2)
    ax.scatter(0, 0, s=30, color=EDGE_COLOUR, zorder=2)
    draw_frames(ax, np.zeros((1, 2)), np.array([[1.0, 0, 0, 0]]), 0.55)
    ax.text(0, -0.45, "x is a terminal vertex; its embedding\npoints (grey) lie at (1, 0) and (−1, 0)\nof the rule's frame (red arrow)",
            ha="center", va="top", fontsize=9, color="#555555")
    setup_panel(ax, "ii) rule  D → x")

    # iii)-v) the derivation for each frame of d, relaxed; the strict outcome is written below.
    for ax, (rotation, title) in zip(axes[2:], cases):
        graph, report = ggg.derive(grammar, host_graph(rotation), steps=1, tolerance=FIGURE5_TOLERANCE)
        _, strict = ggg.derive(grammar, host_graph(rotation), steps=1, tolerance=FIGURE5_TOLERANCE, strict=True)
        positions = graph.positions
        r = math.radians(rotation)
        turn = np.array([[math.cos(r), -math.sin(r)], [math.sin(r), math.cos(r)]])
        for p in expected @ turn.T:
            ax.plot([0, p[0]], [0, p[1]], color=EXPECTED_COLOUR, ls="--", lw=1.0, zorder=0)
            ax.add_patch(Circle(p, FIGURE5_TOLERANCE, facecolor="none", edgecolor=EXPECTED_COLOUR, lw=1.0, zorder=0))
        draw_edges(ax, positions, graph.edges, lw=2.0)
        ax.scatter(*positions.T, s=30, color=EDGE_COLOUR, zorder=2)
        draw_frames(ax, np.zeros((1, 2)), np.array([[math.cos(r), math.sin(r), 0, 0]]), 0.55)
        names = {(round(x, 6), round(y, 6)): n for (x, y), n in zip(host_graph(0.0).positions[1:], HOST_NAMES[1:])}
        label_vertices(ax, positions, [names.get((round(x, 6), round(y, 6)), "x") for x, y in positions])
        connected = sorted(names[(round(x, 6), round(y, 6))] for e in graph.edges for x, y in positions[e] if (x, y) != (0, 0))
        summary = f"relaxed: joins {', '.join(connected)}" if connected else "relaxed: no connection"
        summary += "\nstrict: " + ("applied" if strict["rewrites"] else "refused, d stays")
        ax.text(0, -1.3, summary, ha="center", va="top", fontsize=9, color="#333333")
        setup_panel(ax, title)
        if report["rewrites"] != 1:
            raise SystemExit(f"error: the rule was not applied for rotation {rotation}")
    fig.tight_layout()
    path = out_dir / "relaxed-embedding.png"
    fig.savefig(path, dpi=110, bbox_inches="tight", pad_inches=0.15, metadata=PNG_METADATA)
    plt.close(fig)
    return path


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out-dir", type=Path, default=REPO / "docs" / "figures",
                        help="where to write the PNG files (default: docs/figures of this repository)")
    args = parser.parse_args()
    args.out_dir.mkdir(parents=True, exist_ok=True)
    for make in (sierpinski, relaxed_embedding):
        print(make(args.out_dir))


if __name__ == "__main__":
    main()
