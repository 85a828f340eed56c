"""A camera path along a road graph: the shortest path between two vertices, or a seeded
tour that keeps to the major roads; smoothed, and keyframed frame by frame.

The path follows the edge polylines (the surface's shape points). It is resampled every
metre and smoothed with a Gaussian window (``smoothing_m``) so the camera swings through
intersections in arcs instead of turning on the spot; the camera then moves at constant
speed along the smoothed line and looks at the point ``look_ahead_m`` further on. Every
frame gets a key (linear interpolation), so what renders is exactly what was computed.
"""

import heapq
import math

import numpy as np


class PathError(Exception):
    """No path can be made; the message says why."""


class Network:
    """A road graph as arrays: positions (N, 2), edges (M, 2), polylines, ranks, lengths."""

    def __init__(self, positions, edges, offsets, points, ranks):
        self.positions = np.asarray(positions, dtype=np.float64).reshape(-1, 2)
        self.edges = np.asarray(edges, dtype=np.int64).reshape(-1, 2)
        self.offsets = np.asarray(offsets, dtype=np.int64)
        self.points = np.asarray(points, dtype=np.float64).reshape(-1, 2)
        self.ranks = np.asarray(ranks, dtype=np.int64)
        steps = np.hypot(*np.diff(self.points, axis=0).T) if len(self.points) > 1 else np.zeros(0)
        cumulative = np.concatenate(([0.0], np.cumsum(steps)))
        self.lengths = np.maximum(cumulative[self.offsets[1:] - 1] - cumulative[self.offsets[:-1]], 1e-6)
        n = len(self.positions)
        self.adjacency = [[] for _ in range(n)]
        for e, (u, v) in enumerate(self.edges.tolist()):
            self.adjacency[u].append((v, e))
            self.adjacency[v].append((u, e))

    def polyline(self, edge, forward):
        line = self.points[self.offsets[edge]:self.offsets[edge + 1]]
        return line if forward else line[::-1]

    def shortest_path(self, start, goal):
        """[(edge, forward), ...] of the shortest path (by length) from start to goal."""
        n = len(self.positions)
        for vertex in (start, goal):
            if not 0 <= vertex < n:
                raise PathError("vertex {} is not in the road graph ({} vertices)".format(vertex, n))
        if start == goal:
            raise PathError("the start and the end of the path are the same vertex ({})".format(start))
        distance = {start: 0.0}
        previous = {}
        queue = [(0.0, start)]
        while queue:
            d, u = heapq.heappop(queue)
            if u == goal:
                break
            if d > distance.get(u, math.inf):
                continue
            for v, e in self.adjacency[u]:
                nd = d + self.lengths[e]
                if nd < distance.get(v, math.inf):
                    distance[v] = nd
                    previous[v] = (u, e)
                    heapq.heappush(queue, (nd, v))
        if goal not in previous:
            raise PathError("no road connects vertex {} to vertex {} (they are in different parts of the "
                            "network)".format(start, goal))
        steps = []
        v = goal
        while v != start:
            u, e = previous[v]
            steps.append((e, int(self.edges[e, 0]) == u))
            v = u
        return steps[::-1]

    def tour(self, length_m, seed):
        """[(edge, forward), ...] of a walk of about ``length_m`` metres that prefers the most
        important roads, goes straight on where it can and avoids roads it has driven."""
        rng = np.random.default_rng(int(seed))
        m = len(self.edges)
        if m == 0:
            raise PathError("the road graph has no edges")
        # Major roads: the best ranks that together make a fifth of the network's length.
        order = np.argsort(self.ranks, kind="stable")
        cumulative = np.cumsum(self.lengths[order])
        cut_rank = self.ranks[order[min(np.searchsorted(cumulative, 0.2 * cumulative[-1]), m - 1)]]
        major = np.flatnonzero(self.ranks <= cut_rank)
        weights = self.lengths[major] / self.lengths[major].sum()
        edge = int(rng.choice(major, p=weights))
        forward = bool(rng.random() < 0.5)
        steps = [(edge, forward)]
        used = {edge: 1}
        total = self.lengths[edge]
        while total < length_m and len(steps) < 100000:
            line = self.polyline(edge, forward)
            here = int(self.edges[edge, 1] if forward else self.edges[edge, 0])
            heading = line[-1] - line[-2] if len(line) > 1 else np.zeros(2)
            best, best_score = None, math.inf
            for v, e in self.adjacency[here]:
                if e == edge and len(self.adjacency[here]) > 1:
                    continue
                nxt = self.polyline(e, int(self.edges[e, 0]) == here)
                out = nxt[1] - nxt[0] if len(nxt) > 1 else np.zeros(2)
                turn = _angle(heading, out)
                score = (2.0 * max(0, int(self.ranks[e]) - int(cut_rank)) + 1.5 * turn / math.pi
                         + 3.0 * used.get(e, 0) + 0.3 * rng.random())
                if score < best_score:
                    best, best_score = e, score
            if best is None:
                break
            edge, forward = best, int(self.edges[best, 0]) == here
            steps.append((edge, forward))
            used[edge] = used.get(edge, 0) + 1
            total += self.lengths[edge]
        return steps

    def path_points(self, steps):
        """The polyline of a path (consecutive duplicate points dropped)."""
        parts = [self.polyline(e, forward) for e, forward in steps]
        line = np.concatenate([parts[0]] + [p[1:] for p in parts[1:]]) if parts else np.zeros((0, 2))
        if len(line) > 1:
            keep = np.concatenate(([True], np.hypot(*np.diff(line, axis=0).T) > 1e-6))
            line = line[keep]
        return line


def _angle(a, b):
    na, nb = np.hypot(*a), np.hypot(*b)
    if na < 1e-9 or nb < 1e-9:
        return 0.0
    return math.acos(max(-1.0, min(1.0, float(np.dot(a, b) / (na * nb)))))


def resample(line, step):
    """Points every ``step`` metres along the polyline (its ends included)."""
    seg = np.hypot(*np.diff(line, axis=0).T)
    s = np.concatenate(([0.0], np.cumsum(seg)))
    count = max(2, int(math.ceil(s[-1] / step)) + 1)
    t = np.linspace(0.0, s[-1], count)
    return np.column_stack((np.interp(t, s, line[:, 0]), np.interp(t, s, line[:, 1])))


def smooth(line, sigma_points):
    """Gaussian smoothing of a resampled polyline; the ends stay where they are."""
    if sigma_points < 0.5 or len(line) < 3:
        return line
    radius = int(3 * sigma_points)
    kernel = np.exp(-0.5 * (np.arange(-radius, radius + 1) / sigma_points) ** 2)
    kernel /= kernel.sum()
    # Mirror the line through its end points, so the ends keep their direction.
    head = 2 * line[0] - line[1:radius + 1][::-1]
    tail = 2 * line[-1] - line[-radius - 1:-1][::-1]
    if len(head) < radius:  # a line shorter than the window
        head = np.concatenate([np.repeat(line[:1], radius - len(head), axis=0), head])
        tail = np.concatenate([tail, np.repeat(line[-1:], radius - len(tail), axis=0)])
    padded = np.concatenate([head, line, tail])
    out = np.column_stack([np.convolve(padded[:, k], kernel, mode="valid") for k in range(2)])
    out[0], out[-1] = line[0], line[-1]
    return out


def camera_track(line, frames, height, look_ahead, look_height, smoothing, step=1.0):
    """(locations (F, 3), targets (F, 3)) of a camera moving at constant speed along the
    smoothed ``line`` over ``frames`` frames."""
    if len(line) < 2:
        raise PathError("the path has no length")
    points = smooth(resample(line, step), smoothing / step)
    seg = np.hypot(*np.diff(points, axis=0).T)
    s = np.concatenate(([0.0], np.cumsum(seg)))
    total = s[-1]
    if total <= 0.0:
        raise PathError("the path has no length")
    at = np.linspace(0.0, total, frames)
    ahead = at + look_ahead
    end_direction = points[-1] - points[-2]
    end_direction /= max(np.hypot(*end_direction), 1e-9)

    def sample(where):
        inside = np.minimum(where, total)
        xy = np.column_stack((np.interp(inside, s, points[:, 0]), np.interp(inside, s, points[:, 1])))
        # Past the end: straight on.
        return xy + np.outer(np.maximum(where - total, 0.0), end_direction)

    locations = np.column_stack((sample(at), np.full(frames, height)))
    targets = np.column_stack((sample(ahead), np.full(frames, look_height)))
    return locations, targets, total


def view_directions(locations, targets):
    d = np.asarray(targets) - np.asarray(locations)
    return d / np.linalg.norm(d, axis=1, keepdims=True)


def max_turn_per_frame(locations, targets):
    """Largest angle (radians) between the view directions of consecutive frames."""
    d = view_directions(locations, targets)
    cos = np.clip(np.sum(d[1:] * d[:-1], axis=1), -1.0, 1.0)
    return float(np.max(np.arccos(cos))) if len(cos) else 0.0
