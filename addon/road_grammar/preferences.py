"""Add-on preferences: the road widths used when OpenStreetMap does not tag one."""

from bpy.props import CollectionProperty, FloatProperty, StringProperty
from bpy.types import AddonPreferences, Operator, PropertyGroup

from . import native

DEFAULT_LANE_WIDTH = 3.25


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
    bl_idname = __package__

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
            layout.operator(ROADS_OT_reset_widths.bl_idname, text="Load Default Widths")
            return
        grid = layout.grid_flow(row_major=True, columns=2, even_columns=True)
        for item in self.class_widths:
            grid.prop(item, "width", text=item.name.replace("_", " ").title())
        layout.operator(ROADS_OT_reset_widths.bl_idname, icon='LOOP_BACK')


def get(context):
    """The add-on's preferences."""
    return context.preferences.addons[__package__].preferences


def ensure_class_widths(prefs, ggg):
    """Add an item for each class of the module that the list lacks (keeps user edits)."""
    classes = list(ggg.highway_classes())
    key = ",".join(classes)
    if prefs.filled_for == key and len(prefs.class_widths) == len(classes):
        return
    defaults = ggg.default_widths()
    present = {item.name for item in prefs.class_widths}
    for name in classes:
        if name not in present:
            item = prefs.class_widths.add()
            item.name = name
            item.width = defaults.get(name, item.width)
    prefs.filled_for = key


def class_width_table(prefs, ggg):
    """Widths indexed by highway class code, from the preferences (filled as needed)."""
    ensure_class_widths(prefs, ggg)
    by_name = {item.name: item.width for item in prefs.class_widths}
    return [by_name[name] for name in ggg.highway_classes()]


class ROADS_OT_reset_widths(Operator):
    """Set every class width and the lane width back to the native library's defaults"""

    bl_idname = "roads.reset_widths"
    bl_label = "Reset Widths to Defaults"
    bl_options = {'INTERNAL'}

    def execute(self, context):
        ggg = native.load_or_report(self)
        if ggg is None:
            return {'CANCELLED'}
        prefs = get(context)
        prefs.class_widths.clear()
        prefs.filled_for = ""
        prefs.lane_width = DEFAULT_LANE_WIDTH
        ensure_class_widths(prefs, ggg)
        context.preferences.is_dirty = True
        return {'FINISHED'}
