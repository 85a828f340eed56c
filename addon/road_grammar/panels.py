"""The "Roads" tab of the 3D view's sidebar."""

from bpy.types import Panel

from . import georef, importer, native
from .operators import ROADS_OT_import_osm


def road_graph_object(obj):
    """The road graph ``obj`` is or belongs to (its surface), else None."""
    if obj is None:
        return None
    if obj.get(importer.GRAPH_KEY):
        return obj
    if obj.get(importer.SURFACE_KEY) and obj.parent is not None and obj.parent.get(importer.GRAPH_KEY):
        return obj.parent
    return None


class VIEW3D_PT_roads(Panel):
    bl_space_type = 'VIEW_3D'
    bl_region_type = 'UI'
    bl_category = "Roads"
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
            if georef.KEY_LAT in scene:
                col.label(text="Lat/Lon: {:.6f}, {:.6f}".format(scene[georef.KEY_LAT], scene[georef.KEY_LON]))
            _wrapped_labels(col, str(scene[georef.KEY_SRID]))


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
