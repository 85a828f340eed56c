"""Growing into a region with ggg.grow_region: the rules placed by hand (the graph's
nonterminals) that go first, which of them fitted, and the whole of Grow into Region without
Blender (``grow_into_region``, run in a worker thread)."""

import math

import numpy as np


def fitted(report):
    """For each rule placed by hand that ggg.grow_region was given (in order), whether it was
    placed: its report says what became of each ("placed", "outside", "crossing", ...); one
    that does not fit changes nothing."""
    return [outcome == "placed" for outcome in report["hand_placements"]]


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


class Grown:
    """What Grow into Region computed (``grow_into_region``): the ggg.grow_region
    ``report``, the mesh vertex ids of the placed rules that were grown (``used``), and,
    when something grew, the new graph ``result`` with each of its vertices' ids in the old
    graph (``source``, -1 for a new one); else ``result`` is None."""

    def __init__(self, report, used, result=None, source=None):
        self.report = report
        self.used = used
        self.result = result
        self.source = source


def grow_into_region(job, ggg, old, parsed, polygon, candidates, placements, seed, max_placements, max_vertices,
                     patience, roundabouts=True):
    """Grow into Region on the GraphColumns ``old`` (read from the road graph object) with the
    grammar ``parsed``, without Blender: the streets (the nonterminals left out) are the base,
    the ``placements`` of the nonterminals ``candidates`` that fit go first; a Grown.

    ``job`` is the core.jobs.StepsJob it runs in (its progress and cancelling); raises
    ggg.Error (ggg.Cancelled once the user cancelled)."""
    job.step(0.0, "reading the graph")
    graph = old.graph(ggg)
    # The streets grow; the nonterminals are left out (growth would take them for street
    # vertices), placed first when they are used.
    streets = old.symbols == 0
    base, base_ids, base_edge_ids = ggg.induced_subgraph(graph, streets)
    grown, report = ggg.grow_region(
        base, parsed, polygon, seed=seed, max_placements=max_placements, max_vertices=max_vertices,
        patience=patience, placements=placements, roundabouts=roundabouts, progress=job.stage(0.02, 0.95))
    used = [vertex for vertex, fit in zip(candidates, fitted(report)) if fit]
    if report["added_vertices"] == 0:
        return Grown(report, used)
    job.step(0.95, "joining the new streets to the graph")
    keep = np.ones(len(old.positions), dtype=bool)
    keep[np.asarray(used, dtype=np.int64)] = False
    result, source = ggg.with_grown(graph, keep, base_ids, base_edge_ids, grown)
    job.step(1.0, "done")
    return Grown(report, used, result, source)
