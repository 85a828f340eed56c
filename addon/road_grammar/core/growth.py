"""Growing into a region with ggg.grow_region: the rules placed by hand (the graph's
nonterminals) that go first, which of them fit, and the progress of the growth."""

import math

import numpy as np


class ThrottledProgress:
    """The progress callback of ggg.grow_region (called on every try), passed on to another
    progress callback (e.g. the window manager's progress) only when the percentage or the
    message changes."""

    def __init__(self, progress):
        self._progress = progress
        self._last = None

    def __call__(self, fraction, message):
        key = (int(100.0 * float(fraction)), message)
        if key != self._last:
            self._last = key
            self._progress(fraction, message)
        return True


def placements_that_fit(ggg, base, parsed, polygon, placements):
    """For each of ``placements`` (the tuples of ggg.grow_region), whether it fits into the
    region (inside it, crossing no street, not crowding one) when they are placed in order.

    ggg.grow_region places the rules placed by hand first, in order, before anything else,
    without random choices; one that does not fit changes nothing. With patience=0 it stops
    right after them, so its report counts the ones that fitted, except that when none did
    and no street reaches the region it also seeds the region's middle (one try more than
    the placements: then none fitted)."""

    def fitted(prefix):
        _graph, report = ggg.grow_region(base, parsed, polygon, patience=0, placements=prefix)
        return 0 if report["attempts"] > len(prefix) else report["placements"]

    if not placements:
        return []
    if fitted(placements) == len(placements):
        return [True] * len(placements)
    result, before = [], 0
    for count in range(1, len(placements) + 1):
        now = fitted(placements[:count])
        result.append(now > before)
        before = now
    return result


def placed_rules(columns, parsed, chosen=None):
    """(vertex ids, ggg.grow_region placements) of the nonterminals of ``columns`` (a
    GraphColumns) whose symbol has a rule in the grammar ``parsed`` (and, with ``chosen``, a
    bool per vertex, that are chosen): (symbol, x, y, scale, degrees) from the vertex's
    frame, scale 0 (the rule's learned size) where the vertex has no frame of its own."""
    symbols = {int(rule["symbol"]) for rule in parsed.rules}
    vertices, placements = [], []
    for vertex in np.flatnonzero(columns.symbols).tolist():
        symbol = int(columns.symbols[vertex])
        if symbol not in symbols or (chosen is not None and not chosen[vertex]):
            continue
        a, b, x, y = (float(value) for value in columns.frames[vertex])
        scale = 0.0 if columns.frame_missing[vertex] else math.hypot(a, b)
        vertices.append(vertex)
        placements.append((symbol, x, y, scale, math.degrees(math.atan2(b, a))))
    return vertices, placements
