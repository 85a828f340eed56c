"""Operators of the grammar workflow (paper 3.2-3.3): load a grammar into the scene, add
its axiom, place a rule's nonterminal at the 3D cursor, grow a road graph by derivation
steps, and grow streets into a region with the grammar's rules (ggg.grow_region)."""

import math
import os

import bpy
from bpy.props import StringProperty
from bpy.types import Operator
from bpy_extras.io_utils import ExportHelper, ImportHelper
from mathutils import Vector

import numpy as np

from . import georef, grammar, graph_edit, importer, native, operators, preferences, surface
from . import region as regions


def _grammar_or_report(op, context):
    """(ggg, Text, ggg.Grammar), or None after an ERROR report."""
    try:
        ggg = native.load()
        text, parsed = grammar.active(context)
    except (native.NativeModuleError, grammar.GrammarUnavailable) as ex:
        op.report({'ERROR'}, str(ex))
        return None
    return ggg, text, parsed


def _class_widths(context, ggg, graph):
    prefs = preferences.get(context)
    return surface.road_widths(graph.edge_highway, graph.edge_width, graph.edge_lanes,
                               preferences.class_width_table(prefs, ggg), prefs.lane_width)


def _plural(count, word):
    """'1 rule', '3 rules', '2 vertices'."""
    if count == 1:
        return "1 " + word
    plural = word[:-len("vertex")] + "vertices" if word.endswith("vertex") else word + "s"
    return "{:,} {}".format(count, plural)


def _tries(count):
    return "1 try" if count == 1 else "{:,} tries".format(count)


def _rejections(report):
    """Why the tries of ggg.grow_region failed: '12 outside, 3 crossing, 40 crowded'."""
    parts = ["{:,} outside".format(report["rejected_outside"]), "{:,} crossing".format(report["rejected_crossing"]),
             "{:,} crowded".format(report["rejected_crowded"])]
    if report.get("rejected_off_grid"):
        parts.append("{:,} off the grid".format(report["rejected_off_grid"]))
    if report.get("rejected_small_block"):
        parts.append("{:,} closing a sliver".format(report["rejected_small_block"]))
    return ", ".join(parts)


class ROADS_OT_load_grammar(Operator, ImportHelper):
    """Load a grammar file (ggg-grammar JSON) into the scene; it is kept in the .blend as a text"""

    bl_idname = "roads.load_grammar"
    bl_label = "Load Grammar"
    bl_options = {'REGISTER', 'UNDO'}

    filename_ext = ".json"
    filter_glob: StringProperty(default="*.json", options={'HIDDEN'})

    def execute(self, context):
        path = operators.input_file_or_report(self)
        if path is None:
            return {'CANCELLED'}
        ggg = native.load_or_report(self)
        if ggg is None:
            return {'CANCELLED'}
        try:
            parsed = ggg.read_grammar(path)
        except ggg.Error as ex:
            self.report({'ERROR'}, str(ex))
            return {'CANCELLED'}
        try:
            with open(path, encoding="utf-8") as source:
                content = source.read()
        except (OSError, UnicodeDecodeError) as ex:
            self.report({'ERROR'}, "{}: {}".format(path, ex))
            return {'CANCELLED'}

        # Loading the same file again refreshes its text instead of making a copy.
        text = next((t for t in bpy.data.texts if t.get(grammar.SOURCE_KEY) == path), None)
        if text is None:
            text = bpy.data.texts.new(os.path.basename(path))
        text.from_string(content)
        text[grammar.SOURCE_KEY] = path
        text.use_fake_user = True
        context.scene.road_grammar.text = text
        self.report({'INFO'}, "Loaded grammar '{}' ({}, {}) into the text '{}'".format(
            parsed.name, _plural(len(parsed.rules), "rule"), _plural(len(parsed.symbols), "symbol"), text.name))
        return {'FINISHED'}


class ROADS_OT_save_grammar(Operator, ExportHelper):
    """Write the scene's active grammar to a grammar file"""

    bl_idname = "roads.save_grammar"
    bl_label = "Save Grammar"
    bl_options = {'REGISTER'}

    filename_ext = ".json"
    filter_glob: StringProperty(default="*.json", options={'HIDDEN'})

    @classmethod
    def poll(cls, context):
        return grammar.active_text(context) is not None

    def invoke(self, context, event):
        text = grammar.active_text(context)
        if text is not None and not self.filepath:
            name = text.name if text.name.endswith(".json") else text.name + ".json"
            self.filepath = os.path.join(os.path.dirname(bpy.data.filepath) or os.getcwd(), name)
        return ExportHelper.invoke(self, context, event)

    def execute(self, context):
        found = _grammar_or_report(self, context)
        if found is None:
            return {'CANCELLED'}
        ggg, _text, parsed = found
        path = bpy.path.abspath(self.filepath)
        try:
            parsed.write(path)
        except (ggg.Error, OSError) as ex:
            self.report({'ERROR'}, str(ex))
            return {'CANCELLED'}
        self.report({'INFO'}, "Wrote grammar '{}' to {}".format(parsed.name, path))
        return {'FINISHED'}


class ROADS_OT_add_axiom(Operator):
    """Add the active grammar's axiom as a road graph object (with its nonterminals' frames)"""

    bl_idname = "roads.add_axiom"
    bl_label = "Add Axiom"
    bl_options = {'REGISTER', 'UNDO'}

    def execute(self, context):
        found = _grammar_or_report(self, context)
        if found is None:
            return {'CANCELLED'}
        ggg, text, parsed = found
        try:
            axiom = parsed.axiom_graph()
            if axiom.vertex_count == 0:
                self.report({'ERROR'}, "The grammar '{}' has an empty axiom".format(parsed.name))
                return {'CANCELLED'}
            target, place = georef.grammar_target(ggg, context.scene, parsed.origin_latlon)
            axiom = place(axiom)
            widths = _class_widths(context, ggg, axiom)
        except ggg.Error as ex:
            self.report({'ERROR'}, str(ex))
            return {'CANCELLED'}
        graph_obj, _surface = importer.build(
            context, axiom, list(ggg.highway_classes()), widths, parsed.name, text.name, None,
            target=target, with_frames=True, properties={"grammar": parsed.name})
        if target.warning:
            self.report({'WARNING'}, target.warning)
        self.report({'INFO'}, "Added the axiom of '{}' as {}: {}, {}, {}".format(
            parsed.name, graph_obj.name, _plural(axiom.vertex_count, "vertex"),
            _plural(axiom.edge_count, "edge"),
            _plural(int(np.count_nonzero(axiom.vertex_symbols)), "nonterminal")))
        return {'FINISHED'}


def _cursor_angle(cursor):
    """The 3D cursor's rotation about Z (radians, world): the direction of its X axis."""
    x_axis = cursor.matrix.to_3x3().col[0]
    if math.hypot(x_axis.x, x_axis.y) > 1e-9:
        return math.atan2(x_axis.y, x_axis.x)
    return cursor.matrix.to_euler('XYZ').z


class ROADS_OT_place_rule(Operator):
    """Place a nonterminal of a rule of a grammar (the scene's, or the one named) at the 3D cursor, turned as the cursor, in the active road graph (or a new one)"""

    bl_idname = "roads.place_rule"
    bl_label = "Place Rule"
    bl_options = {'REGISTER', 'UNDO'}

    # (Before ``rule``: Blender sets the properties in this order, and the rule menu lists
    # the rules of this grammar.)
    grammar: StringProperty(
        name="Grammar",
        description="Name of the Text holding the grammar whose rule is placed (empty: the scene's grammar), e.g. "
        "the grammar learned from another road graph",
    )
    rule: grammar.rule_property("Rule whose nonterminal is placed")
    scale: grammar.scale_property("Metres for one unit of the rule (the scale of the nonterminal's frame)")

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        layout.prop_search(self, "grammar", bpy.data, "texts")
        layout.prop(self, "rule")
        layout.prop(self, "scale")

    def invoke(self, context, event):
        settings = context.scene.road_grammar
        if not self.properties.is_property_set("grammar") and settings.place_grammar is not None:
            self.grammar = settings.place_grammar.name
        if not self.properties.is_property_set("rule") and settings.rule not in ('', 'NONE'):
            self.rule = settings.rule
        if not self.properties.is_property_set("scale"):
            self.scale = settings.scale
        return self.execute(context)

    def execute(self, context):
        try:
            ggg = native.load()
            text, parsed = grammar.named(self.grammar) if self.grammar else grammar.active(context)
        except (native.NativeModuleError, grammar.GrammarUnavailable) as ex:
            self.report({'ERROR'}, str(ex))
            return {'CANCELLED'}
        rule = grammar.rule_of(parsed, self.rule)
        if rule is None:
            self.report({'ERROR'}, "The grammar '{}' has no rule '{}'".format(parsed.name, self.rule))
            return {'CANCELLED'}
        cursor = context.scene.cursor
        angle_world = _cursor_angle(cursor)

        graph_obj = importer.road_graph_object(context.active_object)
        warning = None
        if graph_obj is None:
            try:
                target, place = georef.grammar_target(ggg, context.scene, parsed.origin_latlon)
                empty = place(ggg.Graph.from_arrays(np.zeros((0, 2)), np.zeros((0, 2), dtype=np.int64),
                                                    origin_latlon=tuple(parsed.origin_latlon)))
            except ggg.Error as ex:
                self.report({'ERROR'}, str(ex))
                return {'CANCELLED'}
            graph_obj, _surface = importer.build(
                context, empty, list(ggg.highway_classes()), [], parsed.name, text.name, None,
                target=target, with_frames=True, properties={"grammar": parsed.name})
            warning = target.warning
        elif graph_obj.get("grammar") not in (None, parsed.name) and text != grammar.learned_text(graph_obj):
            warning = "{} was made with the grammar '{}', not '{}'".format(
                graph_obj.name, graph_obj["grammar"], parsed.name)

        with graph_edit.object_mode(context, graph_obj):
            to_local = graph_obj.matrix_world.inverted()
            location = to_local @ cursor.location
            direction = to_local.to_3x3() @ Vector((math.cos(angle_world), math.sin(angle_world), 0.0))
            angle = math.atan2(direction.y, direction.x)
            scale = self.scale * math.hypot(direction.x, direction.y)
            if not (scale > 0.0 and math.isfinite(scale)):
                self.report({'ERROR'}, "Cannot place a rule in {}: its transform is degenerate".format(graph_obj.name))
                return {'CANCELLED'}
            vertex = graph_edit.add_nonterminal(graph_obj, (location.x, location.y), rule["symbol"],
                                                (scale * math.cos(angle), scale * math.sin(angle)))
            # Which grammar the nonterminal comes from (Stitch Cities grows it with that one).
            graph_edit.note_grammar(graph_obj, vertex, text.name)
            created = importer.Created()
            importer.add_frames_modifier(graph_obj, created)
            if graph_obj.get("grammar") is None:
                graph_obj["grammar"] = parsed.name
        for obj in context.view_layer.objects:
            obj.select_set(obj == graph_obj)
        context.view_layer.objects.active = graph_obj
        if warning:
            self.report({'WARNING'}, warning)
        self.report({'INFO'}, "Placed {} ({}) of '{}' in {} at ({:.1f}, {:.1f}) m, {:.1f}\u00b0, scale {:g} m".format(
            rule["name"], rule["symbol"], text.name, graph_obj.name, location.x, location.y,
            math.degrees(angle_world), self.scale))
        return {'FINISHED'}


class ROADS_OT_grow(Operator):
    """Grow the active road graph: rewrite its nonterminals by the active grammar's rules for some derivation steps"""

    bl_idname = "roads.grow"
    bl_label = "Grow"
    bl_options = {'REGISTER', 'UNDO'}

    steps: grammar.steps_property()
    max_vertices: grammar.max_vertices_property()
    tolerance_unit: grammar.tolerance_unit_property("Tolerance Unit")
    tolerance: grammar.tolerance_property()
    tolerance_m: grammar.tolerance_m_property("Tolerance (m)")
    strict: grammar.strict_property("Rewrite a nonterminal only when every embedding point finds a vertex to "
                                    "connect to")

    _FROM_SETTINGS = ("steps", "max_vertices", "tolerance_unit", "tolerance", "tolerance_m", "strict")

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        layout.prop(self, "steps")
        layout.prop(self, "max_vertices")
        layout.prop(self, "tolerance_unit")
        layout.prop(self, "tolerance" if self.tolerance_unit == 'RELATIVE' else "tolerance_m")
        layout.prop(self, "strict")

    def invoke(self, context, event):
        settings = context.scene.road_grammar
        for name in self._FROM_SETTINGS:
            if not self.properties.is_property_set(name):
                setattr(self, name, getattr(settings, name))
        return self.execute(context)

    def execute(self, context):
        graph_obj = importer.road_graph_object(context.active_object)
        if graph_obj is None or graph_obj.type != 'MESH':
            self.report({'ERROR'}, "Select a road graph to grow (import roads, add an axiom or place a rule first)")
            return {'CANCELLED'}
        found = _grammar_or_report(self, context)
        if found is None:
            return {'CANCELLED'}
        ggg, _text, parsed = found

        with graph_edit.object_mode(context, graph_obj):
            old = graph_edit.MeshGraph(graph_obj)
            if old.nonterminal_count == 0:
                self.report({'WARNING'}, "Nothing to grow: {} has no nonterminal vertices (symbol > 0); place a "
                            "rule first. The graph is unchanged.".format(graph_obj.name))
                return {'CANCELLED'}
            with importer.Progress(context, read_share=0.9, label="Growing roads") as progress:
                try:
                    graph = old.graph(ggg)
                    tolerance = {"tolerance_m": self.tolerance_m} if self.tolerance_unit == 'METRES' \
                        else {"tolerance": self.tolerance}
                    result, report = ggg.derive(parsed, graph, steps=self.steps, max_vertices=self.max_vertices,
                                                strict=self.strict, progress=progress, **tolerance)
                except ggg.Error as ex:
                    self.report({'ERROR'}, "Cannot grow {}: {}".format(graph_obj.name, ex))
                    return {'CANCELLED'}
                if report["steps"] == 0:
                    # The first step was not applied: nothing to rewrite, or over the budget.
                    self.report({'WARNING'}, self._nothing_message(graph_obj, old, parsed, report))
                    return {'CANCELLED'}
                progress.step(0.0, "updating the mesh")
                replacement = graph_edit.Replacement(graph_obj, old, result, report,
                                                     _class_widths(context, ggg, result))
                replacement.apply(context)
                progress.step(1.0, "done")

        if graph_obj.get("grammar") not in (None, parsed.name):
            self.report({'WARNING'}, "{} was made with the grammar '{}', not '{}'".format(
                graph_obj.name, graph_obj["grammar"], parsed.name))
        message, budget = self._summary(graph_obj, report)
        self.report({'WARNING'} if budget else {'INFO'}, message)
        return {'FINISHED'}

    def _summary(self, graph_obj, report):
        done = _plural(report["steps"], "step")
        if report["steps"] < self.steps:
            done += " of {}".format(self.steps)
        parts = ["Grew {}: {}, {}, {}, {}".format(
            graph_obj.name, done, _plural(report["vertices"], "vertex"), _plural(report["edges"], "edge"),
            _plural(report["rewrites"], "rewrite"))]
        if report["embedding_edges"]:
            parts.append(_plural(report["embedding_edges"], "embedding edge"))
        if report["missed_embeddings"]:
            parts.append("{} found no vertex".format(_plural(report["missed_embeddings"], "embedding point")))
        if report["merged_vertices"]:
            parts.append("{} merged".format(_plural(report["merged_vertices"], "placed vertex")))
        if report["refused"]:
            parts.append("{} refused (strict)".format(_plural(report["refused"], "rewrite")))
        budget = bool(report["stopped_by_budget"])
        if budget:
            parts.append("stopped by budget: the next step would pass {:,} vertices".format(self.max_vertices))
        elif report["converged"]:
            parts.append("converged: a step changed nothing")
        return "; ".join(parts), budget

    def _nothing_message(self, graph_obj, old, parsed, report):
        if not report["nothing_to_rewrite"]:  # stopped by the budget
            reason = "the first step would pass the budget of {:,} vertices".format(self.max_vertices)
        elif report["refused"]:
            reason = "strict embedding refused all {}".format(_plural(report["refused"], "rewrite"))
        else:
            reason = "none of its {} has a rule in the grammar '{}'".format(
                _plural(old.nonterminal_count, "nonterminal"), parsed.name)
        return "Nothing was rewritten in {}: {}. The graph is unchanged.".format(graph_obj.name, reason)


class _ThrottledProgress:
    """The progress callback of ggg.grow_region (called on every try) passed on to an
    importer.Progress only when the percentage or the message changes."""

    def __init__(self, progress):
        self._progress = progress
        self._last = None

    def __call__(self, fraction, message):
        key = (int(100.0 * float(fraction)), message)
        if key != self._last:
            self._last = key
            self._progress(fraction, message)
        return True


def placements_that_fit(ggg, base, parsed, polygon, placements):
    """For each of ``placements`` (the tuples of ggg.grow_region), whether it fits into the
    region (inside it, crossing no street, not crowding one) when they are placed in order.

    ggg.grow_region places the rules placed by hand first, in order, before anything else,
    without random choices; one that does not fit changes nothing. With patience=0 it stops
    right after them, so its report counts the ones that fitted, except that when none did
    and no street reaches the region it also seeds the region's middle (one try more than
    the placements: then none fitted)."""

    def fitted(prefix):
        _graph, report = ggg.grow_region(base, parsed, polygon, patience=0, placements=prefix)
        return 0 if report["attempts"] > len(prefix) else report["placements"]

    if not placements:
        return []
    if fitted(placements) == len(placements):
        return [True] * len(placements)
    result, before = [], 0
    for count in range(1, len(placements) + 1):
        now = fitted(placements[:count])
        result.append(now > before)
        before = now
    return result


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
                if obj not in graph_objs and importer.road_graph_object(obj) not in graph_objs]
    candidates = [obj for obj in selected if regions.is_candidate(obj)]
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
        return regions.polygon(region_obj, context.evaluated_depsgraph_get(), graph_obj)
    except regions.RegionError as ex:
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
        graph_obj = importer.road_graph_object(context.active_object)
        if graph_obj is None or graph_obj.type != 'MESH':
            self.report({'ERROR'}, "Select a road graph to grow into a region (import roads, add an axiom or place a "
                        "rule first)")
            return {'CANCELLED'}
        found = _grammar_or_report(self, context)
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
            with importer.Progress(context, read_share=0.9, label="Growing into {}".format(region_obj.name)) \
                    as progress:
                try:
                    graph = old.graph(ggg)
                    # The streets grow; the nonterminals are left out (growth would take them
                    # for street vertices), placed first when they are used.
                    streets = old.symbols == 0
                    base, base_ids, base_edge_ids = graph_edit.induced_subgraph(ggg, graph, streets)
                    candidates, placements = self._placements(old, parsed)
                    fits = placements_that_fit(ggg, base, parsed, polygon, placements)
                    used = [vertex for vertex, fit in zip(candidates, fits) if fit]
                    grown, report = ggg.grow_region(
                        base, parsed, polygon, seed=self.seed, max_placements=self.max_placements,
                        max_vertices=self.max_vertices, patience=self.patience,
                        placements=[p for p, fit in zip(placements, fits) if fit],
                        progress=_ThrottledProgress(progress))
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
                    result, source = graph_edit.appended(ggg, graph, keep, grown, base_ids, len(base_edge_ids))
                except ggg.Error as ex:
                    self.report({'ERROR'}, "Cannot grow {} into {}: {}".format(graph_obj.name, region_obj.name, ex))
                    return {'CANCELLED'}
                replacement = graph_edit.Replacement(graph_obj, old, result, {"source_vertex": source},
                                                     _class_widths(context, ggg, result))
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
                _plural(left, "placed rule"), region_obj.name, "is" if left == 1 else "are",
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
        symbols = {int(rule["symbol"]) for rule in parsed.rules}
        vertices, placements = [], []
        for vertex in np.flatnonzero(old.symbols).tolist():
            symbol = int(old.symbols[vertex])
            if symbol not in symbols:
                continue
            a, b, x, y = (float(value) for value in old.frames[vertex])
            scale = 0.0 if old.frame_missing[vertex] else math.hypot(a, b)
            vertices.append(vertex)
            placements.append((symbol, x, y, scale, math.degrees(math.atan2(b, a))))
        return vertices, placements

    def _summary(self, graph_obj, region_obj, report, placed):
        parts = ["Grew {} into {}: {}, {}, {} ({} from the border".format(
            graph_obj.name, region_obj.name, _plural(report["placements"], "rule"),
            _plural(report["added_vertices"], "vertex"), _plural(report["added_edges"], "street"),
            report["border_connections"])]
        if report["closing_edges"]:
            parts[0] += ", {} closing dead ends".format(report["closing_edges"])
        if report.get("t_junctions"):
            parts[0] += ", {}".format(_plural(report["t_junctions"], "T-junction"))
        if report.get("pruned_stubs"):
            parts[0] += ", {} cut".format(_plural(report["pruned_stubs"], "loose end"))
        parts[0] += ")"
        joined = report.get("main_road_routes", 0) + report.get("main_road_connectors", 0)
        if joined:
            parts.append("{} continued through the new streets".format(_plural(joined, "main road")))
        if placed:
            parts.append("{} grown".format(_plural(placed, "placed rule")))
        if report["stopped_by_budget"]:
            end = "stopped by budget ({:,} rules, {:,} vertices)".format(self.max_placements, self.max_vertices)
        else:
            end = "region full"
        parts.append("{} after {} ({}); seed {}".format(end, _tries(report["attempts"]), _rejections(report),
                                                       self.seed))
        return "; ".join(parts)

    def _nothing_message(self, graph_obj, region_obj, old, report):
        if report["stopped_by_budget"] and report["placements"] == 0:
            reason = "the graph has {:,} vertices, the budget is {:,}".format(len(old.positions), self.max_vertices)
        else:
            reason = "no rule fits there ({}: {})".format(_tries(report["attempts"]), _rejections(report))
        return "Nothing grew in {} from {}: {}. The graph is unchanged.".format(region_obj.name, graph_obj.name, reason)
