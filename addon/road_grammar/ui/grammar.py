"""The Grammar panel of the sidebar's "Roads" tab: the scene's grammar, its rules, and the
grammar operators with their settings (Place Rule, Grow, Grow into Region with its region,
Stitch Cities)."""

from bpy.types import Panel

from ..data import texts
from ..data.roads import road_graph_object, selected_graphs
from ..operators.grammar import (ROADS_OT_add_axiom, ROADS_OT_grow, ROADS_OT_load_grammar, ROADS_OT_place_rule,
                                 ROADS_OT_save_grammar)
from ..operators.region import ROADS_OT_grow_region
from ..operators.stitch import ROADS_OT_stitch_cities
from .common import RoadsTab, job_progress, wrapped_labels

# Rules listed in the panel; a longer grammar shows the first ones and a count.
MAX_LISTED_RULES = 40


class VIEW3D_PT_roads_grammar(RoadsTab, Panel):
    bl_label = "Grammar"

    def draw(self, context):
        layout = self.layout
        settings = context.scene.road_grammar
        row = layout.row(align=True)
        row.template_ID(settings, "text", open=ROADS_OT_load_grammar.bl_idname)
        row = layout.row(align=True)
        row.operator(ROADS_OT_load_grammar.bl_idname, text="Load", icon='FILEBROWSER')
        row.operator(ROADS_OT_save_grammar.bl_idname, text="Save", icon='EXPORT')

        text, parsed, message = texts.try_active(context)
        if parsed is None:
            if text is not None:
                box = layout.box()
                box.label(text="Not a valid grammar", icon='ERROR')
                wrapped_labels(box, message)
            else:
                layout.label(text="No grammar loaded", icon='INFO')
            return

        box = layout.box()
        col = box.column(align=True)
        col.label(text="{}: {} rule{}".format(parsed.name, len(parsed.rules), "" if len(parsed.rules) == 1 else "s"),
                  icon='OUTLINER_DATA_GP_LAYER')
        lat, lon = parsed.origin_latlon
        col.label(text="Origin: {:.6f}, {:.6f}".format(lat, lon))
        if parsed.rules:
            # One row per rule: its symbol, then the size of S, its embedding points and how
            # often it was used in the network it was learned from.
            col = box.column(align=True)
            for rule in parsed.rules[:MAX_LISTED_RULES]:
                split = col.split(factor=0.3, align=True)
                split.label(text="{} ({})".format(rule["name"], rule["symbol"]))
                split.label(text="{} v, {} e, {} emb, {} uses".format(
                    rule["vertices"], rule["edges"], rule["embedding_points"], rule["uses"]))
            if len(parsed.rules) > MAX_LISTED_RULES:
                box.label(text="... and {} more rules".format(len(parsed.rules) - MAX_LISTED_RULES))

        layout.operator(ROADS_OT_add_axiom.bl_idname, icon='OUTLINER_OB_MESH')

        box = layout.box()
        box.label(text="Place at the 3D Cursor", icon='PIVOT_CURSOR')
        col = box.column(align=True)
        # The grammar whose rules are placed: empty for the scene's, or e.g. another city's.
        col.prop(settings, "place_grammar", text="")
        col.prop(settings, "rule", text="")
        col.prop(settings, "scale")
        op = box.operator(ROADS_OT_place_rule.bl_idname, icon='EMPTY_SINGLE_ARROW')
        op.grammar = settings.place_grammar.name if settings.place_grammar is not None else ""
        if settings.rule not in ('', 'NONE'):
            op.rule = settings.rule
        op.scale = settings.scale

        box = layout.box()
        graph = road_graph_object(context.active_object)
        box.label(text="Grow {}".format(graph.name) if graph is not None else "Grow (select a road graph)",
                  icon='FORCE_CURVE')
        col = box.column(align=True)
        col.prop(settings, "steps")
        col.prop(settings, "max_vertices")
        row = box.row(align=True)
        row.prop(settings, "tolerance_unit", expand=True)
        box.prop(settings, "tolerance" if settings.tolerance_unit == 'RELATIVE' else "tolerance_m")
        box.prop(settings, "strict")
        row = box.row()
        row.enabled = graph is not None
        op = row.operator(ROADS_OT_grow.bl_idname, icon='PLAY')
        for name in ROADS_OT_grow._FROM_SETTINGS:
            setattr(op, name, getattr(settings, name))

        box = layout.box()
        box.label(text="Grow into Region", icon='MESH_PLANE')
        box.prop(settings, "region")
        if settings.region is None:
            box.label(text="Or select a curve or mesh with the graph", icon='INFO')
        col = box.column(align=True)
        col.prop(settings, "region_seed")
        col.prop(settings, "region_max_placements")
        col.prop(settings, "region_patience")
        col.prop(settings, "region_max_vertices")
        box.prop(settings, "region_use_placed")
        box.prop(settings, "region_roundabouts")
        if not job_progress(box, ROADS_OT_grow_region, graph):
            row = box.row()
            row.enabled = graph is not None
            op = row.operator(ROADS_OT_grow_region.bl_idname, icon='PLAY')
            for name, setting in ROADS_OT_grow_region._FROM_SETTINGS.items():
                setattr(op, name, getattr(settings, setting))
            op.region = settings.region.name if settings.region is not None else ""

        _draw_stitch(layout, context, settings)


def _draw_stitch(layout, context, settings):
    """The Stitch Cities box: the two selected road graphs, their grammars, the button (the
    region and the settings are those of Grow into Region)."""
    box = layout.box()
    box.label(text="Stitch Cities", icon='AUTOMERGE_ON')
    active, others = selected_graphs(context)
    col = box.column(align=True)
    if active is None or len(others) != 1:
        col.label(text="Select two road graphs (the one to keep active)", icon='INFO')
    else:
        for obj, fallback in ((active, True), (others[0], False)):
            text = texts.city_grammar_text(context, obj, fallback)
            col.label(text="{}: {}".format(obj.name, text.name if text is not None else "no grammar"),
                      icon='OUTLINER_OB_MESH')
        col.label(text="{} is joined into {}".format(others[0].name, active.name))
    box.prop(settings, "stitch_share")
    box.label(text="Region, seed and budgets: as for Grow into Region", icon='INFO')
    if job_progress(box, ROADS_OT_stitch_cities, active):
        return
    row = box.row()
    row.enabled = active is not None and len(others) == 1
    op = row.operator(ROADS_OT_stitch_cities.bl_idname, icon='PLAY')
    for name, setting in ROADS_OT_stitch_cities._FROM_SETTINGS.items():
        setattr(op, name, getattr(settings, setting))
    op.region = settings.region.name if settings.region is not None else ""


classes = (VIEW3D_PT_roads_grammar,)
