"""The Roads panel of the sidebar's "Roads" tab (import, the active road graph, the scene's
georeference) and the File > Import menu entry."""

import bpy
from bpy.types import Panel

from ..core import georef, native
from ..core.names import SURFACE_KEY
from ..data.roads import road_graph_object
from ..operators.importer import ROADS_OT_import_osm
from .common import RoadsTab, wrapped_labels


class VIEW3D_PT_roads(RoadsTab, Panel):
    bl_label = "Roads"

    def draw(self, context):
        layout = self.layout
        module, message = native.status()
        if module is None:
            box = layout.box()
            box.label(text="Native module not available", icon='ERROR')
            wrapped_labels(box, message)
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
                (child for child in graph.children if child.get(SURFACE_KEY)), None)
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
                wrapped_labels(col, str(scene[georef.KEY_SRID]))


def menu_import(self, context):
    self.layout.operator(ROADS_OT_import_osm.bl_idname, text="OpenStreetMap Roads (.osm/.pbf)")


classes = (VIEW3D_PT_roads,)
menus = ((bpy.types.TOPBAR_MT_file_import, menu_import),)
