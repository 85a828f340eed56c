"""Vertex ids and edges of a road graph: checksums of what an analysis refers to, seeds,
the mesh edge of a vertex pair, which edges a derivation kept, and which vertices a
replacement removes."""

import zlib

import numpy as np


def topology_checksum(vertex_count, edges):
    """A checksum of what the vertex ids of an analysis refer to: the vertex count and the
    edges (moving vertices keeps it)."""
    edges = np.ascontiguousarray(edges, dtype=np.int64)
    return "{}:{}:{:08x}".format(vertex_count, len(edges), zlib.crc32(edges.tobytes()))


def positions_digest(positions):
    """A checksum of vertex positions (the transforms of an analysis depend on them)."""
    return "{:08x}".format(zlib.crc32(np.ascontiguousarray(positions, dtype=np.float64).tobytes()))


def seed_problem(edges, seed):
    """Why the vertices ``seed`` cannot be a seed (fewer than two, or the streets between
    them do not connect them), else None."""
    seed = np.unique(np.asarray(seed, dtype=np.int64))
    if len(seed) == 0:
        return "Select the vertices of a piece of the road graph (e.g. the corners of one block) in Edit Mode first"
    if len(seed) == 1:
        return "Only one vertex is selected: select at least two vertices joined by a street"
    edges = np.asarray(edges, dtype=np.int64).reshape(-1, 2)
    inside = np.isin(edges, seed).all(axis=1)
    induced = edges[inside]
    if len(induced) == 0:
        return "No street joins the {} selected vertices: select a connected piece of the road graph".format(len(seed))
    # A walk over the induced subgraph from one seed vertex must reach them all.
    neighbours = {int(v): [] for v in seed}
    for u, v in induced.tolist():
        neighbours[u].append(v)
        neighbours[v].append(u)
    start = int(seed[0])
    seen = {start}
    stack = [start]
    while stack:
        for w in neighbours[stack.pop()]:
            if w not in seen:
                seen.add(w)
                stack.append(w)
    if len(seen) != len(seed):
        return ("The {} selected vertices are not connected by streets ({} of them are apart from the rest): "
                "select a connected piece of the road graph".format(len(seed), len(seed) - len(seen)))
    return None


class EdgeLookup:
    """The mesh edge joining two vertices, for many pairs at once."""

    def __init__(self, edges, vertex_count):
        edges = np.asarray(edges, dtype=np.int64).reshape(-1, 2)
        self._n = max(int(vertex_count), 1)
        keys = edges.min(axis=1) * self._n + edges.max(axis=1)
        self._order = np.argsort(keys, kind="stable")
        self._keys = keys[self._order]

    def edge_ids(self, u, v):
        """Mesh edge of each pair (u[i], v[i]); raises KeyError when one is not an edge."""
        u = np.asarray(u, dtype=np.int64)
        v = np.asarray(v, dtype=np.int64)
        keys = np.minimum(u, v) * self._n + np.maximum(u, v)
        if len(self._keys) == 0:
            if keys.size:
                raise KeyError("the mesh has no edges")
            return np.zeros(keys.shape, dtype=np.int64)
        where = np.clip(np.searchsorted(self._keys, keys), 0, len(self._keys) - 1)
        if not np.all(self._keys[where] == keys):
            raise KeyError("a pattern edge is not an edge of the mesh")
        return self._order[where]

    def occurrence_edges(self, occurrences, pattern_edges):
        """(n, e) mesh edge ids of the induced edges of each occurrence: ``occurrences``
        (n, k) vertex ids, ``pattern_edges`` (e, 2) pattern vertex pairs."""
        occurrences = np.asarray(occurrences, dtype=np.int64).reshape(len(occurrences), -1)
        pattern_edges = np.asarray(pattern_edges, dtype=np.int64).reshape(-1, 2)
        u = occurrences[:, pattern_edges[:, 0]]
        v = occurrences[:, pattern_edges[:, 1]]
        return self.edge_ids(u, v).reshape(len(occurrences), len(pattern_edges))


def kept_edges(old_edges, source_vertex, new_edges):
    """For each edge of a derived graph, the edge of its input graph it is, else -1.

    ``source_vertex`` is the derivation's report entry (for each new vertex, the input vertex
    it is, -1 for a placed one). An edge is kept with both its vertices, in its direction,
    and a derivation never adds a second edge between two vertices: a new edge between two
    kept vertices that an input edge joins is that input edge (the first of them, as the
    derivation keeps only that one)."""
    old_edges = np.asarray(old_edges, dtype=np.int64).reshape(-1, 2)
    new_edges = np.asarray(new_edges, dtype=np.int64).reshape(-1, 2)
    source_vertex = np.asarray(source_vertex, dtype=np.int64)
    result = np.full(len(new_edges), -1, dtype=np.int64)
    if len(old_edges) == 0 or len(new_edges) == 0:
        return result
    n_old = int(old_edges.max()) + 1
    old_keys = old_edges.min(axis=1) * n_old + old_edges.max(axis=1)
    order = np.argsort(old_keys, kind="stable")
    sorted_keys = old_keys[order]
    u, v = source_vertex[new_edges[:, 0]], source_vertex[new_edges[:, 1]]
    both = (u >= 0) & (v >= 0) & (u < n_old) & (v < n_old)
    keys = np.where(both, np.minimum(u, v) * n_old + np.maximum(u, v), -1)
    where = np.clip(np.searchsorted(sorted_keys, keys), 0, len(sorted_keys) - 1)
    hit = both & (sorted_keys[where] == keys)
    result[hit] = order[where[hit]]
    return result


def replaced_vertices(vertex_count, edges, occurrences):
    """Which vertices ggg.replace_isogroup removes (bool, one per vertex) when it replaces
    ``occurrences`` ((n, k) vertex ids, pairwise without a shared vertex): the vertices of the
    occurrences that no street from outside their own occurrence reaches. A junction (a vertex
    of an occurrence with a street to a vertex that is not in the same occurrence) stays."""
    edges = np.asarray(edges, dtype=np.int64).reshape(-1, 2)
    occurrences = np.asarray(occurrences, dtype=np.int64)
    owner = np.full(int(vertex_count), -1, dtype=np.int64)
    for c, occurrence in enumerate(occurrences):
        owner[occurrence] = c
    a, b = owner[edges[:, 0]], owner[edges[:, 1]]
    own = (a >= 0) & (a == b)
    junction = np.zeros(int(vertex_count), dtype=bool)
    junction[edges[~own].ravel()] = True
    return (owner >= 0) & ~junction


def carried(values, source):
    """``values`` of the old elements for the new ones (``source``: old index or -1; zero
    for -1)."""
    out = np.zeros(len(source), dtype=values.dtype)
    kept = source >= 0
    out[kept] = values[source[kept]]
    return out
