"""The settings of the 3-D city (``scene.road_city``, shown in the sidebar's City panel):
Build City, the fly-through and rendering. The ``*_property`` functions declare each
setting once for the scene and the operators (operators.city), which take the scene's
values when invoked."""

import bpy
from bpy.props import EnumProperty, FloatProperty, IntProperty, StringProperty
from bpy.types import PropertyGroup

MODE_ITEMS = (
    ('PATH', "Shortest Path", "From one selected vertex of the road graph to the other (select two in Edit Mode)"),
    ('TOUR', "Tour", "A seeded tour that keeps to the major roads"),
)
HEIGHT_ITEMS = (
    ('STREET', "Street", "At eye height above the road, looking ahead"),
    ('DRONE', "Drone", "High above the roads, looking down ahead"),
)
ENGINE_ITEMS = (
    ('BLENDER_EEVEE', "Eevee", "Fast; works without a GPU through Mesa's software OpenGL"),
    ('CYCLES', "Cycles (CPU)", "Path tracing on the CPU: slower, physically lit"),
)


def seed_property():
    return IntProperty(name="Seed", description="Seed of the random choices (lots, heights)", default=1, min=0)


def sidewalk_property():
    return FloatProperty(name="Sidewalk", description="Width of the sidewalk between the kerb and the buildings",
                         default=3.0, min=0.0, soft_max=10.0, unit='LENGTH', subtype='DISTANCE')


def sun_elevation_property():
    return FloatProperty(name="Sun Elevation", description="Height of the sun above the horizon, in degrees",
                         default=35.0, min=1.0, max=90.0)


def sun_azimuth_property():
    return FloatProperty(name="Sun Azimuth", description="Direction the sunlight comes from, in degrees from north "
                         "(clockwise)", default=200.0, min=0.0, max=360.0)


def fly_properties():
    """Annotations shared by the fly-through operator and the scene settings."""
    return {
        "mode": EnumProperty(name="Path", items=MODE_ITEMS, default='TOUR'),
        "height": EnumProperty(name="Height", items=HEIGHT_ITEMS, default='DRONE'),
        "duration_s": FloatProperty(name="Duration", description="Length of the fly-through in seconds (at the "
                                    "scene's frame rate)", default=10.0, min=0.5, soft_max=120.0, unit='TIME_ABSOLUTE'),
        "seed": IntProperty(name="Seed", description="Seed of the tour", default=1, min=0),
        "smoothing_m": FloatProperty(name="Smoothing", description="Width of the smoothing window along the path: "
                                     "corners become arcs of about this size", default=25.0, min=0.0, soft_max=200.0,
                                     unit='LENGTH', subtype='DISTANCE'),
    }


class ROADS_PG_city(PropertyGroup):
    """Settings of the city operators (Roads sidebar, City panel)."""

    seed: seed_property()
    sidewalk_m: sidewalk_property()
    sun_elevation: sun_elevation_property()
    sun_azimuth: sun_azimuth_property()
    fly_mode: fly_properties()["mode"]
    fly_height: fly_properties()["height"]
    fly_duration_s: fly_properties()["duration_s"]
    fly_seed: fly_properties()["seed"]
    fly_smoothing_m: fly_properties()["smoothing_m"]
    engine: EnumProperty(name="Engine", items=ENGINE_ITEMS, default='BLENDER_EEVEE')
    resolution_x: IntProperty(name="Width", default=1280, min=16, max=16384, subtype='PIXEL')
    resolution_y: IntProperty(name="Height", default=720, min=16, max=16384, subtype='PIXEL')
    samples: IntProperty(name="Samples", description="Render samples (Eevee: anti-aliasing; Cycles: paths per "
                         "pixel)", default=16, min=1, max=4096)
    directory: StringProperty(name="Output", description="Folder for city.png and flythrough.mp4",
                              default="//render/", subtype='DIR_PATH')


classes = (ROADS_PG_city,)
pointers = ((bpy.types.Scene, "road_city", ROADS_PG_city),)
