"""Operators of grammar learning (inverse procedural modelling, paper 6): learn a grammar of
the active road graph, and show the graph encoded to one level of it, coloured by rule
(paper Fig. 13).

Learn runs ggg.learn in a worker thread (it releases the GIL; see core/jobs.py): from the UI
the operator is modal (progress in the status bar, Esc cancels); from scripts and in
background mode it waits for the thread. Nothing in the scene changes before the
learning has finished, so a failed or cancelled run leaves it as it was. A finished run is
one undo step: the grammar's Text, the result on the graph object and its rules object.
"""

import bpy
from bpy.props import IntProperty
from bpy.types import Operator

from ..core import native
from ..core.jobs import LearningJob
from ..core.levels import DisplayError
from ..core.text import learned_summary, plural
from ..core.topology import seed_problem
from ..core.updates import suspended_updates
from ..data import analysis, learning
from ..display import rules
from ..properties.learning import settings_properties
from .common import constraint_parameters, draw_settings, graph_or_report
from .jobs import ModalJobOperator

# Learning runs in the UI: object name -> LearningJob (for the panel, and so that one
# object is not learned from twice at once).
running = {}


def learner_or_report(op):
    """The module ggg with grammar learning, or None after an ERROR report."""
    ggg = native.load_or_report(op)
    if ggg is None:
        return None
    missing = [name for name in ("learn", "decode", "encoded_graph", "parse_grammar", "Cancelled")
               if not hasattr(ggg, name)]
    if missing:
        op.report({'ERROR'}, "The native module {} cannot learn grammars (it lacks {}); rebuild it".format(
            getattr(ggg, "__file__", "ggg"), ", ".join(missing)))
        return None
    return ggg


class ROADS_OT_learn(ModalJobOperator, Operator):
    """Learn a grammar of the active road graph (its repeated street patterns become rules, level by level); it becomes the scene's grammar. Esc cancels"""

    bl_idname = "roads.learn"
    bl_label = "Learn"
    bl_options = {'REGISTER', 'UNDO'}

    __annotations__ = settings_properties(options={'SKIP_SAVE'})
    _FROM_SETTINGS = ("angle_cells", "distance_cells", "cut", "max_order", "levels", "complete", "mode", "min_aspect",
                      "min_leaves", "min_irregularity", "use_seed")
    _running = running
    _doing = "Learning from"
    _noun = "the learning"
    _progress_label = "Learning a grammar"
    _subject = "Learning from {}"
    _cannot = "Cannot learn from {}"
    _result_noun = "the grammar"
    _changed = "{} changed while it was learned from; learn again"

    def draw(self, context):
        draw_settings(self, ("cut", "max_order", "levels", "complete", "mode", "min_aspect", "min_leaves",
                                          "min_irregularity", "use_seed"))

    def _settings(self, context):
        return context.scene.road_learning

    # -- steps

    def _start(self, context):
        """Read the graph (main thread) and start the worker; False after an ERROR report."""
        obj = graph_or_report(self, context)
        if obj is None:
            return False
        ggg = learner_or_report(self)
        if ggg is None:
            return False
        if obj.name in running:
            self.report({'ERROR'}, "{} is being learned from already".format(obj.name))
            return False
        topology = analysis.MeshTopology(obj, with_classes=True)
        if len(topology.edges) == 0:
            self.report({'ERROR'}, "{} has no edges to learn from".format(obj.name))
            return False
        options = self._options()
        if self.use_seed:
            seed = topology.selected_ids()
            problem = seed_problem(topology.edges, seed)
            if problem is not None:
                self.report({'ERROR'}, "Selection as first rule: " + problem)
                return False
            options["seed"] = seed
        try:
            graph = topology.graph(ggg)
        except ggg.Error as ex:
            self.report({'ERROR'}, "Cannot learn from {}: {}".format(obj.name, ex))
            return False
        self._ggg = ggg
        self._object_name = obj.name
        self._topology = topology
        self._job = LearningJob(ggg, graph, options)
        self._job.start()
        return True

    def _options(self):
        return {
            "lossless": self.mode == 'LOSSLESS', "levels": self.levels, "complete": self.complete,
            "grid": (self.angle_cells, self.distance_cells), "cut": self.cut, "max_order": self.max_order,
            "min_aspect": self.min_aspect, "min_leaves": self.min_leaves, "min_irregularity": self.min_irregularity,
        }

    def _keep(self, context, obj, topology):
        """Keep and show the grammar of the finished job (main thread)."""
        ggg, job, name = self._ggg, self._job, self._object_name
        learned, stats = job.result
        try:
            content = learned.to_json()
            parsed = ggg.parse_grammar(content, name)  # what the Text will hold must read back
        except ggg.Error as ex:
            self.report({'ERROR'}, "The grammar learned from {} does not read back: {}".format(name, ex))
            return {'CANCELLED'}
        if obj.mode == 'EDIT':
            # The result lives on the object: leave Edit Mode, so that it is one (global)
            # undo step with the grammar's text.
            with context.temp_override(active_object=obj, object=obj, edit_object=obj):
                bpy.ops.object.mode_set(mode='OBJECT')
        text = learning.store(context, obj, parsed, content, stats, self._parameters(), job.seconds, topology)
        self.report({'INFO'}, learned_summary(name, stats, job.seconds) + "; kept in the text '{}'".format(text.name))
        if not stats.get("roundtrip", {}).get("edges_equal", True):
            self.report({'WARNING'}, "The grammar of {} does not decode to the same streets".format(name))
        if not parsed.rules:
            self.report({'WARNING'}, "No pattern of {} repeats under these settings: the grammar is the graph itself "
                        "(its axiom)".format(name))
        try:
            rules.show_learned(obj)
        except (DisplayError, native.NativeModuleError) as ex:
            self.report({'WARNING'}, "The grammar is kept, but its levels cannot be shown: {}".format(ex))
        return {'FINISHED'}

    def _parameters(self):
        parts = ["grid {}x{}".format(self.angle_cells, self.distance_cells), "cut {:g}".format(self.cut),
                 "max order {}".format(self.max_order),
                 plural(self.levels, "level") if self.levels else "all levels",
                 "complete" if self.complete else None,
                 "lossless" if self.mode == 'LOSSLESS' else "paper"]
        return ", ".join([p for p in parts if p] + constraint_parameters(self))


def _learned_or_report(op, context):
    obj = graph_or_report(op, context)
    if obj is None:
        return None
    if not obj.road_learning.has_result():
        op.report({'ERROR'}, "{} has no learned grammar: run Learn first".format(obj.name))
        return None
    return obj


class ROADS_OT_show_level(Operator):
    """Show the active road graph encoded to one level of its learned grammar, each street coloured by the rule whose instance holds it"""

    bl_idname = "roads.show_level"
    bl_label = "Show Level"
    bl_options = {'REGISTER', 'UNDO'}

    level: IntProperty(name="Level", description="Level to show (0 = the decoded streets, the highest = the axiom; "
                       "-1: the one shown)", default=-1, min=-1)
    rule: IntProperty(name="Rule", description="Place of the rule to highlight in the list, from 0 (-1: every rule "
                      "in its colour)", default=-1, min=-1)

    def execute(self, context):
        obj = _learned_or_report(self, context)
        if obj is None:
            return {'CANCELLED'}
        result = obj.road_learning
        if self.level > result.levels:
            self.report({'ERROR'}, "The grammar of {} has levels 0 to {}: there is no level {}".format(
                obj.name, result.levels, self.level))
            return {'CANCELLED'}
        if self.rule >= len(result.rules):
            self.report({'ERROR'}, "The grammar of {} has {}: there is no rule {}".format(
                obj.name, plural(len(result.rules), "rule"), self.rule))
            return {'CANCELLED'}
        before = result.level, result.active_rule
        with suspended_updates():
            if self.level >= 0:
                result.level = self.level
            result.active_rule = self.rule
        try:
            view = rules.show_learned(obj)
        except (DisplayError, native.NativeModuleError) as ex:
            with suspended_updates():
                result.level, result.active_rule = before
            self.report({'ERROR'}, str(ex))
            return {'CANCELLED'}
        counts = view.counts()
        shown = ", ".join("{} {}".format(view.rule_names.get(symbol, symbol), instances)
                          for symbol, (instances, _streets) in counts.items())
        self.report({'INFO'}, "{}: level {} of {}, {} of {}{}".format(
            obj.name, view.level, result.levels, plural(sum(i for i, _ in counts.values()), "instance"),
            plural(len(counts), "rule"), " ({})".format(shown) if shown else ""))
        return {'FINISHED'}


classes = (ROADS_OT_learn, ROADS_OT_show_level)
