"""Operators of the graph analyzer (paper 5, Figs. 13 and 17): find the places where a
selected piece of the road graph occurs again, analyse a whole road graph for the street
patterns that repeat (isogroups), and show them.

Analyze runs the native analysis in a worker thread (ggg.analyze releases the GIL; see
jobs.py): from the UI the operator is modal (a timer shows the progress in the status bar;
Esc cancels); from scripts and in background mode it waits for the thread, with the
window manager's progress. Nothing in the scene changes before the analysis has finished,
so a failed or cancelled run leaves it as it was.
"""

import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty
from bpy.types import Operator

import numpy as np

from . import analysis, importer, jobs, native, pattern_display

# Analyses running in the UI: object name -> AnalysisJob (for the panel, and so that one
# object is not analysed twice at once).
running = {}


def stop_all():
    """Cancel the analyses running in the UI and wait for their threads (the add-on is
    being disabled)."""
    jobs.stop_all(running)


def _plural(count, word):
    if count == 1:
        return "1 " + word
    plural = word[:-len("vertex")] + "vertices" if word.endswith("vertex") else word + "s"
    return "{:,} {}".format(count, plural)


def analyzer_or_report(op):
    """The module ggg with the analyzer, or None after an ERROR report."""
    ggg = native.load_or_report(op)
    if ggg is None:
        return None
    missing = [name for name in ("analyze", "find_similar", "Cancelled", "UsageError") if not hasattr(ggg, name)]
    if missing:
        op.report({'ERROR'}, "The native module {} has no analyzer (it lacks {}); rebuild it".format(
            getattr(ggg, "__file__", "ggg"), ", ".join(missing)))
        return None
    return ggg


def graph_or_report(op, context):
    """The road graph object of the active object, or None after an ERROR report."""
    obj = importer.road_graph_object(context.active_object)
    if obj is None or obj.type != 'MESH':
        op.report({'ERROR'}, "Select a road graph (import OpenStreetMap roads first); the active object is {}"
                  .format("'{}', not a road graph".format(context.active_object.name)
                          if context.active_object is not None else "none"))
        return None
    return obj


def draw_settings(op, names):
    """The redo panel of Analyze or Learn ``op``: the grid on one row, then the properties
    ``names``."""
    layout = op.layout
    layout.use_property_split = True
    layout.use_property_decorate = False
    row = layout.row(align=True)
    row.prop(op, "angle_cells", text="Grid")
    row.prop(op, "distance_cells", text="")
    for name in names:
        layout.prop(op, name)


def constraint_parameters(op):
    """The constraints of Analyze or Learn ``op`` that are set, as parts of its parameters text."""
    parts = []
    if op.min_aspect > 0:
        parts.append("min aspect {:g}".format(op.min_aspect))
    if op.min_leaves > 0:
        parts.append("min leaves {}".format(op.min_leaves))
    if op.min_irregularity > 0:
        parts.append("min irregularity {:g}\u00b0".format(op.min_irregularity))
    return parts


# --- Find Similar ---------------------------------------------------------------------

class ROADS_OT_find_similar(Operator):
    """Find every place where the piece of road graph selected in Edit Mode occurs again: select and colour all its occurrences"""

    bl_idname = "roads.find_similar"
    bl_label = "Find Similar"
    bl_options = {'REGISTER', 'UNDO'}

    tolerance: FloatProperty(name="Tolerance", description="Largest vertex displacement of a match, relative to the "
                             "seed's size", default=0.15, min=0.0, soft_max=0.5, precision=3)
    scale: EnumProperty(name="Scale", description="How the size of a match may differ from the seed's",
                        items=analysis.SCALE_ITEMS, default='SIMILARITY')

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
        problem = analysis.seed_problem(topology.edges, seed)
        if problem is not None:
            self.report({'ERROR'}, problem)
            return {'CANCELLED'}
        with importer.Progress(context, read_share=1.0, label="Finding similar") as progress:
            try:
                graph = topology.graph(ggg)
                found = ggg.find_similar(graph, seed, tolerance=self.tolerance,
                                         scale=analysis.SCALE_NAMES[self.scale], progress=progress)
            except ggg.Cancelled:
                self.report({'WARNING'}, "Find Similar was cancelled; nothing changed")
                return {'CANCELLED'}
            except ggg.Error as ex:
                self.report({'ERROR'}, "Cannot search {}: {}".format(obj.name, ex))
                return {'CANCELLED'}
            occurrences = np.asarray(found.occurrences, dtype=np.int64)
            try:
                lookup = pattern_display.EdgeLookup(topology.edges, topology.vertex_count)
                edge_ids = lookup.occurrence_edges(occurrences, found.pattern_edges)
            except KeyError as ex:
                self.report({'ERROR'}, "Cannot show the occurrences in {}: {}".format(obj.name, ex))
                return {'CANCELLED'}
            slots = np.zeros(len(topology.edges), dtype=np.int32)
            slots[edge_ids.ravel()] = pattern_display.MATCH_SLOT
            slots[edge_ids[:1].ravel()] = pattern_display.SEED_SLOT  # occurrence 0 is the seed
            mask = np.zeros(topology.vertex_count, dtype=bool)
            mask[occurrences.ravel()] = True
            pattern_display.write(obj, slots, mask, topology)

        count = len(occurrences)
        self.report({'INFO'}, "{} of the selected pattern ({}, {}): the seed and {} more, {} non-overlapping; "
                    "{} selected".format(_plural(count, "occurrence"), _plural(found.order, "vertex"),
                                         _plural(found.edge_count, "edge"), "{:,}".format(count - 1),
                                         "{:,}".format(len(found.non_overlapping)),
                                         _plural(int(mask.sum()), "vertex")))
        return {'FINISHED'}


# --- Analyze --------------------------------------------------------------------------

class AnalysisJob(jobs.NativeJob):
    """One run of ggg.analyze in a worker thread (see jobs.NativeJob)."""

    thread_name = "road_grammar analyze"

    def _call(self, ggg, graph, options):
        return ggg.analyze(graph, progress=self, **options)


class ROADS_OT_analyze(jobs.ModalJobOperator, Operator):
    """Find the street patterns that repeat in the active road graph (isogroups), list them best first and colour the graph by them; Esc cancels"""

    bl_idname = "roads.analyze"
    bl_label = "Analyze"
    bl_options = {'REGISTER', 'UNDO'}

    __annotations__ = analysis.settings_properties()
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
            "max_order": self.max_order, "min_count": self.min_count, "scale": analysis.SCALE_NAMES[self.scale],
            "tolerance": self.tolerance, "min_aspect": self.min_aspect, "min_leaves": self.min_leaves,
            "min_irregularity": self.min_irregularity,
        }
        if self.use_seed:
            seed = topology.selected_ids()
            problem = analysis.seed_problem(topology.edges, seed)
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
            stored = analysis.StoredAnalysis(result, groups, self.max_stored, self.overview_count)
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
        shown = analysis.show_overview(obj, self.overview_count)
        self.report({'INFO'}, self._summary(obj, result, groups, kept, shown, job.seconds))
        if stored.stopped_by_budget:
            self.report({'WARNING'}, "The analysis of {} stopped early: the next order would hold too many "
                        "occurrences (lower Max Order or raise Min Count)".format(name))
        return {'FINISHED'}

    def _parameters(self):
        parts = ["grid {}x{}".format(self.angle_cells, self.distance_cells),
                 "full" if self.full else "cut {:g}".format(self.cut),
                 "max order {}".format(self.max_order) if self.max_order else "no max order",
                 "min count {}".format(self.min_count), analysis.SCALE_NAMES[self.scale]]
        if "seed" in self._options:
            parts.append("seed of {}, tolerance {:g}".format(_plural(len(self._options["seed"]), "vertex"),
                                                             self.tolerance))
        return ", ".join(parts + constraint_parameters(self))

    def _summary(self, obj, result, groups, kept, shown, seconds):
        if not groups:
            return "Analysed {} in {:.2f} s: no pattern repeats ({} found before the constraints)".format(
                obj.name, seconds, result.detected)
        best = groups[0]
        text = "Analysed {} in {:.2f} s: {} (best: {}, {}, {} non-overlapping)".format(
            obj.name, seconds, _plural(len(groups), "isogroup"), _plural(best.order, "vertex"),
            _plural(best.frequency, "occurrence"), "{:,}".format(len(best.non_overlapping)))
        if kept < len(groups):
            text += "; the best {:,} kept".format(kept)
        return text + "; {} coloured".format(_plural(shown, "occurrence"))



# --- showing stored results ---------------------------------------------------------------

def _analysed_or_report(op, context):
    obj = graph_or_report(op, context)
    if obj is None:
        return None
    if not obj.road_analysis.has_result():
        op.report({'ERROR'}, "{} has not been analysed: run Analyze first".format(obj.name))
        return None
    return obj


def isogroup_index_or_report(op, obj):
    """The place in the list of the analysis of ``obj`` of the isogroup ``op.index`` (-1:
    the active one), or None after an ERROR report."""
    isogroups = obj.road_analysis.isogroups
    index = obj.road_analysis.active_index if op.index < 0 else op.index
    if not 0 <= index < len(isogroups):
        op.report({'ERROR'}, "Choose an isogroup in the list first" if op.index < 0 else
                  "{} has {}: there is no isogroup {}".format(obj.name, _plural(len(isogroups), "isogroup"), index))
        return None
    return index


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
            shown, selected = analysis.show_isogroup(obj, index, select=True,
                                                     only_non_overlapping=self.only_non_overlapping)
        except (analysis.StaleAnalysis, KeyError) as ex:
            self.report({'ERROR'}, str(ex))
            return {'CANCELLED'}
        with pattern_display.suspended_updates():
            result.active_index = index
        item = result.isogroups[index]
        self.report({'INFO'}, "Isogroup {} ({}, {}): {} shown, {} selected".format(
            item.rank, _plural(item.order, "vertex"), _plural(item.edge_count, "edge"),
            _plural(shown, "occurrence"), _plural(selected, "vertex")))
        return {'FINISHED'}


class ROADS_OT_show_patterns(Operator):
    """Colour the road graph by isogroup: the non-overlapping occurrences of each of the best isogroups in its own colour"""

    bl_idname = "roads.show_patterns"
    bl_label = "Show Overview"
    bl_options = {'REGISTER', 'UNDO'}

    count: IntProperty(name="Colours", description="Isogroups to colour, the best first",
                       default=pattern_display.PALETTE_SIZE, min=1, max=pattern_display.PALETTE_SIZE)

    def execute(self, context):
        obj = _analysed_or_report(self, context)
        if obj is None:
            return {'CANCELLED'}
        try:
            shown = analysis.show_overview(obj, self.count)
        except (analysis.StaleAnalysis, KeyError) as ex:
            self.report({'ERROR'}, str(ex))
            return {'CANCELLED'}
        self.report({'INFO'}, "{}: {} coloured".format(obj.name, _plural(shown, "occurrence")))
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
        pattern_display.clear(obj)
        if self.forget:
            analysis.clear(obj)
        else:
            with pattern_display.suspended_updates():
                obj.road_analysis.active_index = -1
        self.report({'INFO'}, "Cleared the pattern colours{} of {}".format(
            " and the analysis" if self.forget else "", obj.name))
        return {'FINISHED'}
