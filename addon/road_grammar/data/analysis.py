"""The graph analyzer in Blender (paper 5): the road graph as the analyzer sees it, and the
results kept on it.

``object.road_analysis`` (properties.analysis.ROADS_PG_analysis) on a road graph object
holds the result of the last Analyze, saved in the .blend. The best isogroups (at most ``max_stored``) are items
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

display.patterns shows a stored result (``show_overview``, ``show_isogroup``).
"""

import json

import bmesh
import numpy as np

from ..core.analysis import NON_OVERLAPPING, OCCURRENCES, PATTERN_EDGES, StaleAnalysis, options_json, same_occurrences
from ..core.names import SYMBOL
from ..core.topology import positions_digest, topology_checksum
from ..core.updates import suspended_updates
from . import mesh as mesh_data


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
        self.positions = mesh_data.positions_xy(mesh)
        self.edges = mesh_data.edge_vertices(mesh)
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
        return mesh_data.read_attribute(mesh, name, np.int64)
    bm = bmesh.from_edit_mesh(mesh)
    elements = bm.verts if domain == 'POINT' else bm.edges
    layer = elements.layers.int.get(name)
    if layer is None:
        return None
    return np.fromiter((element[layer] for element in elements), dtype=np.int64, count=len(elements))


def mesh_checksum(obj):
    """topology_checksum of ``obj``'s mesh as it is stored (Object Mode data)."""
    mesh = obj.data
    return topology_checksum(len(mesh.vertices), mesh_data.edge_vertices(mesh))


def store(obj, stored, topology, seconds, parameters, seeded, options=None):
    """Write ``stored`` (a StoredAnalysis of the graph ``topology``) into
    ``obj.road_analysis``, replacing what was there; ``options``: the keyword arguments of
    ggg.analyze that made it (without ``progress``). Returns the number of isogroups kept."""
    result = obj.road_analysis
    with suspended_updates():
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


def clear(obj, forget_isogroups=True):
    """Forget the analysis of ``obj`` (the colours stay until cleared separately) and, with
    ``forget_isogroups``, the isogroups kept in memory for it (see ``remember``; they are
    only used while the stored result is theirs, so they may stay for an undo)."""
    result = obj.road_analysis
    with suspended_updates():
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
            same_occurrences(kept[1][index], occurrences, non_overlapping, pattern_edges):
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
    if index >= len(groups) or not same_occurrences(groups[index], occurrences, non_overlapping, pattern_edges):
        raise StaleAnalysis("The vertices of {} moved since it was analysed and the analysis now finds other "
                            "patterns: analyse it again".format(obj.name))
    _live.clear()
    _live[obj.name] = (key, list(groups))
    return groups[index]
