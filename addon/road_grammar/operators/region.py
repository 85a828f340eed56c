"""Growing streets into a region with a grammar's rules (ggg.grow_region): Grow into Region,
and what it shares with Stitch Cities (operators.stitch): the region object and its polygon,
the settings taken from the Grammar panel, and reading a road graph for a job.

Grow into Region runs as a job (operators.jobs.ModalJobOperator): the graph, the grammar and
the region are read on the main thread, the growth (core.growth.grow_into_region) runs in a
worker thread, modal from the UI (progress in the status bar, Esc cancels), waited for from
scripts; the mesh is written when it has finished, so a cancelled or failed growth leaves
the scene as it was.
"""

from types import SimpleNamespace

import bpy
from bpy.props import StringProperty
from bpy.types import Operator

from ..core.growth import grow_into_region, placed_rules
from ..core.jobs import StepsJob
from ..core.text import plural, rejections, tries
from ..core.topology import positions_digest, topology_checksum
from ..data import graph_edit, region, roads
from ..data import mesh as mesh_data
from ..display import road_objects
from ..properties import grammar
from .common import class_widths, grammar_or_report
from .jobs import ModalJobOperator

# Growths running in the UI: object name -> StepsJob (for the panel, and so that one graph
# does not grow twice at once).
running = {}


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
    set (F3, the panel's button) takes the panel's value (``_FROM_SETTINGS``: property name
    -> setting name, see jobs.ModalJobOperator.invoke); the redo panel shows the objects to
    pick (``_OBJECTS``) and the settings."""

    _OBJECTS = ("region",)

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        for name in self._OBJECTS:
            layout.prop_search(self, name, context.scene, "objects")
        for name in self._FROM_SETTINGS:
            layout.prop(self, name)

    def _settings(self, context):
        return context.scene.road_grammar


def read_columns(context, obj):
    """The MeshGraph of the road graph ``obj`` as the user sees it (in Edit Mode, the edited
    mesh: Edit Mode is left for the reading), and what changed_since compares (the
    checksum of its vertex ids, which jobs.ModalJobOperator checks when the job has finished,
    and of its positions)."""
    with graph_edit.object_mode(context, obj):
        columns = graph_edit.MeshGraph(obj)
    return columns, SimpleNamespace(checksum=topology_checksum(len(columns.positions), columns.edges),
                                    digest=positions_digest(columns.positions))


def changed_since(obj, topology):
    """Whether the vertices of the road graph ``obj`` moved, or it lost or gained vertices or
    edges, since ``topology`` (read_columns) was read."""
    if obj is None or obj.type != 'MESH':
        return True
    if obj.mode == 'EDIT':
        obj.update_from_editmode()
    positions = mesh_data.positions_xy(obj.data)
    edges = mesh_data.edge_vertices(obj.data)
    return topology_checksum(len(positions), edges) != topology.checksum or \
        positions_digest(positions) != topology.digest


class ROADS_OT_grow_region(GrowSettings, ModalJobOperator, Operator):
    """Grow streets into a region (a closed curve or a mesh, seen from above) with the active grammar's rules, from the active road graph's streets that reach it; Esc cancels"""

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
    roundabouts: grammar.roundabouts_property()

    _FROM_SETTINGS = {"seed": "region_seed", "max_placements": "region_max_placements",
                      "max_vertices": "region_max_vertices", "patience": "region_patience",
                      "use_placed_rules": "region_use_placed", "roundabouts": "region_roundabouts"}
    _running = running
    _doing = "Growing"
    _noun = "the growth"
    _subject = "Growing {}"
    _cannot = "Cannot grow {}"
    _result_noun = "what grew"
    _changed = "{} changed while it grew; grow it again"
    _progress_label = "Growing into a region"

    # Set up by _start.
    _region_name = ""
    _parsed_name = ""
    _old = None
    _placed = ()
    _loops = 1

    def _region_object(self, context, graph_obj):
        return region_object(self, context, (graph_obj,))

    # -- steps

    def _start(self, context):
        """Read the graph, the grammar and the region (main thread) and start the worker;
        False after an ERROR report."""
        graph_obj = roads.road_graph_object(context.active_object)
        if graph_obj is None or graph_obj.type != 'MESH':
            self.report({'ERROR'}, "Select a road graph to grow into a region (import roads, add an axiom or place a "
                        "rule first)")
            return False
        found = grammar_or_report(self, context)
        if found is None:
            return False
        ggg, _text, parsed = found
        if not hasattr(ggg, "grow_region"):
            self.report({'ERROR'}, "The native module {} cannot grow into a region (it lacks grow_region); rebuild "
                        "it".format(getattr(ggg, "__file__", "ggg")))
            return False
        if graph_obj.name in running:
            self.report({'ERROR'}, "{} is growing already".format(graph_obj.name))
            return False
        region_obj = self._region_object(context, graph_obj)
        read = region_polygon(self, context, region_obj, graph_obj, "Cannot grow into")
        if read is None:
            return False
        polygon, self._loops = read
        self.region = region_obj.name  # the redo panel grows into the same region
        self._region_name = region_obj.name
        self._progress_label = "Growing into {}".format(region_obj.name)
        self._parsed_name = parsed.name
        old, self._topology = read_columns(context, graph_obj)
        candidates, placements = self._placements(old, parsed)
        self._ggg, self._object_name, self._old = ggg, graph_obj.name, old
        self._placed = placements
        options = dict(seed=self.seed, max_placements=self.max_placements, max_vertices=self.max_vertices,
                       patience=self.patience, roundabouts=self.roundabouts)
        self._job = StepsJob(ggg, lambda job: grow_into_region(job, ggg, old, parsed, polygon, candidates,
                                                               placements, **options), "road_grammar grow")
        self._job.start()
        return True

    def _report_error(self, error):
        if isinstance(error, self._ggg.Error):
            hint = " (or turn off Use Placed Rules)" if self._placed and isinstance(error, self._ggg.UsageError) \
                else ""
            self.report({'ERROR'}, "Cannot grow {} into {}: {}{}".format(self._object_name, self._region_name,
                                                                        error, hint))
        else:
            super()._report_error(error)

    def _gone(self, context):
        if self._region_name not in bpy.data.objects:
            return "The region {} is gone; what grew is not kept".format(self._region_name)
        if changed_since(bpy.data.objects.get(self._object_name), self._topology):
            return self._changed.format(self._object_name)
        return None

    def _keep(self, context, graph_obj, _topology):
        """Write what grew into the road graph (main thread) and report."""
        grown, old = self._job.result, self._old
        report, used = grown.report, grown.used
        region_name, placements = self._region_name, self._placed
        if grown.result is None:
            self.report({'WARNING'}, self._nothing_message(graph_obj, region_name, old, report))
            return {'CANCELLED'}
        with graph_edit.object_mode(context, graph_obj):
            replacement = graph_edit.Replacement(graph_obj, old, grown.result, {"source_vertex": grown.source},
                                                 class_widths(context, self._ggg, grown.result))
            road_objects.rewrite(replacement)

        if graph_obj.get("grammar") not in (None, self._parsed_name):
            self.report({'WARNING'}, "{} was made with the grammar '{}', not '{}'".format(
                graph_obj.name, graph_obj["grammar"], self._parsed_name))
        if self._loops > 1:
            self.report({'WARNING'}, "{} has {} outlines: grew into the largest".format(region_name, self._loops))
        left = len(placements) - len(used)
        if left:
            self.report({'WARNING'}, "{} did not fit into {} and {} left as {}".format(
                plural(left, "placed rule"), region_name, "is" if left == 1 else "are",
                "it was" if left == 1 else "they were"))
        message = self._summary(graph_obj, region_name, report, len(used))
        self.report({'WARNING'} if report["stopped_by_budget"] else {'INFO'}, message)
        return {'FINISHED'}

    def _placements(self, old, parsed):
        """(mesh vertex ids, ggg.grow_region placements) of the nonterminals to grow first:
        with Use Placed Rules, each one whose symbol has a rule; the frame's scale and angle,
        or the rule's learned size where the vertex has no frame."""
        if not self.use_placed_rules:
            return [], []
        return placed_rules(old, parsed)

    def _summary(self, graph_obj, region_name, report, placed):
        traced = ""
        if report.get("traced_streets"):
            traced = "{} traced on from {} at the border, ".format(
                plural(report["traced_streets"], "street"), plural(report["traced_seeds"], "street"))
        parts = ["Grew {} into {}: {}{}, {}, {} ({} from the border".format(
            graph_obj.name, region_name, traced, plural(report["placements"], "rule"),
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
        if report.get("main_road_extensions"):
            parts.append("{} led on to the new streets".format(plural(report["main_road_extensions"], "main road")))
        if report.get("roundabouts"):
            parts.append(plural(report["roundabouts"], "roundabout"))
        if report.get("cul_de_sacs"):
            parts.append(plural(report["cul_de_sacs"], "dead-end street"))
        if placed:
            parts.append("{} grown".format(plural(placed, "placed rule")))
        if report["stopped_by_budget"]:
            end = "stopped by budget ({:,} rules, {:,} vertices)".format(self.max_placements, self.max_vertices)
        else:
            end = "region full"
        parts.append("{} after {} ({}); seed {}".format(end, tries(report["attempts"]), rejections(report),
                                                       self.seed))
        return "; ".join(parts)

    def _nothing_message(self, graph_obj, region_name, old, report):
        if report["stopped_by_budget"] and report["placements"] == 0 and not report.get("traced_streets"):
            reason = "the graph has {:,} vertices, the budget is {:,}".format(len(old.positions), self.max_vertices)
        else:
            reason = "no rule fits there ({}: {})".format(tries(report["attempts"]), rejections(report))
        return "Nothing grew in {} from {}: {}. The graph is unchanged.".format(region_name, graph_obj.name, reason)


classes = (ROADS_OT_grow_region,)
