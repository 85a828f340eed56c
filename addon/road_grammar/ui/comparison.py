"""The Compare panel of the sidebar's "Roads" tab: which two road graphs Compare takes, its
button, and the last comparison of the active graph (``object.road_compare``) as a table:
each measure of both networks, then the distances."""

from bpy.types import Panel

from ..core.comparison import distance_rows, measure_rows
from ..data import roads
from ..data.analysis import mesh_checksum
from ..operators.comparison import ROADS_OT_compare_graphs
from .common import RoadsTab, columns_of, wrapped_labels

# (header, share of the width) of the table's columns: measure, A, B.
_COLUMNS = (("Measure", 0.5), ("A", 0.5), ("B", 1.0))


def _meaning(layout, meaning):
    if meaning:
        col = layout.column(align=True)
        col.enabled = False
        wrapped_labels(col, meaning, width=40)


class VIEW3D_PT_roads_compare(RoadsTab, Panel):
    bl_label = "Compare"
    bl_options = {'DEFAULT_CLOSED'}

    def draw(self, context):
        layout = self.layout
        active, others = roads.selected_graphs(context)
        box = layout.box()
        if active is None:
            box.label(text="Select two road graphs (the one to compare active)", icon='INFO')
        elif len(others) != 1:
            box.label(text="Select one other road graph" if not others else
                      "{} others are selected: select one".format(len(others)), icon='INFO')
        else:
            box.label(text="{} with {}".format(active.name, others[0].name), icon='ARROW_LEFTRIGHT')
        row = box.row()
        row.enabled = active is not None and len(others) == 1
        row.operator(ROADS_OT_compare_graphs.bl_idname, icon='ARROW_LEFTRIGHT')

        graph = roads.road_graph_object(context.active_object)
        if graph is None or graph.type != 'MESH':
            return
        kept = graph.road_compare
        result = kept.stored()
        if result is None:
            return
        box = layout.box()
        col = box.column(align=True)
        col.label(text="A: {}".format(graph.name))
        col.label(text="B: {}".format(kept.other))
        if graph.mode != 'EDIT' and kept.topology and mesh_checksum(graph) != kept.topology:
            col.label(text="{} changed since".format(graph.name), icon='ERROR')
        box.prop(kept, "show_meanings", icon='TRIA_DOWN' if kept.show_meanings else 'TRIA_RIGHT', emboss=False)

        col = box.column(align=True)
        for cell, (name, _factor) in zip(columns_of(col.row(align=True), _COLUMNS), _COLUMNS):
            cell.label(text=name)
        for _key, label, a, b, meaning in measure_rows(result):
            for cell, text in zip(columns_of(col.row(align=True), _COLUMNS), (label, a, b)):
                cell.label(text=text)
            if kept.show_meanings:
                _meaning(col, meaning)

        col = box.column(align=True)
        col.label(text="Distances (0: alike, 1: most unlike)")
        for _key, label, text, meaning in distance_rows(result):
            split = col.row(align=True).split(factor=0.5, align=True)
            split.label(text=label)
            split.label(text=text)
            if kept.show_meanings:
                _meaning(col, meaning)


classes = (VIEW3D_PT_roads_compare,)
