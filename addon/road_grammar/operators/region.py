"""Growing streets into a region with a grammar's rules (ggg.grow_region): Grow into Region,
and what it shares with Stitch Cities (operators.stitch): the region object and its polygon,
and the settings taken from the Grammar panel."""

import bpy
import numpy as np
from bpy.props import StringProperty
from bpy.types import Operator

from ..core.columns import appended, induced_subgraph
from ..core.growth import ThrottledProgress, placed_rules, placements_that_fit
from ..core.text import plural, rejections, tries
from ..data import graph_edit, region, roads
from ..properties import grammar
from .common import class_widths, grammar_or_report


def region_object(op, context, graph_objs):
    """The region object of Grow into Region and Stitch Cities: the one named by the
    operator's ``region``, else the panel's picker, else the one other curve or mesh selected
    with the road graphs ``graph_objs``; None after an ERROR report."""
    if op.region:
        obj = bpy.data.objects.get(op.region)
        if obj is None:
            op.report({'ERROR'}, "No object named '{}' to grow into".format(op.region))
        return obj
    picked = context.scene.road_grammar.region
    if picked is not None:
        return picked
    selected = [obj for obj in context.selected_objects
                if obj not in graph_objs and roads.road_graph_object(obj) not in graph_objs]
    candidates = [obj for obj in selected if region.is_candidate(obj)]
    if len(candidates) == 1:
        return candidates[0]
    if not candidates:
        op.report({'ERROR'}, "No region: pick one in the Grammar panel (Grow into Region), or select a closed "
                  "curve or a mesh together with the road graph")
    else:
        op.report({'ERROR'}, "Several curves or meshes are selected ({}): select one region, or pick it in "
                  "the Grammar panel".format(", ".join(sorted(obj.name for obj in candidates))))
    return None


def region_polygon(op, context, region_obj, graph_obj, cannot):
    """(polygon, loops) of the region object in the graph's frame, or None after an ERROR
    report (no region, one no longer in the view layer, or an outline that is not one)."""
    if region_obj is None:
        return None
    if context.view_layer.objects.get(region_obj.name) != region_obj:
        op.report({'ERROR'}, "The region {} is not in the view layer (deleted?): pick another one".format(region_obj.name))
        return None
    try:
        return region.polygon(region_obj, context.evaluated_depsgraph_get(), graph_obj)
    except region.RegionError as ex:
        op.report({'ERROR'}, "{} {}: {}".format(cannot, region_obj.name, ex))
        return None


class GrowSettings:
    """Operators that grow with the Grammar panel's settings: a property the caller does not
    set (F3, the panel's button) takes the panel's value; the redo panel shows the objects
    to pick (``_OBJECTS``) and the settings."""

    _OBJECTS = ("region",)

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        for name in self._OBJECTS:
            layout.prop_search(self, name, context.scene, "objects")
        for name in self._FROM_SETTINGS:
            layout.prop(self, name)

    def invoke(self, context, event):
        settings = context.scene.road_grammar
        for name, setting in self._FROM_SETTINGS.items():
            if not self.properties.is_property_set(name):
                setattr(self, name, getattr(settings, setting))
        return self.execute(context)


class ROADS_OT_grow_region(GrowSettings, Operator):
    """Grow streets into a region (a closed curve or a mesh, seen from above) with the active grammar's rules, from the active road graph's streets that reach it"""

    bl_idname = "roads.grow_region"
    bl_label = "Grow into Region"
    bl_options = {'REGISTER', 'UNDO'}

    region: StringProperty(
        name="Region",
        description="Name of the curve or mesh object to fill (empty: the Region of the Grammar panel, else the "
        "other selected curve or mesh)",
        options={'SKIP_SAVE'},
    )
    seed: grammar.seed_property()
    max_placements: grammar.max_placements_property()
    max_vertices: grammar.region_max_vertices_property()
    patience: grammar.patience_property()
    use_placed_rules: grammar.use_placed_property()

    _FROM_SETTINGS = {"seed": "region_seed", "max_placements": "region_max_placements",
                      "max_vertices": "region_max_vertices", "patience": "region_patience",
                      "use_placed_rules": "region_use_placed"}

    def _region_object(self, context, graph_obj):
        return region_object(self, context, (graph_obj,))

    def execute(self, context):
        graph_obj = roads.road_graph_object(context.active_object)
        if graph_obj is None or graph_obj.type != 'MESH':
            self.report({'ERROR'}, "Select a road graph to grow into a region (import roads, add an axiom or place a "
                        "rule first)")
            return {'CANCELLED'}
        found = grammar_or_report(self, context)
        if found is None:
            return {'CANCELLED'}
        ggg, _text, parsed = found
        if not hasattr(ggg, "grow_region"):
            self.report({'ERROR'}, "The native module {} cannot grow into a region (it lacks grow_region); rebuild "
                        "it".format(getattr(ggg, "__file__", "ggg")))
            return {'CANCELLED'}
        region_obj = self._region_object(context, graph_obj)
        read = region_polygon(self, context, region_obj, graph_obj, "Cannot grow into")
        if read is None:
            return {'CANCELLED'}
        polygon, loops = read
        self.region = region_obj.name  # the redo panel grows into the same region

        with graph_edit.object_mode(context, graph_obj):
            old = graph_edit.MeshGraph(graph_obj)
            with roads.Progress(context, read_share=0.9, label="Growing into {}".format(region_obj.name)) \
                    as progress:
                try:
                    graph = old.graph(ggg)
                    # The streets grow; the nonterminals are left out (growth would take them
                    # for street vertices), placed first when they are used.
                    streets = old.symbols == 0
                    base, base_ids, base_edge_ids = induced_subgraph(ggg, graph, streets)
                    candidates, placements = self._placements(old, parsed)
                    fits = placements_that_fit(ggg, base, parsed, polygon, placements)
                    used = [vertex for vertex, fit in zip(candidates, fits) if fit]
                    grown, report = ggg.grow_region(
                        base, parsed, polygon, seed=self.seed, max_placements=self.max_placements,
                        max_vertices=self.max_vertices, patience=self.patience,
                        placements=[p for p, fit in zip(placements, fits) if fit],
                        progress=ThrottledProgress(progress))
                except ggg.Error as ex:
                    hint = " (or turn off Use Placed Rules)" if placements and isinstance(ex, ggg.UsageError) else ""
                    self.report({'ERROR'}, "Cannot grow {} into {}: {}{}".format(graph_obj.name, region_obj.name, ex,
                                                                                hint))
                    return {'CANCELLED'}
                if report["added_vertices"] == 0:
                    self.report({'WARNING'}, self._nothing_message(graph_obj, region_obj, old, report))
                    return {'CANCELLED'}
                progress.step(0.0, "updating the mesh")
                keep = np.ones(len(old.positions), dtype=bool)
                keep[np.asarray(used, dtype=np.int64)] = False
                try:
                    result, source = appended(ggg, graph, keep, grown, base_ids, len(base_edge_ids))
                except ggg.Error as ex:
                    self.report({'ERROR'}, "Cannot grow {} into {}: {}".format(graph_obj.name, region_obj.name, ex))
                    return {'CANCELLED'}
                replacement = graph_edit.Replacement(graph_obj, old, result, {"source_vertex": source},
                                                     class_widths(context, ggg, result))
                replacement.apply(context)
                progress.step(1.0, "done")

        if graph_obj.get("grammar") not in (None, parsed.name):
            self.report({'WARNING'}, "{} was made with the grammar '{}', not '{}'".format(
                graph_obj.name, graph_obj["grammar"], parsed.name))
        if loops > 1:
            self.report({'WARNING'}, "{} has {} outlines: grew into the largest".format(region_obj.name, loops))
        left = len(placements) - len(used)
        if left:
            self.report({'WARNING'}, "{} did not fit into {} and {} left as {}".format(
                plural(left, "placed rule"), region_obj.name, "is" if left == 1 else "are",
                "it was" if left == 1 else "they were"))
        message = self._summary(graph_obj, region_obj, report, len(used))
        self.report({'WARNING'} if report["stopped_by_budget"] else {'INFO'}, message)
        return {'FINISHED'}

    def _placements(self, old, parsed):
        """(mesh vertex ids, ggg.grow_region placements) of the nonterminals to grow first:
        with Use Placed Rules, each one whose symbol has a rule; the frame's scale and angle,
        or the rule's learned size where the vertex has no frame."""
        if not self.use_placed_rules:
            return [], []
        return placed_rules(old, parsed)

    def _summary(self, graph_obj, region_obj, report, placed):
        traced = ""
        if report.get("traced_streets"):
            traced = "{} traced on from {} at the border, ".format(
                plural(report["traced_streets"], "street"), plural(report["traced_seeds"], "street"))
        parts = ["Grew {} into {}: {}{}, {}, {} ({} from the border".format(
            graph_obj.name, region_obj.name, traced, plural(report["placements"], "rule"),
            plural(report["added_vertices"], "vertex"), plural(report["added_edges"], "street"),
            report["border_connections"])]
        if report["closing_edges"]:
            parts[0] += ", {} closing dead ends".format(report["closing_edges"])
        if report.get("t_junctions"):
            parts[0] += ", {}".format(plural(report["t_junctions"], "T-junction"))
        if report.get("pruned_stubs"):
            parts[0] += ", {} cut".format(plural(report["pruned_stubs"], "loose end"))
        parts[0] += ")"
        joined = report.get("main_road_routes", 0) + report.get("main_road_connectors", 0)
        if joined:
            parts.append("{} continued through the new streets".format(plural(joined, "main road")))
        if placed:
            parts.append("{} grown".format(plural(placed, "placed rule")))
        if report["stopped_by_budget"]:
            end = "stopped by budget ({:,} rules, {:,} vertices)".format(self.max_placements, self.max_vertices)
        else:
            end = "region full"
        parts.append("{} after {} ({}); seed {}".format(end, tries(report["attempts"]), rejections(report),
                                                       self.seed))
        return "; ".join(parts)

    def _nothing_message(self, graph_obj, region_obj, old, report):
        if report["stopped_by_budget"] and report["placements"] == 0 and not report.get("traced_streets"):
            reason = "the graph has {:,} vertices, the budget is {:,}".format(len(old.positions), self.max_vertices)
        else:
            reason = "no rule fits there ({}: {})".format(tries(report["attempts"]), rejections(report))
        return "Nothing grew in {} from {}: {}. The graph is unchanged.".format(region_obj.name, graph_obj.name, reason)


classes = (ROADS_OT_grow_region,)
