"""Terminal replacement in Blender (paper Fig. 1): store a piece of street network, then put
it in place of every non-overlapping occurrence of the isogroup chosen in the list.

* Store as Piece (roads.store_replacement): the vertices selected in the road graph and the
  streets between them, or another mesh or curve object, become the scene's piece
  (data/replacement.py keeps it in the .blend).
* Replace (roads.replace_isogroup): ggg.replace_isogroup on the road graph with the chosen
  isogroup of its last analysis (analysis.live_isogroup gives the ggg.Isogroup, with the
  occurrences' transforms) and the stored piece; the result goes back into the same mesh
  through graph_edit.Replacement, as Grow writes its result. The stored analysis no longer
  fits the graph afterwards: it is cleared, with its colours.

Both change nothing when they fail (an error report, CANCELLED).
"""

import bpy
import numpy as np
from bpy.props import IntProperty, StringProperty
from bpy.types import Operator

from ..core.analysis import StaleAnalysis
from ..core.piece import PieceError
from ..core.text import plural
from ..core.topology import replaced_vertices
from ..data import analysis, graph_edit, replacement, roads
from ..display import patterns, road_objects
from .common import analyzer_or_report, class_widths, graph_or_report, isogroup_index_or_report


class ROADS_OT_store_replacement(Operator):
    """Keep the vertices selected in the road graph and the streets between them (or another mesh or curve object) as the piece that Replace puts in place of a pattern"""

    bl_idname = "roads.store_replacement"
    bl_label = "Store as Piece"
    bl_options = {'REGISTER', 'UNDO'}

    object: StringProperty(
        name="Object",
        description="Mesh or curve object whose vertices and edges become the piece, in the road graph's frame "
        "(empty: the vertices selected in the road graph)",
        options={'SKIP_SAVE'},
    )

    def execute(self, context):
        graph_obj = graph_or_report(self, context)
        if graph_obj is None:
            return {'CANCELLED'}
        ggg = analyzer_or_report(self)
        if ggg is None:
            return {'CANCELLED'}
        try:
            if self.object:
                piece_obj = bpy.data.objects.get(self.object)
                if piece_obj is None:
                    raise PieceError("No object named '{}' to store as the piece".format(self.object))
                piece = replacement.from_object(ggg, piece_obj, graph_obj, context.evaluated_depsgraph_get())
            else:
                piece = replacement.from_selection(ggg, graph_obj)
            problem = piece.problem()
            if problem is not None:
                raise PieceError("{}: {}".format(piece.source, problem))
        except PieceError as ex:
            self.report({'ERROR'}, str(ex))
            return {'CANCELLED'}
        replacement.keep(context.scene, piece)
        width, height = piece.size()
        self.report({'INFO'}, "Stored a piece of {} and {} from {} ({:,.1f} x {:,.1f} m)".format(
            plural(piece.vertex_count, "vertex"), plural(piece.edge_count, "street"), piece.source, width, height))
        return {'FINISHED'}


class ROADS_OT_replace_isogroup(Operator):
    """Replace every non-overlapping occurrence of the isogroup chosen in the list by the stored piece, fitted inside each occurrence, and join each piece to the junctions where the streets around meet its occurrence"""

    bl_idname = "roads.replace_isogroup"
    bl_label = "Replace"
    bl_options = {'REGISTER', 'UNDO'}

    index: IntProperty(name="Isogroup", description="Place of the isogroup in the list, from 0 (-1: the active one)",
                       default=-1, min=-1)

    def execute(self, context):
        obj = graph_or_report(self, context)
        if obj is None:
            return {'CANCELLED'}
        ggg = analyzer_or_report(self)
        if ggg is None:
            return {'CANCELLED'}
        if not hasattr(ggg, "replace_isogroup"):
            self.report({'ERROR'}, "The native module {} cannot replace patterns (it lacks replace_isogroup); "
                        "rebuild it".format(getattr(ggg, "__file__", "ggg")))
            return {'CANCELLED'}
        result = obj.road_analysis
        if not result.has_result():
            self.report({'ERROR'}, "{} has not been analysed: run Analyze, then choose an isogroup in the list"
                        .format(obj.name))
            return {'CANCELLED'}
        index = isogroup_index_or_report(self, obj)
        if index is None:
            return {'CANCELLED'}
        item = result.isogroups[index]
        order = item.order
        try:
            piece = replacement.stored(context.scene)
            problem = piece.problem()
            if problem is not None:
                raise PieceError("Cannot replace with the stored piece: " + problem)
            highway = piece.highway_codes(ggg)
        except PieceError as ex:
            self.report({'ERROR'}, str(ex))
            return {'CANCELLED'}

        with graph_edit.object_mode(context, obj):
            with roads.Progress(context, read_share=0.9, label="Replacing patterns") as progress:
                try:
                    topology = analysis.MeshTopology(obj)
                    iso = analysis.live_isogroup(ggg, obj, index, topology, progress)
                    _occurrences, chosen, _edges = analysis.isogroup_arrays(obj, index)
                except StaleAnalysis as ex:
                    self.report({'ERROR'}, str(ex))
                    return {'CANCELLED'}
                except ggg.Cancelled:
                    self.report({'WARNING'}, "Replace was cancelled; nothing changed")
                    return {'CANCELLED'}
                except ggg.Error as ex:
                    self.report({'ERROR'}, "Cannot analyse {} again: {}".format(obj.name, ex))
                    return {'CANCELLED'}
                if len(chosen) == 0:
                    self.report({'ERROR'}, "Isogroup {} has no occurrence to replace".format(item.rank))
                    return {'CANCELLED'}
                old = graph_edit.MeshGraph(obj)
                try:
                    graph = old.graph(ggg)
                    out, report = ggg.replace_isogroup(graph, iso, piece.positions, piece.edges, edge_highway=highway,
                                                       occurrences=chosen)
                except ggg.Error as ex:
                    self.report({'ERROR'}, "Cannot replace the pattern in {}: {}".format(obj.name, ex))
                    return {'CANCELLED'}
                # The vertices not removed (those of no occurrence, and the occurrences'
                # junctions) come first, in their order; then the pieces and intersections.
                removed = replaced_vertices(len(old.positions), old.edges,
                                            np.asarray(iso.occurrences, dtype=np.int64)[chosen])
                kept = np.flatnonzero(~removed)
                if out.vertex_count != len(kept) + report["added_vertices"]:
                    self.report({'ERROR'}, "Cannot replace the pattern in {}: the library returned {:,} vertices, "
                                "not {:,}".format(obj.name, out.vertex_count, len(kept) + report["added_vertices"]))
                    return {'CANCELLED'}
                source = np.concatenate((kept, np.full(report["added_vertices"], -1, dtype=np.int64)))
                progress.step(0.0, "updating the mesh")
                written = graph_edit.Replacement(obj, old, out, {"source_vertex": source},
                                                 class_widths(context, ggg, out))
                road_objects.rewrite(written)
                # The ids of the analysis no longer mean the same vertices: forget it (and its
                # colours), so that the list cannot highlight other vertices. The isogroups in
                # memory stay: an undo brings back the analysis they belong to.
                patterns.clear(obj)
                analysis.clear(obj, forget_isogroups=False)
                progress.step(1.0, "done")

        crossings = report["intersections"]
        self.report({'INFO'}, "Replaced {} of the {}-vertex pattern in {}: {} removed, {:,} added, {} joined{}; "
                    "the analysis is cleared (analyse again)".format(
                        plural(report["replaced"], "occurrence"), order, obj.name,
                        plural(report["removed_vertices"], "vertex"), report["added_vertices"],
                        plural(report["joined_streets"], "street"),
                        ", {} made".format(plural(crossings, "intersection")) if crossings else ""))
        return {'FINISHED'}


classes = (ROADS_OT_store_replacement, ROADS_OT_replace_isogroup)
