"""Add-on preferences: the road widths used when OpenStreetMap does not tag one."""

from bpy.props import CollectionProperty, FloatProperty, StringProperty
from bpy.types import AddonPreferences, PropertyGroup

from ..core import native
from ..data.preferences import ADDON, DEFAULT_LANE_WIDTH

# Its operator (operators.preferences).
RESET_WIDTHS = "roads.reset_widths"


class ROADS_PG_class_width(PropertyGroup):
    """Default width of one highway class (the item's name is the class name)."""

    width: FloatProperty(
        name="Width",
        description="Width of roads of this class that have neither a width nor a lanes tag",
        default=6.0,
        min=0.1,
        soft_max=40.0,
        precision=2,
        unit='LENGTH',
        subtype='DISTANCE',
    )


class ROADS_AP_preferences(AddonPreferences):
    bl_idname = ADDON

    lane_width: FloatProperty(
        name="Lane Width",
        description="Width of one lane, for roads tagged with lanes but not with width",
        default=DEFAULT_LANE_WIDTH,
        min=0.5,
        soft_max=6.0,
        precision=2,
        unit='LENGTH',
        subtype='DISTANCE',
    )
    class_widths: CollectionProperty(type=ROADS_PG_class_width)
    # Class names the list was last filled for, to notice a native module with new classes.
    filled_for: StringProperty(options={'HIDDEN'})

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.prop(self, "lane_width")
        layout.label(text="Width per highway class, used when a road has no width or lanes tag:")
        module, message = native.status()
        if module is None:
            layout.label(text=message, icon='ERROR')
        if len(self.class_widths) == 0:
            layout.operator(RESET_WIDTHS, text="Load Default Widths")
            return
        grid = layout.grid_flow(row_major=True, columns=2, even_columns=True)
        for item in self.class_widths:
            grid.prop(item, "width", text=item.name.replace("_", " ").title())
        layout.operator(RESET_WIDTHS, icon='LOOP_BACK')


classes = (ROADS_PG_class_width, ROADS_AP_preferences)
