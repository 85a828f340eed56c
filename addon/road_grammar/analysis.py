"""The graph analyzer in Blender (paper 5): settings, stored results and the road graph as
the analyzer sees it.

* ``scene.road_analysis`` (ROADS_PG_analysis_settings): the parameters of Analyze and
  Find Similar, shown in the Patterns panel.
* ``object.road_analysis`` (ROADS_PG_analysis) on a road graph object: the result of the
  last Analyze, saved in the .blend. The best isogroups (at most ``max_stored``) are items
  of a collection with their numbers (order, occurrences, non-overlapping, gain, ...);
  their occurrences are three flat int32 arrays in ID properties of the same group (bulk
  copies, no Python object per occurrence):

  - ``occurrences``: the mesh vertex ids of every occurrence, isogroup after isogroup,
    each isogroup an (n, k) block starting at its item's ``occurrence_start``;
  - ``non_overlapping``: per isogroup, indices into its own occurrences (from
    ``non_overlapping_start``), the largest set sharing no vertex;
  - ``pattern_edges``: per isogroup, the (e, 2) pattern vertex pairs of its induced
    edges (from ``edge_start``), so the mesh edges of an occurrence are found without
    searching.

  The mesh vertex ids are the graph's (the graph is built from the mesh in vertex order,
  see ``MeshTopology``). ``topology`` holds a checksum of the mesh's vertex count and
  edges at analysis time: when the mesh has changed since, the ids no longer mean the same
  vertices and the stored result is only listed, not shown. ``options`` holds the
  arguments of ggg.analyze as JSON, so that the same analysis can be run again.

The ggg.Isogroup objects themselves (with each occurrence's transform, which Replace
needs) are not saved: the last analysis keeps them in memory (``remember``), and
``live_isogroup`` gives back the one of a stored item, running the same analysis again
when they are gone (after reopening the file or analysing another graph) or no longer fit
(vertices moved), and checking that it finds the same occurrences.
"""

import json
import zlib

import bmesh
import bpy
import numpy as np
from bpy.props import (BoolProperty, CollectionProperty, EnumProperty, FloatProperty, FloatVectorProperty,
                       IntProperty, PointerProperty, StringProperty)
from bpy.types import PropertyGroup

from . import mesh_build, pattern_display
from .importer import SYMBOL

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


class MeshTopology:
    """The road graph of a mesh as the analyzer sees it: vertex positions (metres, the
    object's local x, y), edges and vertex symbols (and, ``with_classes``, the highway class
    of each edge: a learned grammar's rules keep them), in the mesh's own order, so that
    graph vertex i is mesh vertex i and graph edge j is mesh edge j.

    In Edit Mode the edit mesh is written to the mesh first (``update_from_editmode``), so
    this is what the user sees."""

    def __init__(self, obj, with_classes=False):
        if obj.mode == 'EDIT':
            obj.update_from_editmode()
        mesh = obj.data
        self.positions = mesh_build.positions_xy(mesh)
        self.edges = mesh_build.edge_vertices(mesh)
        self.vertex_count = len(self.positions)
        self.symbols = _int_attribute(obj, SYMBOL, 'POINT')
        if self.symbols is not None:
            self.symbols = np.maximum(self.symbols, 0)
        self.highway = _int_attribute(obj, "highway", 'EDGE') if with_classes else None
        self.selected = np.zeros(self.vertex_count, dtype=bool)
        mesh.vertices.foreach_get("select", self.selected)
        lat, lon = float(obj.get("origin_lat", 0.0)), float(obj.get("origin_lon", 0.0))
        self.origin_latlon = (lat, lon)
        self.checksum = topology_checksum(self.vertex_count, self.edges)


    def graph(self, ggg):
        """The ggg.Graph of the mesh (raises ggg.Error for a mesh the library refuses, e.g. a
        repeated edge)."""
        extra = {} if self.symbols is None else {"vertex_symbols": self.symbols}
        if self.highway is not None:
            extra["edge_highway"] = np.clip(self.highway, 0, len(ggg.highway_classes()) - 1)
        return ggg.Graph.from_arrays(self.positions, self.edges, origin_latlon=self.origin_latlon, **extra)

    def selected_ids(self):
        return np.flatnonzero(self.selected).astype(np.int64)


def _int_attribute(obj, name, domain):
    """The values of the INT attribute ``name`` on ``domain`` ('POINT' or 'EDGE') of
    ``obj``'s mesh as int64, else None. In Edit Mode the values are the edit mesh's
    (Blender's attribute data is empty there)."""
    mesh = obj.data
    attribute = mesh.attributes.get(name)
    if attribute is None or attribute.domain != domain or attribute.data_type != 'INT':
        return None
    if obj.mode != 'EDIT':
        return mesh_build.read_attribute(mesh, name, np.int64)
    bm = bmesh.from_edit_mesh(mesh)
    elements = bm.verts if domain == 'POINT' else bm.edges
    layer = elements.layers.int.get(name)
    if layer is None:
        return None
    return np.fromiter((element[layer] for element in elements), dtype=np.int64, count=len(elements))


def topology_checksum(vertex_count, edges):
    """A checksum of what the vertex ids of an analysis refer to: the vertex count and the
    edges (moving vertices keeps it)."""
    edges = np.ascontiguousarray(edges, dtype=np.int64)
    return "{}:{}:{:08x}".format(vertex_count, len(edges), zlib.crc32(edges.tobytes()))


def mesh_checksum(obj):
    """topology_checksum of ``obj``'s mesh as it is stored (Object Mode data)."""
    mesh = obj.data
    return topology_checksum(len(mesh.vertices), mesh_build.edge_vertices(mesh))


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


# --- properties -----------------------------------------------------------------------

def _item_color(item):
    return pattern_display.slot_color_srgb(item.color_slot)


class ROADS_PG_isogroup(PropertyGroup):
    """One isogroup of an analysis: a street pattern and where it occurs."""

    # name (from PropertyGroup): "order k", what the list's filter matches.
    rank: IntProperty(name="Rank",
                      description="Place in the list: 1 = the largest gain (with a seed: the seed's own group)")
    order: IntProperty(name="Order", description="Vertices of the pattern")
    edge_count: IntProperty(name="Edges", description="Edges of the pattern")
    frequency: IntProperty(name="Occurrences", description="Places where the pattern occurs (they may overlap)")
    non_overlapping_count: IntProperty(name="Non-Overlapping",
                                       description="The largest number of occurrences that share no vertex")
    gain: FloatProperty(name="Gain", description="Description-length gain of encoding the non-overlapping occurrences")
    score: FloatProperty(name="Score", description="Frequency x convex-hull area added by the last vertex (paper 5.1)")
    size_m: FloatProperty(name="Size", description="Mean RMS radius of the occurrences", unit='LENGTH')
    aspect: FloatProperty(name="Aspect", description="Aspect ratio of the pattern (1 = as wide as long)")
    leaves: IntProperty(name="Leaves", description="Pattern vertices with one street")
    irregularity_deg: FloatProperty(name="Irregularity",
                                    description="Mean deviation of the pattern's street angles from multiples of "
                                    "90 degrees")
    parent: IntProperty(name="Parent", description="Rank of the isogroup this one grew from (0: none, or not stored)")
    selection_exact: BoolProperty(name="Exact", description="The non-overlapping set is a proven maximum")
    selection_method: StringProperty(name="Method", description="How the non-overlapping set was chosen")
    color_slot: IntProperty(name="Colour Slot", description="Colour of the isogroup in the overview (0: not coloured)")
    color: FloatVectorProperty(name="Colour", description="Colour of the isogroup in the overview",
                               subtype='COLOR_GAMMA', size=3, get=_item_color)
    occurrence_start: IntProperty(options={'HIDDEN'})
    non_overlapping_start: IntProperty(options={'HIDDEN'})
    edge_start: IntProperty(options={'HIDDEN'})


def _active_index_changed(self, context):
    # Choosing an isogroup in the list highlights it (select + colour); the update is
    # skipped while the add-on itself sets the index.
    if pattern_display.updates_suspended() or self.active_index < 0:
        return
    obj = self.id_data
    try:
        show_isogroup(obj, self.active_index, select=True)
    except (StaleAnalysis, KeyError, ValueError):
        pass  # the panel says why (out of date); an update cannot report


class ROADS_PG_analysis(PropertyGroup):
    """The result of the last Analyze of a road graph object (kept in the .blend)."""

    isogroups: CollectionProperty(type=ROADS_PG_isogroup)
    active_index: IntProperty(name="Isogroup", description="Isogroup shown in the viewport (select + colour)",
                              default=-1, min=-1, update=_active_index_changed)
    detected: IntProperty(name="Detected", description="Isogroups found before the constraints")
    listed: IntProperty(name="Listed", description="Isogroups that passed the constraints")
    stopped_by_budget: BoolProperty(name="Stopped by Budget")
    seeded: BoolProperty(name="Seeded", description="The analysis grew from the selected vertices")
    seconds: FloatProperty(name="Time", description="Duration of the analysis in seconds")
    max_order: IntProperty(name="Largest Order", description="Largest order of an isogroup found")
    parameters: StringProperty(name="Parameters", description="The parameters of the analysis")
    options: StringProperty(name="Options", description="The arguments of ggg.analyze as JSON (to run the same "
                            "analysis again)")
    topology: StringProperty(name="Topology", description="Checksum of the mesh the vertex ids refer to")

    def has_result(self):
        return bool(self.topology)


def settings_properties():
    """The parameters of Analyze, new property objects on each call: the scene's settings
    (ROADS_PG_analysis_settings) and the operator (analysis_ops.ROADS_OT_analyze) declare
    the same ones, and the operator takes the scene's values when invoked."""
    return {
        "angle_cells": IntProperty(
            name="Angle Cells", description="Angle cells of the polar grid a new vertex is binned in (paper 5.1); "
            "finer grids find fewer, closer copies", default=12, min=1, soft_max=72),
        "distance_cells": IntProperty(
            name="Distance Cells", description="Distance cells of the polar grid", default=10, min=1, soft_max=60),
        "cut": FloatProperty(
            name="Frequency Cut", description="Share of the least frequent patterns that are not grown further "
            "(about 0.8 once the patterns are well formed)", default=0.8, min=0.0, max=0.99, precision=2),
        "full": BoolProperty(
            name="Full", description="Grow every pattern (no frequency cut): the paper's ground truth, slow on "
            "large graphs", default=False),
        "max_order": IntProperty(
            name="Max Order", description="Largest pattern in vertices (0 = until nothing repeats)", default=8,
            min=0, soft_max=20),
        "min_count": IntProperty(
            name="Min Count", description="Fewest occurrences for a pattern to count as repeated", default=2, min=2,
            soft_max=100),
        "scale": EnumProperty(
            name="Scale", description="How the sizes of two occurrences may differ", items=SCALE_ITEMS,
            default='SIMILARITY'),
        "tolerance": FloatProperty(
            name="Tolerance", description="Largest vertex displacement of a match, relative to the seed's size "
            "(Find Similar, and Analyze with a seed)", default=0.15, min=0.0, soft_max=0.5, precision=3),
        "min_aspect": FloatProperty(
            name="Min Aspect", description="List only patterns at least this close to square (0 = any; 1 = as "
            "wide as long)", default=0.0, min=0.0, max=1.0, precision=2),
        "min_leaves": IntProperty(
            name="Min Leaves", description="List only patterns with at least this many dead-end vertices",
            default=0, min=0, soft_max=10),
        "min_irregularity": FloatProperty(
            name="Min Irregularity", description="List only patterns whose street angles deviate at least this "
            "much from a right-angled grid (degrees)", default=0.0, min=0.0, max=45.0, precision=1),
        "use_seed": BoolProperty(
            name="Selection as Seed", description="Grow the analysis from the vertices selected in Edit Mode (its "
            "own isogroup comes first)", default=False),
        "max_stored": IntProperty(
            name="Keep", description="Isogroups kept in the list and in the .blend (the best ones)",
            default=DEFAULT_MAX_STORED, min=1, soft_max=2000),
        "overview_count": IntProperty(
            name="Colours", description="Isogroups coloured in the overview, each in its own colour (the best ones)",
            default=pattern_display.PALETTE_SIZE, min=1, max=pattern_display.PALETTE_SIZE),
    }


class ROADS_PG_analysis_settings(PropertyGroup):
    """The parameters of Analyze and Find Similar (Roads sidebar > Patterns)."""

    __annotations__ = {
        **settings_properties(),
        "show_constraints": BoolProperty(name="Constraints", description="Show the selection constraints",
                                         default=False),
    }


# --- storing and reading results -------------------------------------------------------

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
        occurrence_starts = _starts(occurrences)
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
            "non_overlapping_start": (np.int32, _starts(non_overlapping)[:-1]),
            "edge_start": (np.int32, _starts(pattern_edges)[:-1]),
        }
        self.names = ["order {}".format(iso.order) for iso in groups]
        self.methods = [iso.selection_method for iso in groups]
        self.arrays = {OCCURRENCES: _concatenated(occurrences), NON_OVERLAPPING: _concatenated(non_overlapping),
                       PATTERN_EDGES: _concatenated(pattern_edges)}
        self.count = count
        self.listed = len(all_groups)
        self.detected = int(analysis.detected)
        self.stopped_by_budget = bool(analysis.stopped_by_budget)
        self.max_order = max((iso.order for iso in all_groups), default=0)


def store(obj, stored, topology, seconds, parameters, seeded, options=None):
    """Write ``stored`` (a StoredAnalysis of the graph ``topology``) into
    ``obj.road_analysis``, replacing what was there; ``options``: the keyword arguments of
    ggg.analyze that made it (without ``progress``). Returns the number of isogroups kept."""
    result = obj.road_analysis
    with pattern_display.suspended_updates():
        result.isogroups.clear()
        result.active_index = -1
        items = result.isogroups
        for name, method in zip(stored.names, stored.methods):
            item = items.add()
            item.name = name
            item.selection_method = method
        if stored.count:
            for name, (kind, values) in stored.columns.items():
                items.foreach_set(name, np.asarray(values, dtype=kind).reshape(-1))
        for key, values in stored.arrays.items():
            result[key] = values
        result.detected = stored.detected
        result.listed = stored.listed
        result.stopped_by_budget = stored.stopped_by_budget
        result.seconds = float(seconds)
        result.max_order = stored.max_order
        result.parameters = parameters
        result.options = options_json(options) if options is not None else ""
        result.topology = topology.checksum
        result.seeded = bool(seeded)
    return stored.count


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


def _starts(arrays):
    starts = np.zeros(len(arrays) + 1, dtype=np.int64)
    np.cumsum([len(a) for a in arrays], out=starts[1:])
    return starts


def _concatenated(arrays):
    return np.concatenate(arrays).astype(np.int32) if arrays else np.zeros(0, dtype=np.int32)


def clear(obj, forget_isogroups=True):
    """Forget the analysis of ``obj`` (the colours stay until cleared separately) and, with
    ``forget_isogroups``, the isogroups kept in memory for it (see ``remember``; they are
    only used while the stored result is theirs, so they may stay for an undo)."""
    result = obj.road_analysis
    with pattern_display.suspended_updates():
        result.isogroups.clear()
        result.active_index = -1
    for key in (OCCURRENCES, NON_OVERLAPPING, PATTERN_EDGES):
        if key in result:
            del result[key]
    result.topology = ""
    result.parameters = ""
    result.options = ""
    result.detected = result.listed = result.max_order = 0
    result.seconds = 0.0
    result.stopped_by_budget = result.seeded = False
    if forget_isogroups:
        forget(obj)


def _flat(result, key):
    if key not in result:
        return np.zeros(0, dtype=np.int32)
    return np.array(result[key], dtype=np.int32, copy=True)


def isogroup_arrays(obj, index):
    """(occurrences (n, k), non-overlapping indices (m,), pattern edges (e, 2)) of the stored
    isogroup ``index`` of ``obj``, as int64 arrays."""
    result = obj.road_analysis
    item = result.isogroups[index]
    n, k, e = item.frequency, item.order, item.edge_count
    occurrences = _flat_slice(result, OCCURRENCES, item.occurrence_start, n * k).reshape(n, k)
    non_overlapping = _flat_slice(result, NON_OVERLAPPING, item.non_overlapping_start, item.non_overlapping_count)
    edges = _flat_slice(result, PATTERN_EDGES, item.edge_start, 2 * e).reshape(e, 2)
    return occurrences, non_overlapping, edges


def _flat_slice(result, key, start, count):
    if key not in result:
        raise StaleAnalysis("The stored analysis is incomplete; analyse again")
    flat = np.frombuffer(result[key], dtype=np.int32)
    if start < 0 or start + count > len(flat):
        raise StaleAnalysis("The stored analysis is incomplete; analyse again")
    return flat[start:start + count].astype(np.int64)


def check_current(obj, topology=None):
    """Raise StaleAnalysis when ``obj`` has no analysis or its mesh changed since; returns
    the MeshTopology of the mesh (``topology``, or read now; ``False``: none, only check
    the mesh as stored, which is cheap enough for drawing)."""
    result = obj.road_analysis
    if not result.has_result():
        raise StaleAnalysis("{} has not been analysed: run Analyze first".format(obj.name))
    if topology is False:
        checksum = mesh_checksum(obj)
    else:
        topology = topology or MeshTopology(obj)
        checksum = topology.checksum
    if checksum != result.topology:
        raise StaleAnalysis("The road graph {} changed since it was analysed (vertices or edges added or removed): "
                            "analyse it again".format(obj.name))
    return topology


# --- the isogroups themselves (ggg.Isogroup, with the occurrences' transforms) ---------------

# Object name -> (key, isogroups): the ggg.Isogroup objects of the kept items of the last
# analysis run in this session (one object at a time, so that a large analysis is not held
# twice). ``key`` says what they were computed from: (topology checksum, positions digest,
# options), so they are used only while the stored result and the vertices are the same.
_live = {}


def positions_digest(positions):
    """A checksum of vertex positions (the transforms of an analysis depend on them)."""
    return "{:08x}".format(zlib.crc32(np.ascontiguousarray(positions, dtype=np.float64).tobytes()))


def _live_key(result, positions):
    return (result.topology, positions_digest(positions), result.options)


def remember(obj, topology, groups):
    """Keep ``groups`` (the ggg.Isogroup objects of the items just stored in
    ``obj.road_analysis``, computed from ``topology``, the MeshTopology analysed) for
    ``live_isogroup``. Replaces what was kept for any object."""
    _live.clear()
    _live[obj.name] = (_live_key(obj.road_analysis, topology.positions), list(groups))


def forget(obj=None):
    """Drop the isogroups kept for ``obj`` (None: for every object)."""
    if obj is None:
        _live.clear()
    else:
        _live.pop(obj.name, None)


def _same_occurrences(iso, occurrences, non_overlapping, pattern_edges):
    return (np.array_equal(np.asarray(iso.occurrences, dtype=np.int64).reshape(occurrences.shape), occurrences)
            and np.array_equal(np.asarray(iso.non_overlapping, dtype=np.int64), non_overlapping)
            and np.array_equal(np.asarray(iso.pattern_edges, dtype=np.int64).reshape(-1, 2), pattern_edges))


def live_isogroup(ggg, obj, index, topology=None, progress=None):
    """The ggg.Isogroup of the stored item ``index`` of ``obj``'s analysis, as the mesh is
    now: the one kept in memory when it was computed from these vertices, else that of the
    same analysis (the stored ``options``) run again on the mesh (this can take as long as
    Analyze). Either way it has exactly the stored occurrences and non-overlapping set.

    Raises StaleAnalysis (no analysis, a changed mesh, no isogroup ``index``, no stored
    options, or vertices moved so that the analysis finds other patterns), ggg.Cancelled
    when ``progress`` cancels, ggg.Error when the library refuses the graph."""
    topology = check_current(obj, topology)
    result = obj.road_analysis
    if not 0 <= index < len(result.isogroups):
        raise StaleAnalysis("{} has no isogroup {}".format(obj.name, index + 1))
    occurrences, non_overlapping, pattern_edges = isogroup_arrays(obj, index)
    key = _live_key(result, topology.positions)
    kept = _live.get(obj.name)
    if kept is not None and kept[0] == key and index < len(kept[1]) and \
            _same_occurrences(kept[1][index], occurrences, non_overlapping, pattern_edges):
        return kept[1][index]
    if not result.options:
        raise StaleAnalysis("The analysis of {} does not say how it was made (an older version of the add-on?): "
                            "analyse it again".format(obj.name))
    try:
        options = json.loads(result.options)
    except ValueError as ex:
        raise StaleAnalysis("The stored options of the analysis of {} cannot be read ({}): analyse it again".format(
            obj.name, ex)) from ex
    if not isinstance(options, dict):
        raise StaleAnalysis("The stored options of the analysis of {} cannot be read: analyse it again".format(
            obj.name))
    if "grid" in options:
        options["grid"] = tuple(options["grid"])
    if "seed" in options:
        options["seed"] = np.asarray(options["seed"], dtype=np.int64)
    try:
        again = ggg.analyze(topology.graph(ggg), progress=progress, **options)
    except TypeError as ex:  # options the module does not take
        raise StaleAnalysis("The analysis of {} cannot be run again ({}): analyse it again".format(obj.name, ex)) \
            from ex
    groups = again.isogroups[:len(result.isogroups)]  # a new list on every access: read once
    if index >= len(groups) or not _same_occurrences(groups[index], occurrences, non_overlapping, pattern_edges):
        raise StaleAnalysis("The vertices of {} moved since it was analysed and the analysis now finds other "
                            "patterns: analyse it again".format(obj.name))
    _live.clear()
    _live[obj.name] = (key, list(groups))
    return groups[index]


def show_isogroup(obj, index, select=True, only_non_overlapping=False):
    """Colour the occurrences of stored isogroup ``index`` (its overview colour, or the
    match colour when it has none) and select their vertices. Returns (occurrences shown,
    vertices selected)."""
    topology = check_current(obj)
    result = obj.road_analysis
    if not 0 <= index < len(result.isogroups):
        raise StaleAnalysis("{} has no isogroup {}".format(obj.name, index + 1))
    occurrences, non_overlapping, pattern_edges = isogroup_arrays(obj, index)
    if only_non_overlapping:
        occurrences = occurrences[non_overlapping]
    slot = result.isogroups[index].color_slot or pattern_display.MATCH_SLOT
    lookup = pattern_display.EdgeLookup(topology.edges, topology.vertex_count)
    slots = np.zeros(len(topology.edges), dtype=np.int32)
    slots[lookup.occurrence_edges(occurrences, pattern_edges).ravel()] = slot
    vertex_mask = None
    if select:
        vertex_mask = np.zeros(topology.vertex_count, dtype=bool)
        vertex_mask[occurrences.ravel()] = True
    pattern_display.write(obj, slots, vertex_mask, topology)
    return len(occurrences), 0 if vertex_mask is None else int(vertex_mask.sum())


def show_overview(obj, count=None):
    """Colour the graph by isogroup (paper Fig. 13): the non-overlapping occurrences of each
    of the first ``count`` coloured isogroups in its own colour, the best ones first (an
    occurrence is coloured only where no better isogroup was). Returns the number of
    occurrences coloured."""
    topology = check_current(obj)
    result = obj.road_analysis
    lookup = pattern_display.EdgeLookup(topology.edges, topology.vertex_count)
    slots = np.zeros(len(topology.edges), dtype=np.int32)
    shown = 0
    for index, item in enumerate(result.isogroups):
        if item.color_slot <= 0 or (count is not None and item.color_slot > count):
            continue
        occurrences, non_overlapping, pattern_edges = isogroup_arrays(obj, index)
        if len(pattern_edges) == 0 or len(non_overlapping) == 0:
            continue
        edge_ids = lookup.occurrence_edges(occurrences[non_overlapping], pattern_edges)
        # Non-overlapping occurrences share no vertex, hence no edge: testing them all at
        # once against the colours so far is exact.
        free = (slots[edge_ids] == 0).all(axis=1)
        slots[edge_ids[free].ravel()] = item.color_slot
        shown += int(free.sum())
    pattern_display.write(obj, slots, None, topology)
    with pattern_display.suspended_updates():
        result.active_index = -1
    return shown


def register():
    bpy.types.Scene.road_analysis = PointerProperty(type=ROADS_PG_analysis_settings)
    bpy.types.Object.road_analysis = PointerProperty(type=ROADS_PG_analysis)


def unregister():
    del bpy.types.Object.road_analysis
    del bpy.types.Scene.road_analysis
