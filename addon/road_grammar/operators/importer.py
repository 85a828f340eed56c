"""Importing OpenStreetMap roads (and GeoJSON, .ggraph) as a road graph mesh with road
surfaces."""

from bpy.props import BoolProperty, EnumProperty, FloatProperty, StringProperty
from bpy.types import Operator
from bpy_extras.io_utils import ImportHelper

from ..core import georef, native
from ..core.names import object_name
from ..data import roads
from ..data import preferences
from ..display import road_objects
from .common import input_file_or_report

HIGHWAY_ITEMS = (
    ('DRIVABLE', "Drivable", "Roads for cars: motorway to residential, links and living streets"),
    ('ALL', "All", "Every way with a highway tag, footways and paths included"),
    ('CUSTOM', "Custom", "The comma-separated highway values given below"),
)


class ROADS_OT_import_osm(Operator, ImportHelper):
    """Import the road network of an OpenStreetMap file as a graph mesh and road surfaces"""

    bl_idname = "roads.import_osm"
    bl_label = "Import OpenStreetMap Roads"
    bl_options = {'REGISTER', 'UNDO'}

    filename_ext = ".osm"
    filter_glob: StringProperty(
        default="*.osm;*.pbf;*.osm.bz2;*.osm.gz;*.geojson;*.json;*.ggraph",
        options={'HIDDEN'},
    )
    highways: EnumProperty(
        name="Highways",
        description="Which ways with a highway tag become roads",
        items=HIGHWAY_ITEMS,
        default='DRIVABLE',
    )
    highways_custom: StringProperty(
        name="Highway Values",
        description="Comma-separated highway values to import, e.g. primary,secondary,residential",
        default="primary,secondary,tertiary,residential",
    )
    keep_shape_nodes: BoolProperty(
        name="Keep Shape Nodes",
        description="Make every OSM node a vertex instead of keeping the degree-2 chains "
        "as the geometry of one edge",
        default=False,
    )
    consolidate_m: FloatProperty(
        name="Consolidate",
        description="Merge intersections closer than this (dual carriageways, roundabouts); 0 = off",
        default=0.0,
        min=0.0,
        soft_max=50.0,
        unit='LENGTH',
        subtype='DISTANCE',
    )
    build_surface: BoolProperty(
        name="Road Surfaces",
        description="Also make an object with flat road ribbons of each road's width "
        "(Geometry Nodes, editable)",
        default=True,
    )

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        layout.prop(self, "highways")
        if self.highways == 'CUSTOM':
            layout.prop(self, "highways_custom")
        layout.prop(self, "keep_shape_nodes")
        layout.prop(self, "consolidate_m")
        layout.prop(self, "build_surface")

    def _highway_spec(self):
        if self.highways == 'CUSTOM':
            return ",".join(v.strip() for v in self.highways_custom.split(",") if v.strip())
        return self.highways.lower()

    def execute(self, context):
        path = input_file_or_report(self)
        if path is None:
            return {'CANCELLED'}
        highways = self._highway_spec()
        if not highways:
            self.report({'ERROR'}, "No highway values given for the custom highway filter")
            return {'CANCELLED'}
        ggg = native.load_or_report(self)
        if ggg is None:
            return {'CANCELLED'}

        prefs = preferences.get(context)
        # A scene that is georeferenced already: the graph is read into its frame.
        target = georef.target(context.scene)
        with roads.Progress(context) as progress:
            try:
                graph = ggg.read_graph(
                    path,
                    highways=highways,
                    keep_shape_nodes=self.keep_shape_nodes,
                    consolidate_m=self.consolidate_m,
                    origin_latlon=target.origin,
                    progress=progress,
                )
            except ggg.Error as ex:
                self.report({'ERROR'}, str(ex))
                return {'CANCELLED'}
            if graph.edge_count == 0:
                self.report({'ERROR'}, "{}: no roads matching '{}'".format(path, highways))
                return {'CANCELLED'}

            classes = list(ggg.highway_classes())
            widths = ggg.road_widths(graph, class_widths=preferences.class_width_table(prefs, ggg),
                                     lane_width=prefs.lane_width)
            options = {
                "highways": highways,
                "keep_shape_nodes": self.keep_shape_nodes,
                "consolidate_m": self.consolidate_m,
            }
            graph_obj, _surface_obj = road_objects.build(
                context, graph, classes, widths, object_name(path), path, options,
                with_surface=self.build_surface, progress=progress, target=target,
            )

        if target.warning:
            self.report({'WARNING'}, target.warning)
        self.report(
            {'INFO'},
            "Imported {}: {} vertices, {} edges, {:.1f} km of road".format(
                graph_obj.name, graph.vertex_count, graph.edge_count, graph.total_length_m / 1000.0
            ),
        )
        return {'FINISHED'}


classes = (ROADS_OT_import_osm,)
