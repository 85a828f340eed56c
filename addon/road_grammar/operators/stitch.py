"""Stitch Cities (paper Fig. 18): two road graphs side by side, each with its own grammar,
joined by growing the gap between them with the rules of both.

roads.stitch_cities joins the other selected road graph into the active one (its vertices
brought into the active object's frame, every edge attribute kept), grows the region with
the active city's grammar (seed), then again with the other city's (seed + 1) from the
streets that reach the region, the first city's new ones among them, so that growth from
both sides meets, continues the main roads of both cities through the grown streets
(ggg.continue_hierarchy), writes the result into the active object (graph_edit.Replacement, as
Grow into Region does) and removes the other graph object with its surface and displays.

It runs as a job (operators.jobs.ModalJobOperator): the objects and grammars are read on
the main thread, the stitch itself (core.stitching.stitch) runs in a worker thread, modal
from the UI (progress in the status bar, Esc cancels), waited for from scripts. Everything
is computed before the first change: an error or Esc leaves the scene as it was.
"""

import bpy
import numpy as np
from bpy.props import StringProperty
from bpy.types import Operator

from ..core import native
from ..core.jobs import StepsJob
from ..core.names import RULE_GRAMMARS_KEY
from ..core.stitching import City, stitch
from ..core.text import plural, rejections, tries
from ..data import graph_edit, roads, texts
from ..display import road_objects
from ..properties import grammar
from .common import class_widths
from .jobs import ModalJobOperator
from .region import GrowSettings, changed_since, read_columns, region_object, region_polygon

# Stitches running in the UI: active object name -> StepsJob (for the panel, and so that one
# graph is not stitched twice at once).
running = {}


class ROADS_OT_stitch_cities(GrowSettings, ModalJobOperator, Operator):
    """Stitch two road graphs (the active one and one other selected): join the other into the active one and grow the region between them with the grammar of each; Esc cancels"""

    bl_idname = "roads.stitch_cities"
    bl_label = "Stitch Cities"
    bl_options = {'REGISTER', 'UNDO'}

    other: StringProperty(
        name="Other City",
        description="Name of the road graph joined into the active one (empty: the other selected road graph)",
        options={'SKIP_SAVE'},
    )
    region: StringProperty(
        name="Region",
        description="Name of the curve or mesh object to fill (empty: the Region of the Grammar panel, else the "
        "selected curve or mesh that is not a road graph)",
        options={'SKIP_SAVE'},
    )
    share: grammar.share_property()
    seed: grammar.seed_property()
    max_placements: grammar.max_placements_property()
    max_vertices: grammar.region_max_vertices_property()
    patience: grammar.patience_property()
    use_placed_rules: grammar.use_placed_property()
    roundabouts: grammar.roundabouts_property()

    _FROM_SETTINGS = {"share": "stitch_share", "seed": "region_seed", "max_placements": "region_max_placements",
                      "max_vertices": "region_max_vertices", "patience": "region_patience",
                      "use_placed_rules": "region_use_placed", "roundabouts": "region_roundabouts"}

    _OBJECTS = ("other", "region")
    _running = running
    _doing = "Stitching"
    _noun = "the stitch"
    _subject = "Stitching {}"
    _cannot = "Cannot stitch {}"
    _result_noun = "the stitch"
    _changed = "{} changed during the stitch; stitch again"
    _progress_label = "Stitching"

    # Set up by _start.
    _names = ("", "", "")
    _other_topology = None
    _loops = 1
    _without_second = False

    # --- what to stitch ------------------------------------------------------------------

    def _cities(self, context):
        """(active graph, other graph) or None after an ERROR report."""
        active, others = roads.selected_graphs(context, self.other)
        if active is None:
            self.report({'ERROR'}, "Stitch Cities needs two road graphs: select the other one, then the one to keep "
                        "(active)")
            return None
        if self.other and not others:
            self.report({'ERROR'}, "'{}' is not another road graph to stitch to {}".format(self.other, active.name))
            return None
        if len(others) != 1:
            if not others:
                self.report({'ERROR'}, "Stitch Cities needs two road graphs: only {} is selected (select the other "
                            "city too)".format(active.name))
            else:
                self.report({'ERROR'}, "Stitch Cities joins two road graphs, {} are selected ({}): select one "
                            "besides the active {}".format(len(others) + 1, ", ".join(sorted(o.name for o in others)),
                                                           active.name))
            return None
        other = others[0]
        if context.view_layer.objects.get(other.name) != other:
            self.report({'ERROR'}, "The road graph {} is not in the view layer".format(other.name))
            return None
        return active, other

    def _grammars(self, context, active, other):
        """((Text, Grammar) of the active city, (Text, Grammar) of the other or None), or
        None after an ERROR report; a warning when the other city has none."""
        text_a = texts.city_grammar_text(context, active, True)
        if text_a is None:
            self.report({'ERROR'}, "No grammar for {}: learn it (Roads sidebar > Learn) or load one into the scene"
                        .format(active.name))
            return None
        text_b = texts.city_grammar_text(context, other, False)
        try:
            first = texts.of_text(text_a)
            second = texts.of_text(text_b) if text_b is not None else None
        except (texts.GrammarUnavailable, native.NativeModuleError) as ex:
            self.report({'ERROR'}, str(ex))
            return None
        return first, second

    # --- running -------------------------------------------------------------------------

    def _start(self, context):
        """Read both cities, their grammars and the region (main thread) and start the worker;
        False after an ERROR report."""
        ggg = native.load_or_report(self)
        if ggg is None:
            return False
        cities = self._cities(context)
        if cities is None:
            return False
        active, other = cities
        if active.name in running:
            self.report({'ERROR'}, "{} is being stitched already".format(active.name))
            return False
        grammars = self._grammars(context, active, other)
        if grammars is None:
            return False
        (text_a, parsed_a), second = grammars
        text_b, parsed_b = second if second is not None else (None, None)
        region_obj = region_object(self, context, (active, other))
        read = region_polygon(self, context, region_obj, active, "Cannot stitch into")
        if read is None:
            return False
        polygon, self._loops = read
        # The redo panel stitches the same objects.
        self.region, self.other = region_obj.name, other.name
        self._names = (active.name, other.name, region_obj.name)
        self._without_second = second is None
        self._progress_label = "Stitching {} and {}".format(active.name, other.name)

        old_a, self._topology = read_columns(context, active)
        old_b, self._other_topology = read_columns(context, other)
        matrix = np.array(active.matrix_world.inverted() @ other.matrix_world, dtype=np.float64)
        # Which grammar each nonterminal comes from: Place Rule's note, else its city's.
        name_b = text_b.name if text_b is not None else None
        first = City(old_a, text_a.name, parsed_a, graph_edit.noted_grammars(active, old_a, text_a.name))
        second_city = City(old_b, name_b, parsed_b, graph_edit.noted_grammars(other, old_b, name_b or ""))
        options = dict(seed=self.seed, share=self.share, max_placements=self.max_placements,
                       max_vertices=self.max_vertices, patience=self.patience,
                       use_placed_rules=self.use_placed_rules, roundabouts=self.roundabouts)
        self._ggg, self._object_name = ggg, active.name
        self._job = StepsJob(ggg, lambda job: stitch(job, ggg, first, second_city, matrix, polygon, **options),
                             "road_grammar stitch")
        self._job.start()
        return True

    def _report_error(self, error):
        name_a, name_b, region_name = self._names
        if isinstance(error, self._ggg.Error):
            hint = " (or turn off Use Placed Rules)" if isinstance(error, self._ggg.UsageError) and \
                self.use_placed_rules else ""
            self.report({'ERROR'}, "Cannot stitch {} and {} into {}: {}{}".format(name_a, name_b, region_name, error,
                                                                                 hint))
        else:
            super()._report_error(error)

    def _gone(self, context):
        name_a, name_b, region_name = self._names
        if region_name not in bpy.data.objects:
            return "The region {} is gone; the stitch is not kept".format(region_name)
        if changed_since(bpy.data.objects.get(name_a), self._topology):
            return self._changed.format(name_a)
        if changed_since(bpy.data.objects.get(name_b), self._other_topology):
            return self._changed.format(name_b)
        return None

    def _keep(self, context, active, _topology):
        """Write the stitched graph into the active city, remove the other (main thread) and
        report."""
        name_a, name_b, region_name = self._names
        other = bpy.data.objects[name_b]
        done = self._job.result
        reports = done.reports
        if done.result is None:
            self.report({'WARNING'}, "Nothing grew in {} between {} and {}: no rule fits there ({}: {}). The "
                        "scene is unchanged.".format(region_name, name_a, name_b, tries(reports[0]["attempts"]),
                                                     rejections(reports[0])))
            return {'CANCELLED'}
        with graph_edit.object_mode(context, active):
            replacement = graph_edit.Replacement(active, done.old, done.result, {"source_vertex": done.source},
                                                 class_widths(context, self._ggg, done.result))
            road_objects.rewrite(replacement)
            if done.names:
                active[RULE_GRAMMARS_KEY] = done.names
            elif RULE_GRAMMARS_KEY in active:
                del active[RULE_GRAMMARS_KEY]
            roads.remove_graph_object(other)
            active.select_set(True)
            context.view_layer.objects.active = active

        if self._without_second:
            self.report({'WARNING'}, "{} has no grammar (learn it first): the gap grew with {}'s rules only".format(
                name_b, name_a))
        if self._loops > 1:
            self.report({'WARNING'}, "{} has {} outlines: grew into the largest".format(region_name, self._loops))
        if done.left:
            self.report({'WARNING'}, "{} did not fit into {} and {} left as {}".format(
                plural(done.left, "placed rule"), region_name, "is" if done.left == 1 else "are",
                "it was" if done.left == 1 else "they were"))
        counts = {"passes": reports, "traced": done.traced, "added_vertices": done.added_vertices,
                  "added_edges": done.added_edges, "from_a": done.from_a, "from_b": done.from_b,
                  "placed": done.placed, "hierarchy": done.hierarchy}
        budget = any(report["stopped_by_budget"] for report in reports)
        self.report({'WARNING'} if budget else {'INFO'}, self._summary(name_a, name_b, region_name, counts))
        return {'FINISHED'}

    def _summary(self, name_a, name_b, region_name, counts):
        passes = counts["passes"]
        rules_b = passes[1]["placements"] if len(passes) > 1 else 0
        parts = ["Stitched {} and {} in {}: {} of {}, {} of {}, {}, {} new streets, {} from {}'s streets, {} from "
                 "{}'s".format(name_a, name_b, region_name, plural(passes[0]["placements"], "rule"), name_a,
                               plural(rules_b, "rule"), name_b, plural(counts["added_vertices"], "vertex"),
                               "{:,}".format(counts["added_edges"]), counts["from_a"], name_a, counts["from_b"],
                               name_b)]
        traced = counts["traced"]
        if traced and traced["traced_streets"]:
            parts.append("{} traced on into it from {} of both".format(
                plural(traced["traced_streets"], "street"), plural(traced["traced_seeds"], "street")))
        if counts["placed"]:
            parts.append("{} grown".format(plural(counts["placed"], "placed rule")))
        hierarchy = counts["hierarchy"]
        joined = hierarchy["routes"] + hierarchy["connectors"]
        if joined:
            part = "{} continued across the gap ({} raised to their class".format(
                plural(joined, "main road"), plural(hierarchy["raised_streets"] + hierarchy["connector_streets"],
                                                       "street"))
            if hierarchy["intersections"]:
                part += ", {}".format(plural(hierarchy["intersections"], "new intersection"))
            parts.append(part + ")")
        if hierarchy.get("extensions"):
            parts.append("{} led on to the new streets".format(plural(hierarchy["extensions"], "main road")))
        ends = []
        for name, report in zip((name_a, name_b), passes):
            if "share_of" in report:
                ends.append("{}: its share ({:,} of {})".format(name, report["placements"],
                                                                plural(report["share_of"], "rule")))
                continue
            end = "stopped by budget" if report["stopped_by_budget"] else "region full"
            ends.append("{}: {} after {}".format(name, end, tries(report["attempts"])))
        parts.append(", ".join(ends))
        parts.append("seed {}".format(self.seed) + (" and {}".format(self.seed + 1) if len(passes) > 1 else ""))
        return "; ".join(parts)


classes = (ROADS_OT_stitch_cities,)
