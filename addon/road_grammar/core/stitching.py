"""Stitch Cities without Blender (``stitch``, run in a worker thread): two road graphs'
columns joined side by side, the region between them grown with the grammar of each, the
main roads of both continued across it. operators.stitch reads the objects and writes the
result."""

import numpy as np

from .columns import joined
from .growth import fitted, placed_rules
from .names import RULE_GRAMMAR


class City:
    """One of the two cities of a stitch: its GraphColumns ``columns`` (read from its object),
    the name of its grammar Text (``text_name``, None without one) and that grammar
    (``parsed``), and ``notes``: for each of its vertices, the name of the grammar Text its
    nonterminal comes from (data.graph_edit.noted_grammars)."""

    def __init__(self, columns, text_name, parsed, notes):
        self.columns = columns
        self.text_name = text_name
        self.parsed = parsed
        self.notes = notes


class Stitched:
    """What ``stitch`` computed: the joined GraphColumns ``old`` (the first city's vertices
    and edges, then the second's), the growth ``reports`` (one per grammar), ``traced`` (the
    report of the tracing of the streets that reach the gap), ``hierarchy`` (of the main roads
    continued), the placed rules grown (``placed``) and left (``left``), the names of the
    grammars the nonterminals left come from (``names``) and, when something grew, the new
    graph ``result`` with each vertex's id in the joined graph (``source``, -1 for a new one),
    the vertices and streets added and how many new streets end on each city (``from_a``,
    ``from_b``); else ``result`` is None."""

    result = None
    source = None
    traced = None
    hierarchy = None
    added_vertices = 0
    added_edges = 0
    from_a = 0
    from_b = 0


def _placements(old, notes, text_name, parsed, use_placed_rules):
    """(vertex ids of the joined graph, placements) of the nonterminals that come from the
    grammar ``text_name`` and have a rule in it (with Use Placed Rules)."""
    if not use_placed_rules or parsed is None:
        return [], []
    return placed_rules(old, parsed, [note == text_name for note in notes])


def stitch(job, ggg, first, second, matrix, polygon, seed, share, max_placements, max_vertices, patience,
           use_placed_rules, roundabouts=True):
    """Stitch the City ``second`` (brought into ``first``'s frame by the 4x4 ``matrix``) to the
    City ``first`` across the region ``polygon``; a Stitched.

    The rules placed by hand go first, each with its own grammar; the streets of both cities
    that reach the gap are traced on into it; then the first city's grammar grows (seed; its
    ``share`` of what it would place alone when the second has a grammar), the second's
    grows what is left (seed + 1), and the main roads are continued once over both growths.
    ``job`` is the core.jobs.StepsJob it runs in (its progress and cancelling); raises
    ggg.Error (ggg.Cancelled once the user cancelled)."""
    job.step(0.0, "joining the two graphs")
    out = Stitched()
    n_a, n_b = len(first.columns.positions), len(second.columns.positions)
    text_a, parsed_a = first.text_name, first.parsed
    text_b, parsed_b = second.text_name, second.parsed
    notes = list(first.notes) + list(second.notes)
    old = joined(ggg, first.columns, second.columns, matrix)
    names = sorted({note for note, symbol in zip(notes, old.symbols.tolist()) if note and symbol > 0})
    if names or RULE_GRAMMAR in old.point_attributes:
        # The notes, renumbered for the joined graph's list of grammar names.
        old.point_attributes[RULE_GRAMMAR] = ('INT', np.array(
            [names.index(note) + 1 if note and symbol > 0 else 0
             for note, symbol in zip(notes, old.symbols.tolist())], dtype=np.int64))
    out.old, out.names = old, names

    passes = [(text_a, parsed_a, seed, parsed_b is not None and share < 1.0, (0.3, 0.6))]
    if parsed_b is not None:
        passes.append((text_b, parsed_b, seed + 1, False, (0.6, 0.9)))
    used, reports, first_placed = [], [], None
    left = 0
    graph = old.graph(ggg)
    streets = old.symbols == 0
    base, base_ids, base_edge_ids = ggg.induced_subgraph(graph, streets)
    grown = base
    # The rules placed by hand go first, each with its own grammar: the other city's before
    # anything grows (patience 0: only them), the active city's at the start of its growth.
    # (Each report says which of them fitted; one that does not changes nothing.)
    placed, candidates_of = {}, {}
    for text, parsed in ((text_b, parsed_b), (text_a, parsed_a)):
        if parsed is None or text in placed:
            continue
        candidates, placements = _placements(old, notes, text, parsed, use_placed_rules)
        placed[text], candidates_of[text] = placements, candidates
        if text != text_a and placements:
            grown, first_placed = ggg.grow_region(
                grown, parsed, polygon, seed=seed + 1, max_placements=len(placements),
                max_vertices=max_vertices, patience=0, placements=placements, continue_hierarchy=False,
                trace_streets=False, roundabouts=roundabouts, progress=job.stage(0.02, 0.05, text))
            fits = fitted(first_placed)
            used.extend(vertex for vertex, fit in zip(candidates, fits) if fit)
            left += fits.count(False)
            placed[text] = []
    # The streets of both cities that reach the gap are traced on into it first, after the
    # junctions around it (patience 0: no rule yet); the grammars' rules then fill what is
    # left.
    grown, out.traced = ggg.grow_region(
        grown, parsed_a, polygon, seed=seed, patience=0, max_vertices=max_vertices, continue_hierarchy=False,
        roundabouts=roundabouts, progress=job.stage(0.05, 0.3, "both cities"))
    for text, parsed, pass_seed, shared, (low, high) in passes:
        fitting = placed.pop(text, [])
        candidates = candidates_of.get(text, []) if fitting else []

        def grow(limit, low, high):
            return ggg.grow_region(
                grown, parsed, polygon, seed=pass_seed, max_placements=limit, max_vertices=max_vertices,
                patience=patience, placements=fitting, continue_hierarchy=False, trace_streets=False,
                roundabouts=roundabouts, progress=job.stage(low, high, text))

        middle = (low + high) / 2.0 if shared else high
        result = grow(max_placements, low, middle)
        if shared:
            # The active city's share of what it would place alone; the other's grammar
            # grows the rest of the region.
            alone = result[1]["placements"]
            limit = max(fitted(result[1]).count(True), int(round(share * alone)))
            if limit == 0:  # (share 0: the other city's grammar grows it all)
                result = (grown, {key: (False if isinstance(value, bool) else [] if isinstance(value, list) else 0)
                                  for key, value in result[1].items()})
            elif limit < alone:
                result = grow(limit, middle, high)
            if limit < alone:
                result[1]["stopped_by_budget"] = False  # (the share, not a budget)
                result[1]["share_of"] = alone
        grown, report = result
        reports.append(report)
        if fitting:
            fits = fitted(report)
            fits += [False] * (len(fitting) - len(fits))  # (none placed when the share left it no room)
            used.extend(vertex for vertex, fit in zip(candidates, fits) if fit)
            left += fits.count(False)
    # The main roads are continued once, over the streets of both growths: across the seam,
    # those of one city meet those of the other only through both.
    job.step(0.9, "continuing the main roads across the gap")
    grown, out.hierarchy = ggg.continue_hierarchy(grown, base.edge_count, region=polygon)
    if first_placed is not None:
        # (The other city's placed rules count as its rules.)
        reports[-1]["placements"] += first_placed["placements"]
        for key in ("added_vertices", "added_edges"):
            reports[-1][key] += first_placed[key]
    out.reports, out.placed, out.left = reports, len(used), left
    # (The main roads' connectors add streets and intersections after the growths.)
    out.added_vertices = grown.vertex_count - base.vertex_count
    if out.added_vertices == 0:
        return out
    job.step(0.95, "joining the new streets to the graph")
    keep = np.ones(len(old.positions), dtype=bool)
    keep[np.asarray(used, dtype=np.int64)] = False
    out.result, out.source = ggg.with_grown(graph, keep, base_ids, base_edge_ids, grown)
    # The new streets that end on a vertex of either city.
    edges = np.asarray(out.result.edges, dtype=np.int64).reshape(-1, 2)
    out.added_edges = grown.edge_count - base.edge_count
    ends = out.source[edges[len(edges) - out.added_edges:]]
    out.from_a = int(np.count_nonzero(((ends >= 0) & (ends < n_a)).any(axis=1)))
    out.from_b = int(np.count_nonzero(((ends >= n_a) & (ends < n_a + n_b)).any(axis=1)))
    job.step(1.0, "done")
    return out
