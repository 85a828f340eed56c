"""A road graph read by the native module -> Blender objects.

Two objects per import, linked to the active collection:

* "<name>": the graph itself, a mesh of loose edges (one vertex per graph vertex, one
  edge per graph edge, same order as the ggg.Graph arrays) with the edge attributes
  `highway` (class code), `width` (metres), `rank`, `lanes` and `oneway`;
* "<name> Surface" (child of the first): the edge polylines, with `width`, `highway` and
  `rank` per segment, and the "Road Surface" Geometry Nodes modifier that makes them
  flat ribbons.
"""

import threading
import time

import bpy
import numpy as np

from . import georef, mesh_build, surface

GRAPH_KEY = "road_graph"
SURFACE_KEY = "road_surface"
CLASSES_KEY = "highway_classes"

_SOURCE_SUFFIXES = (".osm.pbf", ".osm.bz2", ".osm.gz", ".osm", ".pbf", ".bz2", ".gz",
                    ".geojson", ".json", ".ggraph")


def object_name(path):
    """'paris_marais' for '/data/paris_marais.osm.pbf'."""
    name = bpy.path.basename(path)
    lower = name.lower()
    for suffix in _SOURCE_SUFFIXES:
        if lower.endswith(suffix) and len(name) > len(suffix):
            return name[: -len(suffix)]
    return name


class Progress:
    """Window-manager progress for the native reader's callback.

    The callback may come from a thread of the native library: Blender is only touched
    from the thread that created this object, other calls just record the state.
    """

    def __init__(self, context, read_share=0.85):
        self._wm = context.window_manager
        # The status bar in the UI; the console in background mode.
        self._workspace = None if bpy.app.background or context.window is None else context.workspace
        self._thread = threading.get_ident()
        self._read_share = read_share
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
        """The ggg progress callback (reading): fraction in [0, 1] and what it does."""
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
        text = "Importing roads: {} ({:.0f}%)".format(self.message, 100.0 * self.fraction)
        if self._workspace is not None:
            self._workspace.status_text_set(text)
        else:
            now = time.monotonic()
            if now - self._last_print > 1.0 or self.fraction >= 1.0:
                print(text)
                self._last_print = now


class _Created:
    """Datablocks made during one import, removed again if the import fails midway."""

    def __init__(self):
        self.items = []

    def add(self, datablock):
        self.items.append(datablock)
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


def _graph_attributes(graph, widths):
    return {
        "highway": ('INT', graph.edge_highway),
        "width": ('FLOAT', widths),
        "rank": ('INT', graph.edge_rank),
        "lanes": ('INT', graph.edge_lanes),
        "oneway": ('INT', graph.edge_oneway),
    }


def build(context, graph, classes, widths, name, source, options, with_surface=True, progress=None):
    """Create the road objects for ``graph``; returns (graph object, surface object or None,
    warning or None). Either everything is created or nothing is."""
    created = _Created()
    try:
        return _build(context, graph, classes, widths, name, source, options, with_surface, progress, created)
    except BaseException:
        created.remove_all()
        raise


def _build(context, graph, classes, widths, name, source, options, with_surface, progress, created):
    def step(fraction, message):
        if progress is not None:
            progress.step(fraction, message)

    scene = context.scene
    lat, lon = (float(v) for v in graph.origin_latlon)
    place = georef.placement(scene, lat, lon)

    step(0.0, "graph mesh")
    positions = np.asarray(graph.positions, dtype=np.float64)
    edges = np.asarray(graph.edges, dtype=np.int32)
    mesh = created.add(mesh_build.new_edge_mesh(name, positions, edges, _graph_attributes(graph, widths)))
    graph_obj = created.add(bpy.data.objects.new(name, mesh))
    graph_obj[GRAPH_KEY] = 1
    graph_obj[CLASSES_KEY] = {class_name: code for code, class_name in enumerate(classes)}
    graph_obj["source"] = source
    graph_obj["origin_lat"] = lat
    graph_obj["origin_lon"] = lon
    graph_obj["crs"] = georef.proj_string(lat, lon)
    graph_obj["total_length_m"] = float(graph.total_length_m)
    graph_obj["import_options"] = options
    graph_obj.location = (place.location[0], place.location[1], 0.0)
    graph_obj.rotation_euler = (0.0, 0.0, place.rotation)

    surface_obj = None
    if with_surface:
        step(0.3, "surface polylines")
        offsets, points = graph.edge_geometry()
        points, segments, owner = mesh_build.polyline_segments(offsets, points, positions, edges)
        surface_mesh = created.add(mesh_build.new_edge_mesh(
            graph_obj.name + " Surface", points, segments, {
                "width": ('FLOAT', np.asarray(widths)[owner]),
                "highway": ('INT', np.asarray(graph.edge_highway)[owner]),
                "rank": ('INT', np.asarray(graph.edge_rank)[owner]),
            }))
        step(0.7, "surface modifier")
        surface_obj = created.add(bpy.data.objects.new(graph_obj.name + " Surface", surface_mesh))
        surface_obj[SURFACE_KEY] = 1
        surface_obj.parent = graph_obj
        groups_before = set(bpy.data.node_groups.keys())
        materials_before = set(bpy.data.materials.keys())
        group = surface.node_group()
        mat = surface.material()
        if group.name not in groups_before:
            created.add(group)
        if mat.name not in materials_before:
            created.add(mat)
        surface.add_modifier(surface_obj, group, mat)
        # The graph object is for editing and analysis; the surface is what renders.
        graph_obj.hide_render = True

    step(0.9, "linking")
    collection = context.collection or scene.collection
    collection.objects.link(graph_obj)
    if surface_obj is not None:
        collection.objects.link(surface_obj)
    if place.set_georef:
        georef.write(scene, lat, lon)
    for obj in context.view_layer.objects:
        obj.select_set(False)
    graph_obj.select_set(True)
    context.view_layer.objects.active = graph_obj
    step(1.0, "done")
    return graph_obj, surface_obj, place.warning
