"""Operators of the graph analyzer (paper 5, Figs. 13 and 17): find the places where a
selected piece of the road graph occurs again, analyse a whole road graph for the street
patterns that repeat (isogroups), and show them.

Analyze runs the native analysis in a worker thread (ggg.analyze releases the GIL; see
core/jobs.py and operators/jobs.py): from the UI the operator is modal (a timer shows the
progress in the status bar; Esc cancels); from scripts and in background mode it waits for
the thread, with the window manager's progress. Nothing in the scene changes before the analysis has finished,
so a failed or cancelled run leaves it as it was.
"""

import bpy
import numpy as np
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty
from bpy.types import Operator

from ..core.analysis import SCALE_ITEMS, SCALE_NAMES, StaleAnalysis, StoredAnalysis
from ..core.jobs import AnalysisJob
from ..core.palette import MATCH_SLOT, PALETTE_SIZE, SEED_SLOT
from ..core.text import plural
from ..core.topology import EdgeLookup, seed_problem
from ..core.updates import suspended_updates
from ..data import analysis, roads
from ..display import patterns
from ..properties.analysis import settings_properties
from .common import analyzer_or_report, constraint_parameters, draw_settings, graph_or_report, isogroup_index_or_report
from .jobs import ModalJobOperator

# Analyses running in the UI: object name -> AnalysisJob (for the panel, and so that one
# object is not analysed twice at once).
running = {}


# --- Find Similar ---------------------------------------------------------------------

class ROADS_OT_find_similar(Operator):
    """Find every place where the piece of road graph selected in Edit Mode occurs again: select and colour all its occurrences"""

    bl_idname = "roads.find_similar"
    bl_label = "Find Similar"
    bl_options = {'REGISTER', 'UNDO'}

    tolerance: FloatProperty(name="Tolerance", description="Largest vertex displacement of a match, relative to the "
                             "seed's size", default=0.2, min=0.0, soft_max=0.5, precision=3)
    scale: EnumProperty(name="Scale", description="How the size of a match may differ from the seed's",
                        items=SCALE_ITEMS, default='SIMILARITY')

    include_analysis_group: BoolProperty(
        name="As Analyze Groups", description="Also find every copy that Analyze groups with the selection (the "
        "analysis compares the copies with each other, not only with the selection); off: only the copies within "
        "the tolerance of the selection", default=True)

    _FROM_SETTINGS = ("tolerance", "scale")

    def invoke(self, context, event):
        settings = context.scene.road_analysis
        for name in self._FROM_SETTINGS:
            if not self.properties.is_property_set(name):
                setattr(self, name, getattr(settings, name))
        return self.execute(context)

    def execute(self, context):
        obj = graph_or_report(self, context)
        if obj is None:
            return {'CANCELLED'}
        ggg = analyzer_or_report(self)
        if ggg is None:
            return {'CANCELLED'}
        topology = analysis.MeshTopology(obj)
        seed = topology.selected_ids()
        problem = seed_problem(topology.edges, seed)
        if problem is not None:
            self.report({'ERROR'}, problem)
            return {'CANCELLED'}
        with roads.Progress(context, read_share=1.0, label="Finding similar") as progress:
            try:
                graph = topology.graph(ggg)
                # The scene's grid and cut: Find Similar finds at least what Analyze groups with the seed.
                settings = context.scene.road_analysis
                found = ggg.find_similar(graph, seed, tolerance=self.tolerance, scale=SCALE_NAMES[self.scale],
                                         grid=(settings.angle_cells, settings.distance_cells), cut=settings.cut,
                                         include_analysis_group=self.include_analysis_group, progress=progress)
            except ggg.Cancelled:
                self.report({'WARNING'}, "Find Similar was cancelled; nothing changed")
                return {'CANCELLED'}
            except ggg.Error as ex:
                self.report({'ERROR'}, "Cannot search {}: {}".format(obj.name, ex))
                return {'CANCELLED'}
            occurrences = np.asarray(found.occurrences, dtype=np.int64)
            try:
                lookup = EdgeLookup(topology.edges, topology.vertex_count)
                edge_ids = lookup.occurrence_edges(occurrences, found.pattern_edges)
            except KeyError as ex:
                self.report({'ERROR'}, "Cannot show the occurrences in {}: {}".format(obj.name, ex))
                return {'CANCELLED'}
            slots = np.zeros(len(topology.edges), dtype=np.int32)
            slots[edge_ids.ravel()] = MATCH_SLOT
            slots[edge_ids[:1].ravel()] = SEED_SLOT  # occurrence 0 is the seed
            mask = np.zeros(topology.vertex_count, dtype=bool)
            mask[occurrences.ravel()] = True
            patterns.write(obj, slots, mask, topology)

        count = len(occurrences)
        self.report({'INFO'}, "{} of the selected pattern ({}, {}): the seed and {} more, {} non-overlapping; "
                    "{} selected".format(plural(count, "occurrence"), plural(found.order, "vertex"),
                                         plural(found.edge_count, "edge"), "{:,}".format(count - 1),
                                         "{:,}".format(len(found.non_overlapping)),
                                         plural(int(mask.sum()), "vertex")))
        return {'FINISHED'}


# --- Analyze --------------------------------------------------------------------------

class ROADS_OT_analyze(ModalJobOperator, Operator):
    """Find the street patterns that repeat in the active road graph (isogroups), list them best first and colour the graph by them; Esc cancels"""

    bl_idname = "roads.analyze"
    bl_label = "Analyze"
    bl_options = {'REGISTER', 'UNDO'}

    __annotations__ = settings_properties()
    _FROM_SETTINGS = ("angle_cells", "distance_cells", "cut", "full", "max_order", "min_count", "scale", "tolerance",
                      "min_aspect", "min_leaves", "min_irregularity", "use_seed", "max_stored", "overview_count")
    _running = running
    _doing = "Analysing"
    _noun = "the analysis"
    _progress_label = "Analysing roads"
    _subject = "The analysis of {}"
    _cannot = "Cannot analyse {}"
    _result_noun = "the analysis"
    _changed = "{} changed during the analysis; analyse it again"

    def draw(self, context):
        draw_settings(self, ("cut", "full", "max_order", "min_count", "scale", "use_seed", "tolerance", "min_aspect",
                             "min_leaves", "min_irregularity", "max_stored", "overview_count"))

    def _settings(self, context):
        return context.scene.road_analysis

    # -- steps

    def _start(self, context):
        """Read the graph (main thread) and start the worker; False after an ERROR report."""
        obj = graph_or_report(self, context)
        if obj is None:
            return False
        ggg = analyzer_or_report(self)
        if ggg is None:
            return False
        if obj.name in running:
            self.report({'ERROR'}, "{} is being analysed already".format(obj.name))
            return False
        topology = analysis.MeshTopology(obj)
        options = {
            "grid": (self.angle_cells, self.distance_cells), "cut": self.cut, "full": self.full,
            "max_order": self.max_order, "min_count": self.min_count, "scale": SCALE_NAMES[self.scale],
            "tolerance": self.tolerance, "min_aspect": self.min_aspect, "min_leaves": self.min_leaves,
            "min_irregularity": self.min_irregularity,
        }
        if self.use_seed:
            seed = topology.selected_ids()
            problem = seed_problem(topology.edges, seed)
            if problem is not None:
                self.report({'ERROR'}, "Selection as seed: " + problem)
                return False
            options["seed"] = seed
        if len(topology.edges) == 0:
            self.report({'ERROR'}, "{} has no edges to analyse".format(obj.name))
            return False
        try:
            graph = topology.graph(ggg)
        except ggg.Error as ex:
            self.report({'ERROR'}, "Cannot analyse {}: {}".format(obj.name, ex))
            return False
        self._ggg = ggg
        self._object_name = obj.name
        self._topology = topology
        self._options = options
        self._job = AnalysisJob(ggg, graph, options)
        self._job.start()
        return True

    def _keep(self, context, obj, topology):
        """Store and show the result of the finished job (main thread)."""
        job, name = self._job, self._object_name
        result = job.result
        groups = result.isogroups  # a new list on every access: read once
        try:
            stored = StoredAnalysis(result, groups, self.max_stored, self.overview_count)
        except ValueError as ex:
            self.report({'ERROR'}, "Cannot keep the analysis of {}: {}".format(name, ex))
            return {'CANCELLED'}
        if obj.mode == 'EDIT':
            # The results live on the object: leave Edit Mode, so that they are one
            # (global) undo step with the colours.
            with context.temp_override(active_object=obj, object=obj, edit_object=obj):
                bpy.ops.object.mode_set(mode='OBJECT')
        kept = analysis.store(obj, stored, topology, job.seconds, self._parameters(), "seed" in self._options,
                              self._options)
        # The isogroups themselves (with their transforms), for Replace; from the vertices
        # that were analysed.
        analysis.remember(obj, self._topology, groups[:kept])
        shown = patterns.show_overview(obj, self.overview_count)
        self.report({'INFO'}, self._summary(obj, result, groups, kept, shown, job.seconds))
        if stored.stopped_by_budget:
            self.report({'WARNING'}, "The analysis of {} stopped early: the next order would hold too many "
                        "occurrences (lower Max Order or raise Min Count)".format(name))
        return {'FINISHED'}

    def _parameters(self):
        parts = ["grid {}x{}".format(self.angle_cells, self.distance_cells),
                 "full" if self.full else "cut {:g}".format(self.cut),
                 "max order {}".format(self.max_order) if self.max_order else "no max order",
                 "min count {}".format(self.min_count), SCALE_NAMES[self.scale]]
        if "seed" in self._options:
            parts.append("seed of {}, tolerance {:g}".format(plural(len(self._options["seed"]), "vertex"),
                                                             self.tolerance))
        return ", ".join(parts + constraint_parameters(self))

    def _summary(self, obj, result, groups, kept, shown, seconds):
        if not groups:
            return "Analysed {} in {:.2f} s: no pattern repeats ({} found before the constraints)".format(
                obj.name, seconds, result.detected)
        best = groups[0]
        text = "Analysed {} in {:.2f} s: {} (best: {}, {}, {} non-overlapping)".format(
            obj.name, seconds, plural(len(groups), "isogroup"), plural(best.order, "vertex"),
            plural(best.frequency, "occurrence"), "{:,}".format(len(best.non_overlapping)))
        if kept < len(groups):
            text += "; the best {:,} kept".format(kept)
        return text + "; {} coloured".format(plural(shown, "occurrence"))



# --- showing stored results ---------------------------------------------------------------

def _analysed_or_report(op, context):
    obj = graph_or_report(op, context)
    if obj is None:
        return None
    if not obj.road_analysis.has_result():
        op.report({'ERROR'}, "{} has not been analysed: run Analyze first".format(obj.name))
        return None
    return obj


class ROADS_OT_select_isogroup(Operator):
    """Select the vertices of every occurrence of an isogroup of the last analysis and colour them"""

    bl_idname = "roads.select_isogroup"
    bl_label = "Select Occurrences"
    bl_options = {'REGISTER', 'UNDO'}

    index: IntProperty(name="Isogroup", description="Place of the isogroup in the list, from 0 (-1: the active one)",
                       default=-1, min=-1)
    only_non_overlapping: BoolProperty(name="Only Non-Overlapping",
                                       description="Only the largest set of occurrences that share no vertex",
                                       default=False)

    def execute(self, context):
        obj = _analysed_or_report(self, context)
        if obj is None:
            return {'CANCELLED'}
        result = obj.road_analysis
        index = isogroup_index_or_report(self, obj)
        if index is None:
            return {'CANCELLED'}
        try:
            shown, selected = patterns.show_isogroup(obj, index, select=True,
                                                     only_non_overlapping=self.only_non_overlapping)
        except (StaleAnalysis, KeyError) as ex:
            self.report({'ERROR'}, str(ex))
            return {'CANCELLED'}
        with suspended_updates():
            result.active_index = index
        item = result.isogroups[index]
        self.report({'INFO'}, "Isogroup {} ({}, {}): {} shown, {} selected".format(
            item.rank, plural(item.order, "vertex"), plural(item.edge_count, "edge"),
            plural(shown, "occurrence"), plural(selected, "vertex")))
        return {'FINISHED'}


class ROADS_OT_show_patterns(Operator):
    """Colour the road graph by isogroup: the non-overlapping occurrences of each of the best isogroups in its own colour"""

    bl_idname = "roads.show_patterns"
    bl_label = "Show Overview"
    bl_options = {'REGISTER', 'UNDO'}

    count: IntProperty(name="Colours", description="Isogroups to colour, the best first",
                       default=PALETTE_SIZE, min=1, max=PALETTE_SIZE)

    def execute(self, context):
        obj = _analysed_or_report(self, context)
        if obj is None:
            return {'CANCELLED'}
        try:
            shown = patterns.show_overview(obj, self.count)
        except (StaleAnalysis, KeyError) as ex:
            self.report({'ERROR'}, str(ex))
            return {'CANCELLED'}
        self.report({'INFO'}, "{}: {} coloured".format(obj.name, plural(shown, "occurrence")))
        return {'FINISHED'}


class ROADS_OT_clear_patterns(Operator):
    """Remove the pattern colours from the active road graph"""

    bl_idname = "roads.clear_patterns"
    bl_label = "Clear Colours"
    bl_options = {'REGISTER', 'UNDO'}

    forget: BoolProperty(name="Forget Analysis", description="Also remove the stored isogroups", default=False)

    def execute(self, context):
        obj = graph_or_report(self, context)
        if obj is None:
            return {'CANCELLED'}
        patterns.clear(obj)
        if self.forget:
            analysis.clear(obj)
        else:
            with suspended_updates():
                obj.road_analysis.active_index = -1
        self.report({'INFO'}, "Cleared the pattern colours{} of {}".format(
            " and the analysis" if self.forget else "", obj.name))
        return {'FINISHED'}


classes = (ROADS_OT_find_similar, ROADS_OT_analyze, ROADS_OT_select_isogroup, ROADS_OT_show_patterns,
           ROADS_OT_clear_patterns)
