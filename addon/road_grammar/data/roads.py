"""Road graph objects: a road graph (ggg.Graph) -> Blender objects, the road graph of an
object, the ones selected, and removing one with what belongs to it. (The modifiers that
draw them are display's; display.road_objects makes the objects with them.)

Two objects per graph, linked to the active collection:

* "<name>": the graph itself, a mesh of loose edges (one vertex per graph vertex, one
  edge per graph edge, same order as the ggg.Graph arrays) with the edge attributes
  `highway` (class code), `width` (metres), `rank`, `lanes`, `oneway` and, when some
  road has one, `name` (text); and, when the graph has nonterminal vertices (grammars,
  see operators/grammar.py), the point attributes `symbol` and `frame_a` / `frame_b` with
  the "Rule Frames" modifier that draws them;
* "<name> Surface" (child of the first): the edge polylines, with `width`, `highway`,
  `rank` and `graph_edge` (the graph edge it belongs to) per segment, and the "Road
  Surface" Geometry Nodes modifier that makes them flat ribbons.
"""

import threading
import time

import bpy
import numpy as np

from ..core.columns import more_rewrite_slots
from ..core.names import (CLASSES_KEY, FRAME_A, FRAME_B, GRAPH_KEY, NAME, PATTERNS_KEY, RULES_KEY, SURFACE_EDGE,
                          SURFACE_KEY, SYMBOL, more_rewrite_names)
from ..core.polylines import polyline_segments
from . import mesh


class Progress:
    """Window-manager progress for the native reader's callback.

    The callback may come from a thread of the native library: Blender is only touched
    from the thread that created this object, other calls just record the state.
    """

    def __init__(self, context, read_share=0.85, label="Importing roads"):
        self._wm = context.window_manager
        # The status bar in the UI; the console in background mode.
        self._workspace = None if bpy.app.background or context.window is None else context.workspace
        self._thread = threading.get_ident()
        self._read_share = read_share
        self._label = label
        self.fraction = 0.0
        self.message = ""
        self._last_print = 0.0

    def __enter__(self):
        self._wm.progress_begin(0.0, 1.0)
        return self

    def __exit__(self, *exc):
        self._wm.progress_end()
        if self._workspace is not None:
            self._workspace.status_text_set(None)
        return False

    def __call__(self, fraction, message):
        """The ggg progress callback (reading, deriving): fraction in [0, 1] and what it does."""
        self.fraction = min(max(float(fraction), 0.0), 1.0) * self._read_share
        self.message = message
        if threading.get_ident() == self._thread:
            self._show()
        return True

    def step(self, fraction, message):
        """Progress of the building that follows the read, fraction in [0, 1]."""
        self.fraction = self._read_share + (1.0 - self._read_share) * fraction
        self.message = message
        self._show()

    def _show(self):
        self._wm.progress_update(self.fraction)
        text = "{}: {} ({:.0f}%)".format(self._label, self.message, 100.0 * self.fraction)
        if self._workspace is not None:
            self._workspace.status_text_set(text)
        else:
            now = time.monotonic()
            if now - self._last_print > 1.0 or self.fraction >= 1.0:
                print(text)
                self._last_print = now


class Created:
    """Datablocks made during one import, removed again if the import fails midway."""

    def __init__(self):
        self.items = []

    def add(self, datablock):
        self.items.append(datablock)
        return datablock

    def shared(self, make):
        """A shared node group or material from ``make`` (which finds or creates it),
        remembered as created when ``make`` created it."""
        groups_before = set(bpy.data.node_groups.keys())
        materials_before = set(bpy.data.materials.keys())
        datablock = make()
        if datablock.name not in (groups_before if isinstance(datablock, bpy.types.NodeTree) else materials_before):
            self.add(datablock)
        return datablock

    def remove_all(self):
        for datablock in reversed(self.items):
            if isinstance(datablock, bpy.types.Object):
                bpy.data.objects.remove(datablock)
            elif isinstance(datablock, bpy.types.Mesh):
                bpy.data.meshes.remove(datablock)
            elif isinstance(datablock, bpy.types.Material):
                bpy.data.materials.remove(datablock)
            elif isinstance(datablock, bpy.types.NodeTree):
                bpy.data.node_groups.remove(datablock)
        self.items.clear()


def road_graph_object(obj):
    """The road graph ``obj`` is or belongs to (its surface), else None."""
    if obj is None:
        return None
    if obj.get(GRAPH_KEY):
        return obj
    if obj.get(SURFACE_KEY) and obj.parent is not None and obj.parent.get(GRAPH_KEY):
        return obj.parent
    return None


def surface_object(graph_obj):
    """The surface child of a road graph object, else None."""
    return next((child for child in graph_obj.children if child.get(SURFACE_KEY)), None)


def selected_graphs(context, other_name=""):
    """(active road graph or None, the other road graphs: the one named, else the selected
    ones that are not the active one)."""
    active = road_graph_object(context.active_object)
    if active is not None and active.type != 'MESH':
        active = None
    if other_name:
        obj = bpy.data.objects.get(other_name)
        graph = road_graph_object(obj)
        return active, ([graph] if graph is not None and graph is not active else [])
    others = []
    for obj in context.selected_objects:
        graph = road_graph_object(obj)
        if graph is not None and graph is not active and graph not in others and graph.type == 'MESH':
            others.append(graph)
    return active, others


def _descendants(obj):
    """``obj``'s children, grandchildren, ... (depth first)."""
    found = []
    for child in obj.children:
        found.append(child)
        found.extend(_descendants(child))
    return found


def remove_graph_object(graph_obj):
    """Remove a road graph object with what belongs to it (its surface, its Rules and
    Patterns displays, their meshes); other children are unparented where they are."""
    owned = [graph_obj]
    for child in _descendants(graph_obj):
        if child.get(SURFACE_KEY) or child.get(RULES_KEY) or child.get(PATTERNS_KEY):
            owned.append(child)
        elif child.parent in owned:
            matrix = child.matrix_world.copy()
            child.parent = None
            child.matrix_world = matrix
    meshes = [obj.data for obj in owned if isinstance(obj.data, bpy.types.Mesh)]
    for obj in reversed(owned):
        bpy.data.objects.remove(obj)
    for graph_mesh in meshes:
        if graph_mesh.users == 0:
            bpy.data.meshes.remove(graph_mesh)


def graph_edge_attributes(graph, widths):
    """The edge attributes of the graph mesh from ``graph``'s columns and the road ``widths``."""
    attributes = {
        "highway": ('INT', graph.edge_highway),
        "width": ('FLOAT', widths),
        "rank": ('INT', graph.edge_rank),
        "lanes": ('INT', graph.edge_lanes),
        "oneway": ('INT', graph.edge_oneway),
    }
    names = graph.edge_names
    if any(names):
        attributes[NAME] = (mesh.STRING, names)
    return attributes


def vertex_attributes(symbols, frames, more_rewrites=None):
    """The point attributes of nonterminals: symbol and the frame's (a, b), and the slots of
    the rewrites pending at a vertex besides its own (``Graph.more_rewrites``)."""
    frames = np.asarray(frames, dtype=np.float64).reshape(-1, 4)
    attributes = {
        SYMBOL: ('INT', np.asarray(symbols, dtype=np.int64)),
        FRAME_A: ('FLOAT', frames[:, 0]),
        FRAME_B: ('FLOAT', frames[:, 1]),
    }
    if more_rewrites is not None:
        for slot, (slot_symbols, a, b) in enumerate(more_rewrite_slots(len(frames), more_rewrites), start=2):
            symbol_name, a_name, b_name = more_rewrite_names(slot)
            attributes[symbol_name] = ('INT', slot_symbols)
            attributes[a_name] = ('FLOAT', a)
            attributes[b_name] = ('FLOAT', b)
    return attributes


def surface_geometry(positions, edges, offsets, points, edge_attributes):
    """(points, segments, segment attributes) of the surface mesh: the edge polylines
    (``offsets``/``points`` as Graph.edge_geometry()) with ``width``, ``highway`` and
    ``rank`` of their edge and its index ``graph_edge``."""
    points, segments, owner = polyline_segments(offsets, points, positions, edges)
    attributes = {name: (edge_attributes[name][0], np.asarray(edge_attributes[name][1])[owner])
                  for name in ("width", "highway", "rank")}
    attributes[SURFACE_EDGE] = ('INT', owner)
    return points, segments, attributes


def has_nonterminals(graph):
    """Whether ``graph`` has a nonterminal vertex (symbol > 0)."""
    return bool(np.any(np.asarray(graph.vertex_symbols) != 0))


def new_objects(graph, classes, widths, name, source, options, created, with_surface=True, with_frames=False,
                location=(0.0, 0.0), properties=None, step=None):
    """The objects of ``graph``: (graph object, surface object or None), not yet linked to a
    collection; every datablock made is remembered in ``created``.

    ``with_frames`` adds the nonterminal point attributes, ``location`` places the object,
    ``properties`` are more custom properties of the graph object; ``step(fraction,
    message)`` is told the progress."""
    def report(fraction, message):
        if step is not None:
            step(fraction, message)

    lat, lon = (float(v) for v in graph.origin_latlon)
    report(0.0, "graph mesh")
    positions = np.asarray(graph.positions, dtype=np.float64)
    edges = np.asarray(graph.edges, dtype=np.int32)
    edge_attributes = graph_edge_attributes(graph, widths)
    graph_mesh = created.add(mesh.new_edge_mesh(
        name, positions, edges, edge_attributes,
        vertex_attributes(graph.vertex_symbols, graph.vertex_frames, graph.more_rewrites) if with_frames else None))
    graph_obj = created.add(bpy.data.objects.new(name, graph_mesh))
    graph_obj[GRAPH_KEY] = 1
    graph_obj[CLASSES_KEY] = {class_name: code for code, class_name in enumerate(classes)}
    graph_obj["source"] = source
    graph_obj["origin_lat"] = lat
    graph_obj["origin_lon"] = lon
    graph_obj["crs"] = graph.crs
    graph_obj["total_length_m"] = float(graph.total_length_m)
    if options is not None:
        graph_obj["import_options"] = options
    for key, value in (properties or {}).items():
        graph_obj[key] = value
    graph_obj.location = (location[0], location[1], 0.0)

    surface_obj = None
    if with_surface:
        report(0.3, "surface polylines")
        offsets, points = graph.edge_geometry()
        points, segments, attributes = surface_geometry(positions, edges, offsets, points, edge_attributes)
        surface_mesh = created.add(mesh.new_edge_mesh(graph_obj.name + " Surface", points, segments, attributes))
        surface_obj = created.add(bpy.data.objects.new(graph_obj.name + " Surface", surface_mesh))
        surface_obj[SURFACE_KEY] = 1
        surface_obj.parent = graph_obj
        # The graph object is for editing and analysis; the surface is what renders.
        graph_obj.hide_render = True
    return graph_obj, surface_obj


def link(context, graph_obj, surface_obj, graph, target=None):
    """Link the objects of new_objects to the active collection, set the scene's
    georeference for ``graph`` (``target``, a georef.Target, for the first graph), and make
    the graph object the one selected and active."""
    scene = context.scene
    collection = context.collection or scene.collection
    collection.objects.link(graph_obj)
    if surface_obj is not None:
        collection.objects.link(surface_obj)
    if target is not None:
        target.finish(scene, graph)
    for obj in context.view_layer.objects:
        obj.select_set(False)
    graph_obj.select_set(True)
    context.view_layer.objects.active = graph_obj
