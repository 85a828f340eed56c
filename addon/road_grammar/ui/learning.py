"""The Learn panel of the Roads sidebar tab: Learn with its settings, and the grammar learned
from the active road graph: its numbers, the level shown (a slider) and its rules in a list
(choosing one highlights its instances)."""

from bpy.types import Panel, UIList

from ..core.text import compact, plural, size_lines
from ..data import analysis, texts
from ..data.roads import road_graph_object
from ..display import rules
from ..operators.grammar import ROADS_OT_place_rule, ROADS_OT_save_grammar
from ..operators.learning import ROADS_OT_learn, ROADS_OT_show_level
from .common import RoadsTab, constraints, header, run_button, swatch_cells, wrapped_labels

# Columns of the rule list after the colour swatch: header and width (a fraction of the
# rest of the row, left to right): the rule's symbol name, its level, its uses (instances)
# and the vertices of its right-hand side.
_COLUMNS = (("Rule", 0.34), ("Level", 0.33), ("Uses", 0.5), ("Verts", 1.0))


class ROADS_UL_learned_rules(UIList):
    """Rules of a learned grammar: colour, name, level, uses and vertices."""

    def draw_item(self, context, layout, data, item, icon, active_data, active_property, index=0, flt_flag=0):
        if self.layout_type == 'GRID':
            layout.alignment = 'CENTER'
            layout.label(text=item.name)
            return
        name, level, uses, vertices = swatch_cells(layout, item, _COLUMNS)
        name.label(text=item.name)
        level.label(text=str(item.level))
        uses.label(text=compact(item.uses))
        vertices.label(text=str(item.vertex_count))


class VIEW3D_PT_roads_learn(RoadsTab, Panel):
    bl_label = "Learn"

    def draw(self, context):
        layout = self.layout
        settings = context.scene.road_learning
        graph = road_graph_object(context.active_object)

        box = layout.box()
        box.label(text="Learn from {}".format(graph.name) if graph is not None else "Learn (select a road graph)",
                  icon='OUTLINER_DATA_GP_LAYER')
        col = box.column(align=True)
        row = col.row(align=True)
        row.prop(settings, "angle_cells", text="Grid")
        row.prop(settings, "distance_cells", text="")
        col.prop(settings, "cut", text="Cut")
        col.prop(settings, "max_order")
        col.prop(settings, "levels")
        col.prop(settings, "complete")
        box.row(align=True).prop(settings, "mode", expand=True)
        box.prop(settings, "use_seed")
        constraints(box.column(align=True), settings)
        run_button(box, graph, settings, ROADS_OT_learn)


class VIEW3D_PT_roads_learned_rules(RoadsTab, Panel):
    bl_label = "Learned Grammar"
    bl_parent_id = "VIEW3D_PT_roads_learn"

    def draw(self, context):
        layout = self.layout
        graph = road_graph_object(context.active_object)
        if graph is None:
            layout.label(text="No road graph selected")
            return
        result = graph.road_learning
        if not result.has_result():
            layout.label(text="Nothing learned yet")
            return
        stats = result.stats_dict()
        roundtrip = stats.get("roundtrip", {})
        axiom = stats.get("axiom", {})
        col = layout.column(align=True)
        col.label(text="{}, {}, {:.2f} s".format(plural(len(result.rules), "rule"),
                                                  plural(result.levels, "level"), result.seconds))
        col.label(text="{} ({})".format(plural(stats.get("instances", 0), "instance"), result.mode))
        col.label(text="Axiom: {:,} v, {:,} e".format(axiom.get("vertices", 0), axiom.get("edges", 0)))
        for line in size_lines(stats):
            col.label(text=line)
        col.label(text="Round trip: {}, max {:.3g} m".format(
            "same edges" if roundtrip.get("edges_equal") else "edges differ",
            roundtrip.get("max_displacement_m", 0.0)), icon='CHECKMARK' if roundtrip.get("edges_equal") else 'ERROR')
        wrapped_labels(col, result.parameters, width=28)

        text = result.text
        if text is None:
            box = layout.box()
            box.label(text="The grammar's text is gone", icon='ERROR')
            box.label(text="Learn again")
            return
        col = layout.column(align=True)
        col.label(text=text.name, icon='TEXT')
        active = texts.active_text(context) == text
        if not active:
            col.label(text="Not the scene's grammar", icon='INFO')
        if graph.mode != 'EDIT' and result.topology and analysis.mesh_checksum(graph) != result.topology:
            col.label(text="The graph changed since", icon='ERROR')

        row = layout.row(align=True)
        row.prop(result, "level", text="Level")
        row.label(text="of {}".format(result.levels))
        problem = rules.display_problems.get(graph.name)
        if problem is not None:
            box = layout.box()
            box.label(text="Cannot show the level", icon='ERROR')
            wrapped_labels(box, problem, width=28)

        header(layout, _COLUMNS)
        layout.template_list("ROADS_UL_learned_rules", "", result, "rules", result, "active_rule", rows=6)

        index = result.active_rule
        if 0 <= index < len(result.rules):
            item = result.rules[index]
            box = layout.box()
            col = box.column(align=True)
            col.label(text="{} (symbol {}), level {}".format(item.name, item.symbol, item.level))
            col.label(text="{:,} uses".format(item.uses))
            col.label(text="{} vertices, {} edges".format(item.vertex_count, item.edge_count))
            col.label(text="{} nonterminals, {} embedding".format(item.nonterminals, item.embedding_points))
            if active:
                op = box.operator(ROADS_OT_place_rule.bl_idname, icon='EMPTY_SINGLE_ARROW')
                try:
                    op.rule = item.name
                except TypeError:  # the text was edited and no longer has the rule
                    pass
                op.scale = context.scene.road_grammar.scale
        row = layout.row(align=True)
        op = row.operator(ROADS_OT_show_level.bl_idname, text="All Rules", icon='COLOR')
        op.level, op.rule = -1, -1
        sub = row.row(align=True)
        sub.enabled = active
        sub.operator(ROADS_OT_save_grammar.bl_idname, text="Save", icon='EXPORT')


classes = (ROADS_UL_learned_rules, VIEW3D_PT_roads_learn, VIEW3D_PT_roads_learned_rules)
