"""The City panel of the sidebar's "Roads" tab: Build City, the fly-through and rendering,
with their settings (scene.road_city); a running job (the city's plan, a render) shows its
progress instead of its buttons."""

from bpy.types import Panel

from ..display import city
from ..operators.city import ROADS_OT_build_city, ROADS_OT_flythrough, ROADS_OT_render_city
from .common import RoadsTab, job_progress, run_button


class VIEW3D_PT_roads_city(RoadsTab, Panel):
    bl_label = "City"

    def draw(self, context):
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
        run_button(box, graph, settings, ROADS_OT_build_city, icon='MOD_BUILD')
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
        op = row.operator(ROADS_OT_flythrough.bl_idname, icon='ANIM')
        for name, setting in ROADS_OT_flythrough._FROM_SETTINGS.items():
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
        if job_progress(box, ROADS_OT_render_city, context.scene):
            return
        row = box.row(align=True)
        for animation, text, icon in ((False, "Still", 'RENDER_STILL'), (True, "Animation", 'RENDER_ANIMATION')):
            op = row.operator(ROADS_OT_render_city.bl_idname, text=text, icon=icon)
            op.animation = animation
            for name in ROADS_OT_render_city._FROM_SETTINGS:
                setattr(op, name, getattr(settings, name))


classes = (VIEW3D_PT_roads_city,)
