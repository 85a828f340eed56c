"""The Patterns panel of the Roads sidebar tab: Find Similar, Analyze with its settings,
the isogroups of the last analysis in a list (choosing one highlights it), and Replace (the
chosen isogroup's occurrences replaced by a stored piece)."""

from bpy.types import Panel, UIList

from ..core.analysis import StaleAnalysis
from ..core.text import compact
from ..data import analysis
from ..data.roads import road_graph_object
from ..operators.analysis import (ROADS_OT_analyze, ROADS_OT_clear_patterns, ROADS_OT_find_similar,
                                  ROADS_OT_select_isogroup, ROADS_OT_show_patterns)
from ..operators.replacement import ROADS_OT_replace_isogroup, ROADS_OT_store_replacement
from .common import RoadsTab, constraints, header, run_button, swatch_cells, wrapped_labels

# Columns of the isogroup list after the colour swatch: header and width (a fraction of
# the rest of the row, left to right). The sidebar is narrow, so the headers are short
# (docs/blender.md explains them): order (pattern vertices), occurrences, non-overlapping
# occurrences, gain. The rank is the place in the list (and in the details below it).
_COLUMNS = (("Order", 0.25), ("Occ.", 0.34), ("N-o.", 0.5), ("Gain", 1.0))


class ROADS_UL_isogroups(UIList):
    """Isogroups of an analysis, best first: colour, order, occurrences, non-overlapping
    occurrences and gain."""

    def draw_item(self, context, layout, data, item, icon, active_data, active_property, index=0, flt_flag=0):
        if self.layout_type == 'GRID':
            layout.alignment = 'CENTER'
            layout.label(text=str(item.rank))
            return
        order, count, non_overlapping, gain = swatch_cells(layout, item, _COLUMNS)
        order.label(text=str(item.order))
        count.label(text=compact(item.frequency))
        non_overlapping.label(text=compact(item.non_overlapping_count))
        gain.label(text=compact(item.gain))


class VIEW3D_PT_roads_patterns(RoadsTab, Panel):
    bl_label = "Patterns"

    def draw(self, context):
        layout = self.layout
        settings = context.scene.road_analysis
        graph = road_graph_object(context.active_object)

        box = layout.box()
        box.label(text="Find Similar", icon='VIEWZOOM')
        col = box.column(align=True)
        col.prop(settings, "tolerance")
        col.prop(settings, "scale", text="")
        row = box.row()
        row.enabled = graph is not None
        op = row.operator(ROADS_OT_find_similar.bl_idname, icon='RESTRICT_SELECT_OFF')
        op.tolerance, op.scale = settings.tolerance, settings.scale
        if graph is not None and graph.mode != 'EDIT':
            box.label(text="Select a block in Edit Mode")

        box = layout.box()
        box.label(text="Analyze {}".format(graph.name) if graph is not None else "Analyze (select a road graph)",
                  icon='VIEWZOOM')
        col = box.column(align=True)
        row = col.row(align=True)
        row.prop(settings, "angle_cells", text="Grid")
        row.prop(settings, "distance_cells", text="")
        col.prop(settings, "max_order")
        col.prop(settings, "min_count")
        row = col.row(align=True)
        row.prop(settings, "full", toggle=True)
        sub = row.row(align=True)
        sub.enabled = not settings.full
        sub.prop(settings, "cut", text="Cut")
        col.prop(settings, "scale", text="")
        col = box.column(align=True)
        col.prop(settings, "use_seed")
        col.prop(settings, "max_stored")
        col.prop(settings, "overview_count")
        constraints(col, settings)
        run_button(box, graph, settings, ROADS_OT_analyze)


class VIEW3D_PT_roads_isogroups(RoadsTab, Panel):
    bl_label = "Isogroups"
    bl_parent_id = "VIEW3D_PT_roads_patterns"

    def draw(self, context):
        layout = self.layout
        graph = road_graph_object(context.active_object)
        if graph is None:
            layout.label(text="No road graph selected")
            return
        result = graph.road_analysis
        if not result.has_result():
            layout.label(text="Not analysed yet")
            return
        col = layout.column(align=True)
        col.label(text="{:,} isogroups, {:.2f} s".format(result.listed, result.seconds))
        if len(result.isogroups) < result.listed:
            col.label(text="The best {:,} are kept".format(len(result.isogroups)))
        wrapped_labels(col, result.parameters, width=28)
        if result.stopped_by_budget:
            col.label(text="Stopped early (budget)", icon='ERROR')
        stale = None
        if graph.mode != 'EDIT':  # in Edit Mode, reading the mesh on every redraw is too costly
            try:
                analysis.check_current(graph, topology=False)
            except StaleAnalysis as ex:
                stale = str(ex)
        if stale is not None:
            box = layout.box()
            box.label(text="Out of date", icon='ERROR')
            wrapped_labels(box, stale, width=28)

        header(layout, _COLUMNS)
        layout.template_list("ROADS_UL_isogroups", "", result, "isogroups", result, "active_index", rows=8)

        index = result.active_index
        if 0 <= index < len(result.isogroups):
            item = result.isogroups[index]
            box = layout.box()
            col = box.column(align=True)
            col.label(text="Isogroup {}".format(item.rank))
            col.label(text="{} vertices, {} edges".format(item.order, item.edge_count))
            col.label(text="{:,} occurrences".format(item.frequency))
            col.label(text="{:,} non-overlapping{}".format(item.non_overlapping_count,
                                                           " (exact)" if item.selection_exact else ""))
            wrapped_labels(col, "by " + item.selection_method, width=28)
            col.label(text="Gain {:,.1f}".format(item.gain))
            col.label(text="Score {:,.1f}".format(item.score))
            col.label(text="Size {:.1f} m, aspect {:.2f}".format(item.size_m, item.aspect))
            col.label(text="{} leaves, irregular {:.1f}\u00b0".format(item.leaves, item.irregularity_deg))
            if item.parent:
                col.label(text="Grew from isogroup {}".format(item.parent))
            col = box.column(align=True)
            op = col.operator(ROADS_OT_select_isogroup.bl_idname, text="Select Occurrences",
                              icon='RESTRICT_SELECT_OFF')
            op.index, op.only_non_overlapping = index, False
            op = col.operator(ROADS_OT_select_isogroup.bl_idname, text="Select Non-Overlapping")
            op.index, op.only_non_overlapping = index, True
        row = layout.row(align=True)
        op = row.operator(ROADS_OT_show_patterns.bl_idname, text="Overview", icon='COLOR')
        op.count = context.scene.road_analysis.overview_count
        row.operator(ROADS_OT_clear_patterns.bl_idname, text="Clear", icon='X')


class VIEW3D_PT_roads_replace(RoadsTab, Panel):
    bl_label = "Replace"
    bl_parent_id = "VIEW3D_PT_roads_patterns"

    def draw(self, context):
        layout = self.layout
        settings = context.scene.road_replacement
        graph = road_graph_object(context.active_object)

        box = layout.box()
        box.label(text="Piece", icon='MESH_CIRCLE')
        col = box.column(align=True)
        if settings.has_piece():
            col.label(text="{:,} vertices, {:,} streets".format(settings.vertex_count, settings.edge_count))
            col.label(text="{:,.1f} x {:,.1f} m as drawn".format(settings.width_m, settings.height_m))
            wrapped_labels(col, "from " + settings.source, width=28)
        else:
            col.label(text="No piece stored")
        row = box.row()
        row.enabled = graph is not None
        row.operator(ROADS_OT_store_replacement.bl_idname, text="Store Selection as Piece",
                     icon='RESTRICT_SELECT_OFF').object = ""
        if graph is not None and graph.mode != 'EDIT':
            box.label(text="Select its vertices in Edit Mode")
        box.prop(settings, "piece_object", text="")
        row = box.row()
        row.enabled = graph is not None and settings.piece_object is not None
        op = row.operator(ROADS_OT_store_replacement.bl_idname, text="Store Object as Piece", icon='OBJECT_DATA')
        op.object = settings.piece_object.name if settings.piece_object is not None else ""

        box = layout.box()
        box.label(text="Replace", icon='MOD_BOOLEAN')
        col = box.column(align=True)
        result = graph.road_analysis if graph is not None else None
        index = result.active_index if result is not None else -1
        chosen = result is not None and result.has_result() and 0 <= index < len(result.isogroups)
        if graph is None:
            col.label(text="No road graph selected")
        elif not result.has_result():
            col.label(text="Analyze first")
        elif not chosen:
            col.label(text="Choose an isogroup in the list")
        else:
            item = result.isogroups[index]
            col.label(text="Isogroup {}: {} vertices".format(item.rank, item.order))
            col.label(text="{:,} non-overlapping occurrences".format(item.non_overlapping_count))
        row = box.row()
        row.enabled = chosen and settings.has_piece()
        op = row.operator(ROADS_OT_replace_isogroup.bl_idname, text="Replace", icon='PLAY')
        op.index = index if chosen else -1


classes = (ROADS_UL_isogroups, VIEW3D_PT_roads_patterns, VIEW3D_PT_roads_isogroups, VIEW3D_PT_roads_replace)
