"""Edge polylines as flat arrays: (offsets (M+1,), points (P, 2)), as
``Graph.edge_geometry()`` gives them, and the segments of a surface mesh made from them."""

import numpy as np


def ramp(counts):
    """0..c-1 for each count c, concatenated (np.concatenate([np.arange(c) for c in counts]))."""
    counts = np.asarray(counts, dtype=np.int64)
    total = int(counts.sum())
    if total == 0:
        return np.zeros(0, dtype=np.int64)
    starts = np.cumsum(counts) - counts
    return np.arange(total, dtype=np.int64) - np.repeat(starts, counts)


def complete_polylines(offsets, points, positions, edges):
    """(offsets, points) of ``Graph.edge_geometry()`` form where every edge has a polyline
    of two points or more: one with fewer points becomes the straight segment between the
    edge's vertices (``positions``, ``edges``)."""
    offsets = np.asarray(offsets, dtype=np.int64)
    points = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    counts = np.diff(offsets)
    short = np.flatnonzero(counts < 2)
    if len(short) == 0:
        return offsets, points
    edges = np.asarray(edges, dtype=np.int64).reshape(-1, 2)
    positions = np.asarray(positions, dtype=np.float64).reshape(-1, 2)
    new_counts = counts.copy()
    new_counts[short] = 2
    new_offsets = np.zeros(len(counts) + 1, dtype=np.int64)
    np.cumsum(new_counts, out=new_offsets[1:])
    new_points = np.empty((new_offsets[-1], 2), dtype=np.float64)
    keep = counts >= 2
    src = np.repeat(offsets[:-1][keep], counts[keep]) + ramp(counts[keep])
    dst = np.repeat(new_offsets[:-1][keep], counts[keep]) + ramp(counts[keep])
    new_points[dst] = points[src]
    new_points[new_offsets[short]] = positions[edges[short, 0]]
    new_points[new_offsets[short] + 1] = positions[edges[short, 1]]
    return new_offsets, new_points


def polyline_segments(offsets, points, positions, edges):
    """Segments of the edge polylines.

    ``offsets`` (M+1,) and ``points`` (P, 2) are ``Graph.edge_geometry()``. A polyline with
    fewer than two points stands for the straight segment between the edge's vertices
    (``positions``, ``edges``); those end points are appended to the point array.
    Returns (points (P', 2), segments (S, 2) int32, owner (S,) int64: the edge of each segment).
    """
    offsets, points = complete_polylines(offsets, points, positions, edges)
    segment_counts = np.diff(offsets) - 1
    owner = np.repeat(np.arange(len(segment_counts), dtype=np.int64), segment_counts)
    start = np.repeat(offsets[:-1], segment_counts) + ramp(segment_counts)
    segments = np.stack((start, start + 1), axis=1).astype(np.int32)
    return points, segments, owner


def segment_polylines(points, segments, owner, edge_count):
    """The inverse of polyline_segments: (offsets (edge_count+1,) int64, points (P, 2)), the
    polyline of each edge from its segments (a chain, in order, as polyline_segments makes
    them). An edge without segments gets no points (it stands for the straight segment)."""
    points = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    segments = np.asarray(segments, dtype=np.int64).reshape(-1, 2)
    owner = np.asarray(owner, dtype=np.int64)
    valid = (owner >= 0) & (owner < edge_count)
    order = np.argsort(owner[valid], kind="stable")
    segments = segments[valid][order]
    owner = owner[valid][order]
    counts = np.bincount(owner, minlength=edge_count).astype(np.int64)
    point_counts = np.where(counts > 0, counts + 1, 0)
    offsets = np.zeros(edge_count + 1, dtype=np.int64)
    np.cumsum(point_counts, out=offsets[1:])
    out = np.empty((offsets[-1], 2), dtype=np.float64)
    first_segment = np.cumsum(counts) - counts
    has = counts > 0
    out[offsets[:-1][has]] = points[segments[first_segment[has], 0]]
    out[np.repeat(offsets[:-1], counts) + 1 + ramp(counts)] = points[segments[:, 1]]
    return offsets, out
