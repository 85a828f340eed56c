"""An analysis (ggg.analyze) as it is kept on a road graph object: the best isogroups'
numbers as columns and their occurrences as three flat int32 arrays (see
``data.analysis``), computed without Blender data, and the arguments that made it."""

import json

import numpy as np

# ID property keys of the flat arrays in ROADS_PG_analysis.
OCCURRENCES = "occurrences"
NON_OVERLAPPING = "non_overlapping"
PATTERN_EDGES = "pattern_edges"

DEFAULT_MAX_STORED = 200

SCALE_ITEMS = (
    ('SIMILARITY', "Similarity", "Patterns match at any size (rotation, translation and uniform scale)"),
    ('RIGID', "Rigid", "Patterns match only at the same size (rotation and translation)"),
    ('RANGE', "Scale Range", "Patterns match at sizes from half to twice the seed's (Analyze: sizes within a "
     "factor 4 of each other)"),
)
SCALE_NAMES = {'SIMILARITY': "similarity", 'RIGID': "rigid", 'RANGE': "range"}


class StaleAnalysis(Exception):
    """The object has no analysis, or its mesh changed since; the message says which."""


class StoredAnalysis:
    """What ``store`` writes, computed from a ggg.Analysis without touching Blender data (so
    that a result that cannot be kept changes nothing): the best ``max_stored`` of
    ``all_groups`` (the analysis's isogroups: the module makes that list on every access,
    so it is read once), the first ``overview_count`` of them with a colour. Raises
    ValueError when the occurrences are too many to store."""

    def __init__(self, analysis, all_groups, max_stored, overview_count):
        groups = all_groups[:max_stored]
        occurrences = [np.ascontiguousarray(iso.occurrences, dtype=np.int32).ravel() for iso in groups]
        non_overlapping = [np.ascontiguousarray(iso.non_overlapping, dtype=np.int64).astype(np.int32)
                           for iso in groups]
        pattern_edges = [np.ascontiguousarray(iso.pattern_edges, dtype=np.int32).ravel() for iso in groups]
        occurrence_starts = starts(occurrences)
        if occurrence_starts[-1] >= 2 ** 31:
            raise ValueError("the best {} isogroups have {:,} occurrence vertex ids, more than can be stored; keep "
                             "fewer".format(len(groups), occurrence_starts[-1]))
        count = len(groups)
        parents = np.array([iso.parent for iso in groups], dtype=np.int64).reshape(-1)
        # Numbers for foreach_set: fast even for tens of thousands of isogroups.
        self.columns = {
            "rank": (np.int32, np.arange(1, count + 1)),
            "order": (np.int32, [iso.order for iso in groups]),
            "edge_count": (np.int32, [iso.edge_count for iso in groups]),
            "frequency": (np.int32, [iso.frequency for iso in groups]),
            "non_overlapping_count": (np.int32, [len(chosen) for chosen in non_overlapping]),
            "gain": (np.float32, [iso.gain for iso in groups]),
            "score": (np.float32, [iso.score for iso in groups]),
            "size_m": (np.float32, [iso.size_m for iso in groups]),
            "aspect": (np.float32, [iso.aspect for iso in groups]),
            "leaves": (np.int32, [iso.leaves for iso in groups]),
            "irregularity_deg": (np.float32, [iso.irregularity_deg for iso in groups]),
            # parent: an index into the analysis's isogroups, i.e. its rank - 1; 0: not kept.
            "parent": (np.int32, np.where((parents >= 0) & (parents < count), parents + 1, 0)),
            "selection_exact": (np.bool_, [bool(iso.selection_exact) for iso in groups]),
            "color_slot": (np.int32, np.where(np.arange(count) < overview_count, np.arange(1, count + 1), 0)),
            "occurrence_start": (np.int32, occurrence_starts[:-1]),
            "non_overlapping_start": (np.int32, starts(non_overlapping)[:-1]),
            "edge_start": (np.int32, starts(pattern_edges)[:-1]),
        }
        self.names = ["order {}".format(iso.order) for iso in groups]
        self.methods = [iso.selection_method for iso in groups]
        self.arrays = {OCCURRENCES: concatenated(occurrences), NON_OVERLAPPING: concatenated(non_overlapping),
                       PATTERN_EDGES: concatenated(pattern_edges)}
        self.count = count
        self.listed = len(all_groups)
        self.detected = int(analysis.detected)
        self.stopped_by_budget = bool(analysis.stopped_by_budget)
        self.max_order = max((iso.order for iso in all_groups), default=0)


def options_json(options):
    """The keyword arguments of ggg.analyze as JSON (arrays and tuples as lists)."""
    def plain(value):
        if isinstance(value, np.ndarray):
            return value.tolist()
        if isinstance(value, tuple):
            return list(value)
        if isinstance(value, np.generic):
            return value.item()
        return value
    return json.dumps({name: plain(value) for name, value in options.items()}, sort_keys=True)


def starts(arrays):
    """Where each of ``arrays`` starts in their concatenation, and their total length last."""
    result = np.zeros(len(arrays) + 1, dtype=np.int64)
    np.cumsum([len(a) for a in arrays], out=result[1:])
    return result


def concatenated(arrays):
    """``arrays`` one after the other as int32."""
    return np.concatenate(arrays).astype(np.int32) if arrays else np.zeros(0, dtype=np.int32)


def same_occurrences(iso, occurrences, non_overlapping, pattern_edges):
    """Whether the ggg.Isogroup ``iso`` has exactly these (stored) occurrences."""
    return (np.array_equal(np.asarray(iso.occurrences, dtype=np.int64).reshape(occurrences.shape), occurrences)
            and np.array_equal(np.asarray(iso.non_overlapping, dtype=np.int64), non_overlapping)
            and np.array_equal(np.asarray(iso.pattern_edges, dtype=np.int64).reshape(-1, 2), pattern_edges))
