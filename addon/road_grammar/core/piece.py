"""The piece of street network that Replace (roads.replace_isogroup, paper Fig. 1) puts in
place of a pattern's occurrences, as it is stored (JSON)

    {"version": 1, "source": "grid (selection)",
     "positions": [[x, y], ...],              # metres, in the frame of the road graph it came from
     "edges": [[i, j], ...],                  # indices into positions
     "highway": ["residential", ...]}         # the road class of each edge (ggg.highway_classes())

The piece is drawn at any size and place: ggg.replace_isogroup centres it on the pattern and
scales it to the pattern's size, keeping its orientation in the graph's frame, then fits each
copy inside the occurrence it replaces.
"""

import json

import numpy as np

VERSION = 1
DEFAULT_CLASS = "residential"  # ggg.replace_isogroup's class of an edge without one


class PieceError(Exception):
    """No piece, or one that cannot be used; the message says why."""


class Piece:
    """A replacement piece: positions (N, 2) float64 in metres, edges (M, 2) int64 and the
    road class name of each edge."""

    def __init__(self, positions, edges, highway, source=""):
        self.positions = np.asarray(positions, dtype=np.float64).reshape(-1, 2)
        self.edges = np.asarray(edges, dtype=np.int64).reshape(-1, 2)
        self.highway = [str(name) for name in highway]
        self.source = str(source)
        if len(self.highway) != len(self.edges):
            raise PieceError("The piece has {} road classes for {} streets".format(len(self.highway),
                                                                                   len(self.edges)))

    @property
    def vertex_count(self):
        return len(self.positions)

    @property
    def edge_count(self):
        return len(self.edges)

    def size(self):
        """(width, height) in metres of the piece's bounding box."""
        if len(self.positions) == 0:
            return 0.0, 0.0
        extent = self.positions.max(axis=0) - self.positions.min(axis=0)
        return float(extent[0]), float(extent[1])

    def problem(self):
        """Why the piece cannot replace a pattern (no vertices, no streets, not finite, no
        extent), else None. Indices out of range are left to the library, which says so."""
        if self.vertex_count == 0:
            return "The piece has no vertices"
        if self.edge_count == 0:
            return "The piece has no streets (edges): a piece needs streets to join the streets around it"
        if not np.all(np.isfinite(self.positions)):
            return "The piece has vertices that are not finite"
        if max(self.size()) <= 0.0:
            return "The piece's {} vertices are all at one place: it has no size".format(self.vertex_count)
        return None

    def highway_codes(self, ggg):
        """The class code of each edge for ggg.replace_isogroup; raises PieceError for a
        name the library does not know."""
        codes = {name: code for code, name in enumerate(ggg.highway_classes())}
        unknown = sorted({name for name in self.highway if name not in codes})
        if unknown:
            raise PieceError("The piece has road classes the library does not know: {}".format(", ".join(unknown)))
        return np.array([codes[name] for name in self.highway], dtype=np.int64)

    def to_json(self):
        return json.dumps({"version": VERSION, "source": self.source, "positions": self.positions.tolist(),
                           "edges": self.edges.tolist(), "highway": self.highway})

    @classmethod
    def from_json(cls, text):
        try:
            data = json.loads(text)
            positions = np.asarray(data["positions"], dtype=np.float64)
            edges = np.asarray(data["edges"], dtype=np.int64)
            highway = data.get("highway")
            if highway is None:
                highway = [DEFAULT_CLASS] * len(edges)
            if positions.size and (positions.ndim != 2 or positions.shape[1] != 2):
                raise ValueError("positions must be [x, y] pairs")
            if edges.size and (edges.ndim != 2 or edges.shape[1] != 2):
                raise ValueError("edges must be [i, j] pairs")
            if not isinstance(highway, list):
                raise ValueError("highway must be a list of class names")
            return cls(positions, edges, highway, data.get("source", ""))
        except (ValueError, TypeError, KeyError, AttributeError) as ex:
            raise PieceError("The stored piece cannot be read ({}: {}); store a piece again".format(
                type(ex).__name__, ex)) from ex


def class_names(ggg, codes, count):
    """Class names of ``count`` edges from INT codes (None: the default class), clipped to
    the library's classes as a road graph's are (analysis.MeshTopology.graph)."""
    if codes is None:
        return [DEFAULT_CLASS] * count
    names = list(ggg.highway_classes())
    return [names[code] for code in np.clip(np.asarray(codes, dtype=np.int64), 0, len(names) - 1).tolist()]
