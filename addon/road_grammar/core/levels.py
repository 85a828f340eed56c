"""What a level of a learned grammar shows (paper Fig. 13): the streets the grammar decodes
to, the rule whose instance holds each street at that level and the nonterminal vertices of
the graph encoded to that level, with their colour slots (core.palette)."""

import numpy as np

from .palette import DIMMED_SLOT, NEUTRAL_SLOT, rule_slot


class DisplayError(Exception):
    """A level cannot be shown; the message says why."""


class LevelView:
    """The decoded streets of a learned grammar, the rule holding each street at ``level``
    and the nonterminal vertices of the graph encoded to that level."""

    def __init__(self, ggg, parsed, level, streets):
        self.level = int(level)
        self.positions = np.asarray(streets.positions, dtype=np.float64).reshape(-1, 2)
        self.edges = np.asarray(streets.edges, dtype=np.int64).reshape(-1, 2)
        self.highway = np.asarray(streets.edge_highway, dtype=np.int64)
        self.slot_of = {int(rule["symbol"]): rule_slot(index) for index, rule in enumerate(parsed.rules)}
        self.rule_names = {int(rule["symbol"]): rule["name"] for rule in parsed.rules}
        if self.level == 0:
            self.edge_rule = np.zeros(len(self.edges), dtype=np.int64)
            self.marker_positions = np.zeros((0, 2), dtype=np.float64)
            self.marker_rule = np.zeros(0, dtype=np.int64)
            return
        level_graph, image = ggg.encoded_graph(parsed, self.level)
        symbols = np.asarray(level_graph.vertex_symbols, dtype=np.int64)
        image = np.asarray(image, dtype=np.int64)
        if len(image) != len(self.positions):
            raise DisplayError("level {}: the image has {} vertices, the streets {}".format(
                self.level, len(image), len(self.positions)))
        a, b = image[self.edges[:, 0]], image[self.edges[:, 1]]
        own = (a == b) & (a >= 0)
        self.edge_rule = np.zeros(len(self.edges), dtype=np.int64)
        self.edge_rule[own] = symbols[a[own]]
        nonterminals = np.flatnonzero(symbols > 0)
        self.marker_positions = np.asarray(level_graph.positions, dtype=np.float64).reshape(-1, 2)[nonterminals]
        self.marker_rule = symbols[nonterminals]

    def slots(self, symbols, default):
        lookup = np.full(max(self.slot_of, default=0) + 1, default, dtype=np.int64)
        for symbol, slot in self.slot_of.items():
            lookup[symbol] = slot
        symbols = np.asarray(symbols, dtype=np.int64)
        inside = (symbols >= 0) & (symbols < len(lookup))
        return np.where(inside, lookup[np.clip(symbols, 0, len(lookup) - 1)], default)

    def edge_slots(self, highlight=0):
        slots = np.where(self.edge_rule > 0, self.slots(self.edge_rule, NEUTRAL_SLOT), NEUTRAL_SLOT)
        if highlight:
            slots = np.where(self.edge_rule == highlight, slots, NEUTRAL_SLOT)
        return slots

    def marker_slots(self, highlight=0):
        slots = self.slots(self.marker_rule, DIMMED_SLOT)
        if highlight:
            slots = np.where(self.marker_rule == highlight, slots, DIMMED_SLOT)
        return slots

    def counts(self):
        """{symbol: (instances at this level, streets they hold)} of the rules present."""
        instances = dict(zip(*np.unique(self.marker_rule, return_counts=True)))
        streets = dict(zip(*np.unique(self.edge_rule[self.edge_rule > 0], return_counts=True)))
        return {int(s): (int(instances.get(s, 0)), int(streets.get(s, 0)))
                for s in sorted(set(instances) | set(streets))}
