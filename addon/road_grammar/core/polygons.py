"""Polygons seen from above: the closed loops of an outline's edges, areas and
point-in-polygon (the region of Grow into Region and Stitch Cities)."""

import numpy as np


class RegionError(Exception):
    """The object cannot be a region; the message says why."""


def closed_loops(edges, name="the region"):
    """The closed loops of ``edges`` ((M, 2) vertex ids, every vertex on exactly two of
    them): a list of vertex id arrays in the order of the loop. Raises RegionError for open
    ends and branches."""
    edges = np.asarray(edges, dtype=np.int64).reshape(-1, 2)
    edges = edges[edges[:, 0] != edges[:, 1]]
    if len(edges) == 0:
        raise RegionError("{} has no edges".format(name))
    degree = np.bincount(edges.ravel())
    used = np.flatnonzero(degree)
    open_ends = int(np.count_nonzero(degree[used] == 1))
    if open_ends:
        raise RegionError("The outline of {} is not closed: it has {} open end{} (make the curve cyclic, Alt+C, or "
                          "close the loop of edges)".format(name, open_ends, "" if open_ends == 1 else "s"))
    if degree.max() > 2:
        raise RegionError("The outline of {} branches: a vertex is on {} of its edges; a region is one closed "
                          "loop".format(name, int(degree.max())))
    neighbours = {}
    for u, v in edges.tolist():
        neighbours.setdefault(u, []).append(v)
        neighbours.setdefault(v, []).append(u)
    seen = set()
    loops = []
    for start in used.tolist():
        if start in seen:
            continue
        loop, previous, current = [start], -1, start
        seen.add(start)
        while True:
            a, b = neighbours[current]
            following = b if a == previous else a
            if following == start or following in seen:
                break
            loop.append(following)
            seen.add(following)
            previous, current = current, following
        loops.append(np.array(loop, dtype=np.int64))
    return loops


def clean(ring):
    """``ring`` without repeated consecutive corners (nor a last corner equal to the first)."""
    ring = np.asarray(ring, dtype=np.float64).reshape(-1, 2)
    if len(ring) == 0:
        return ring
    extent = float(np.ptp(ring, axis=0).max()) if len(ring) > 1 else 0.0
    step = np.linalg.norm(ring - np.roll(ring, 1, axis=0), axis=1)
    keep = step > 1e-9 * max(extent, 1.0)
    if not keep.any():
        return ring[:1]
    return ring[keep]


def signed_area(ring):
    """Shoelace area of a polygon (N, 2), positive when counter-clockwise."""
    ring = np.asarray(ring, dtype=np.float64).reshape(-1, 2)
    if len(ring) < 3:
        return 0.0
    x, y = ring[:, 0], ring[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


def contains(ring, points):
    """Whether each of ``points`` (K, 2) lies inside the polygon ``ring`` (even-odd rule,
    as the growth tests it)."""
    ring = np.asarray(ring, dtype=np.float64).reshape(-1, 2)
    points = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    inside = np.zeros(len(points), dtype=bool)
    a, b = ring, np.roll(ring, 1, axis=0)
    for (ax, ay), (bx, by) in zip(a, b):
        crosses = (ay > points[:, 1]) != (by > points[:, 1])
        with np.errstate(divide="ignore", invalid="ignore"):
            x = (bx - ax) * (points[:, 1] - ay) / (by - ay) + ax
        inside ^= crosses & (points[:, 0] < x)
    return inside
