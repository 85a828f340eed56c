"""The "Roads" tab of the 3D view's sidebar: the Roads panel (import, the active road
graph, the scene's georeference) and the Grammar panel (the scene's grammar, its rules,
and the grammar operators with their settings, Grow into Region's region among them)."""

from bpy.types import Panel

from . import georef, grammar, importer, native
from .grammar_ops import (ROADS_OT_add_axiom, ROADS_OT_grow, ROADS_OT_grow_region, ROADS_OT_load_grammar,
                          ROADS_OT_place_rule, ROADS_OT_save_grammar)
from .operators import ROADS_OT_import_osm
from .stitch_ops import ROADS_OT_stitch_cities, city_grammar_text, selected_graphs

road_graph_object = importer.road_graph_object

# Rules listed in the panel; a longer grammar shows the first ones and a count.
MAX_LISTED_RULES = 40


class _RoadsTab:
    """Where the panels are: the "Roads" tab of the 3D view's sidebar."""

    bl_space_type = 'VIEW_3D'
    bl_region_type = 'UI'
    bl_category = "Roads"


class VIEW3D_PT_roads(_RoadsTab, Panel):
    bl_label = "Roads"

    def draw(self, context):
        layout = self.layout
        module, message = native.status()
        if module is None:
            box = layout.box()
            box.label(text="Native module not available", icon='ERROR')
            _wrapped_labels(box, message)
        layout.operator(ROADS_OT_import_osm.bl_idname, text="Import OpenStreetMap", icon='IMPORT')

        obj = context.active_object
        graph = road_graph_object(obj)
        if graph is None:
            layout.label(text="No road graph selected")
        else:
            box = layout.box()
            box.label(text=graph.name, icon='OUTLINER_OB_MESH')
            mesh = graph.data
            col = box.column(align=True)
            col.label(text="Vertices: {:,}".format(len(mesh.vertices)))
            col.label(text="Edges: {:,}".format(len(mesh.edges)))
            if "total_length_m" in graph:
                col.label(text="Length: {:.2f} km".format(graph["total_length_m"] / 1000.0))
            if "origin_lat" in graph:
                col.label(text="Origin: {:.6f}, {:.6f}".format(graph["origin_lat"], graph["origin_lon"]))
            surface_obj = obj if obj is not graph else next(
                (child for child in graph.children if child.get(importer.SURFACE_KEY)), None)
            if surface_obj is not None:
                col.label(text="Surface: {}".format(surface_obj.name))

        scene = context.scene
        if georef.has_georef(scene):
            box = layout.box()
            box.label(text="Scene Georeference", icon='WORLD')
            col = box.column(align=True)
            origin = georef.origin(scene)
            if origin is not None:
                col.label(text="Lat/Lon: {:.6f}, {:.6f}".format(*origin))
            if georef.KEY_SRID in scene:
                _wrapped_labels(col, str(scene[georef.KEY_SRID]))


class VIEW3D_PT_roads_grammar(_RoadsTab, Panel):
    bl_label = "Grammar"

    def draw(self, context):
        layout = self.layout
        settings = context.scene.road_grammar
        row = layout.row(align=True)
        row.template_ID(settings, "text", open=ROADS_OT_load_grammar.bl_idname)
        row = layout.row(align=True)
        row.operator(ROADS_OT_load_grammar.bl_idname, text="Load", icon='FILEBROWSER')
        row.operator(ROADS_OT_save_grammar.bl_idname, text="Save", icon='EXPORT')

        text, parsed, message = grammar.try_active(context)
        if parsed is None:
            if text is not None:
                box = layout.box()
                box.label(text="Not a valid grammar", icon='ERROR')
                _wrapped_labels(box, message)
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
        row = box.row()
        row.enabled = graph is not None
        op = row.operator(ROADS_OT_grow_region.bl_idname, icon='PLAY')
        for name, setting in ROADS_OT_grow_region._FROM_SETTINGS.items():
            setattr(op, name, getattr(settings, setting))
        op.region = settings.region.name if settings.region is not None else ""

        _draw_stitch(layout, context, settings)


class VIEW3D_PT_roads_city(_RoadsTab, Panel):
    bl_label = "City"

    def draw(self, context):
        from . import city, city_ops

        layout = self.layout
        settings = context.scene.road_city
        graph = city.city_graph(context)
        box = layout.box()
        box.label(text="Build {}".format(graph.name) if graph is not None else "Build (select a road graph)",
                  icon='HOME')
        col = box.column(align=True)
        col.prop(settings, "seed")
        col.prop(settings, "sidewalk_m")
        col.prop(settings, "sun_elevation")
        col.prop(settings, "sun_azimuth")
        row = box.row()
        row.enabled = graph is not None
        op = row.operator(city_ops.ROADS_OT_build_city.bl_idname, icon='MOD_BUILD')
        for name in city_ops.ROADS_OT_build_city._FROM_SETTINGS:
            setattr(op, name, getattr(settings, name))
        existing = city.find_collection(graph) if graph is not None else None
        if existing is not None:
            box.label(text="{:,} blocks, {:,} buildings".format(existing.get("blocks", 0), existing.get("buildings", 0)))

        box = layout.box()
        box.label(text="Fly-Through", icon='CAMERA_DATA')
        box.row().prop(settings, "fly_mode", expand=True)
        box.row().prop(settings, "fly_height", expand=True)
        col = box.column(align=True)
        col.prop(settings, "fly_duration_s")
        col.prop(settings, "fly_smoothing_m")
        if settings.fly_mode == 'TOUR':
            col.prop(settings, "fly_seed")
        else:
            box.label(text="Pick two vertices in Edit Mode", icon='INFO')
        row = box.row()
        row.enabled = graph is not None
        op = row.operator(city_ops.ROADS_OT_flythrough.bl_idname, icon='ANIM')
        for name, setting in city_ops.ROADS_OT_flythrough._FROM_SETTINGS.items():
            setattr(op, name, getattr(settings, setting))

        box = layout.box()
        box.label(text="Render", icon='RENDER_STILL')
        col = box.column(align=True)
        col.prop(settings, "engine", text="")
        row = col.row(align=True)
        row.prop(settings, "resolution_x")
        row.prop(settings, "resolution_y")
        col.prop(settings, "samples")
        box.prop(settings, "directory")
        row = box.row(align=True)
        for animation, text, icon in ((False, "Still", 'RENDER_STILL'), (True, "Animation", 'RENDER_ANIMATION')):
            op = row.operator(city_ops.ROADS_OT_render_city.bl_idname, text=text, icon=icon)
            op.animation = animation
            for name in city_ops.ROADS_OT_render_city._FROM_SETTINGS:
                setattr(op, name, getattr(settings, name))


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
            text = city_grammar_text(context, obj, fallback)
            col.label(text="{}: {}".format(obj.name, text.name if text is not None else "no grammar"),
                      icon='OUTLINER_OB_MESH')
        col.label(text="{} is joined into {}".format(others[0].name, active.name))
    box.prop(settings, "stitch_share")
    box.label(text="Region, seed and budgets: as for Grow into Region", icon='INFO')
    row = box.row()
    row.enabled = active is not None and len(others) == 1
    op = row.operator(ROADS_OT_stitch_cities.bl_idname, icon='PLAY')
    for name, setting in ROADS_OT_stitch_cities._FROM_SETTINGS.items():
        setattr(op, name, getattr(settings, setting))
    op.region = settings.region.name if settings.region is not None else ""


def _wrapped_labels(layout, text, width=48):
    """Long messages as several labels (a label does not wrap)."""
    line = ""
    for word in text.split():
        if line and len(line) + 1 + len(word) > width:
            layout.label(text=line)
            line = word
        else:
            line = word if not line else line + " " + word
    if line:
        layout.label(text=line)
