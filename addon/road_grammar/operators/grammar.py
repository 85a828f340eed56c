"""Operators of the grammar workflow (paper 3.2-3.3): load a grammar into the scene, add
its axiom, place a rule's nonterminal at the 3D cursor, and grow a road graph by derivation
steps. (Growing streets into a region with the grammar's rules: operators.region.)"""

import math
import os

import bpy
import numpy as np
from bpy.props import StringProperty
from bpy.types import Operator
from bpy_extras.io_utils import ExportHelper, ImportHelper
from mathutils import Vector

from ..core import georef, native
from ..core.grammar import rule_of
from ..core.names import SOURCE_KEY
from ..core.text import plural
from ..data import graph_edit, roads, texts
from ..display import frames, road_objects
from ..properties import grammar
from .common import class_widths, grammar_or_report, input_file_or_report


class ROADS_OT_load_grammar(Operator, ImportHelper):
    """Load a grammar file (ggg-grammar JSON) into the scene; it is kept in the .blend as a text"""

    bl_idname = "roads.load_grammar"
    bl_label = "Load Grammar"
    bl_options = {'REGISTER', 'UNDO'}

    filename_ext = ".json"
    filter_glob: StringProperty(default="*.json", options={'HIDDEN'})

    def execute(self, context):
        path = input_file_or_report(self)
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
        text = next((t for t in bpy.data.texts if t.get(SOURCE_KEY) == path), None)
        if text is None:
            text = bpy.data.texts.new(os.path.basename(path))
        text.from_string(content)
        text[SOURCE_KEY] = path
        text.use_fake_user = True
        context.scene.road_grammar.text = text
        self.report({'INFO'}, "Loaded grammar '{}' ({}, {}) into the text '{}'".format(
            parsed.name, plural(len(parsed.rules), "rule"), plural(len(parsed.symbols), "symbol"), text.name))
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
        return texts.active_text(context) is not None

    def invoke(self, context, event):
        text = texts.active_text(context)
        if text is not None and not self.filepath:
            name = text.name if text.name.endswith(".json") else text.name + ".json"
            self.filepath = os.path.join(os.path.dirname(bpy.data.filepath) or os.getcwd(), name)
        return ExportHelper.invoke(self, context, event)

    def execute(self, context):
        found = grammar_or_report(self, context)
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
        found = grammar_or_report(self, context)
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
            widths = class_widths(context, ggg, axiom)
        except ggg.Error as ex:
            self.report({'ERROR'}, str(ex))
            return {'CANCELLED'}
        graph_obj, _surface = road_objects.build(
            context, axiom, list(ggg.highway_classes()), widths, parsed.name, text.name, None,
            target=target, with_frames=True, properties={"grammar": parsed.name})
        if target.warning:
            self.report({'WARNING'}, target.warning)
        self.report({'INFO'}, "Added the axiom of '{}' as {}: {}, {}, {}".format(
            parsed.name, graph_obj.name, plural(axiom.vertex_count, "vertex"),
            plural(axiom.edge_count, "edge"),
            plural(int(np.count_nonzero(axiom.vertex_symbols)), "nonterminal")))
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
            text, parsed = texts.named(self.grammar) if self.grammar else texts.active(context)
        except (native.NativeModuleError, texts.GrammarUnavailable) as ex:
            self.report({'ERROR'}, str(ex))
            return {'CANCELLED'}
        rule = rule_of(parsed, self.rule)
        if rule is None:
            self.report({'ERROR'}, "The grammar '{}' has no rule '{}'".format(parsed.name, self.rule))
            return {'CANCELLED'}
        cursor = context.scene.cursor
        angle_world = _cursor_angle(cursor)

        graph_obj = roads.road_graph_object(context.active_object)
        warning = None
        if graph_obj is None:
            try:
                target, place = georef.grammar_target(ggg, context.scene, parsed.origin_latlon)
                empty = place(ggg.Graph.from_arrays(np.zeros((0, 2)), np.zeros((0, 2), dtype=np.int64),
                                                    origin_latlon=tuple(parsed.origin_latlon)))
            except ggg.Error as ex:
                self.report({'ERROR'}, str(ex))
                return {'CANCELLED'}
            graph_obj, _surface = road_objects.build(
                context, empty, list(ggg.highway_classes()), [], parsed.name, text.name, None,
                target=target, with_frames=True, properties={"grammar": parsed.name})
            warning = target.warning
        elif graph_obj.get("grammar") not in (None, parsed.name) and text != texts.learned_text(graph_obj):
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
            frames.add_to(graph_obj, roads.Created())
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
        graph_obj = roads.road_graph_object(context.active_object)
        if graph_obj is None or graph_obj.type != 'MESH':
            self.report({'ERROR'}, "Select a road graph to grow (import roads, add an axiom or place a rule first)")
            return {'CANCELLED'}
        found = grammar_or_report(self, context)
        if found is None:
            return {'CANCELLED'}
        ggg, _text, parsed = found

        with graph_edit.object_mode(context, graph_obj):
            old = graph_edit.MeshGraph(graph_obj)
            if old.nonterminal_count == 0:
                self.report({'WARNING'}, "Nothing to grow: {} has no nonterminal vertices (symbol > 0); place a "
                            "rule first. The graph is unchanged.".format(graph_obj.name))
                return {'CANCELLED'}
            with roads.Progress(context, read_share=0.9, label="Growing roads") as progress:
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
                                                     class_widths(context, ggg, result))
                road_objects.rewrite(replacement)
                progress.step(1.0, "done")

        if graph_obj.get("grammar") not in (None, parsed.name):
            self.report({'WARNING'}, "{} was made with the grammar '{}', not '{}'".format(
                graph_obj.name, graph_obj["grammar"], parsed.name))
        message, budget = self._summary(graph_obj, report)
        self.report({'WARNING'} if budget else {'INFO'}, message)
        return {'FINISHED'}

    def _summary(self, graph_obj, report):
        done = plural(report["steps"], "step")
        if report["steps"] < self.steps:
            done += " of {}".format(self.steps)
        parts = ["Grew {}: {}, {}, {}, {}".format(
            graph_obj.name, done, plural(report["vertices"], "vertex"), plural(report["edges"], "edge"),
            plural(report["rewrites"], "rewrite"))]
        if report["embedding_edges"]:
            parts.append(plural(report["embedding_edges"], "embedding edge"))
        if report["missed_embeddings"]:
            parts.append("{} found no vertex".format(plural(report["missed_embeddings"], "embedding point")))
        if report["merged_vertices"]:
            parts.append("{} merged".format(plural(report["merged_vertices"], "placed vertex")))
        if report["refused"]:
            parts.append("{} refused (strict)".format(plural(report["refused"], "rewrite")))
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
            reason = "strict embedding refused all {}".format(plural(report["refused"], "rewrite"))
        else:
            reason = "none of its {} has a rule in the grammar '{}'".format(
                plural(old.nonterminal_count, "nonterminal"), parsed.name)
        return "Nothing was rewritten in {}: {}. The graph is unchanged.".format(graph_obj.name, reason)


classes = (ROADS_OT_load_grammar, ROADS_OT_save_grammar, ROADS_OT_add_axiom, ROADS_OT_place_rule, ROADS_OT_grow)
