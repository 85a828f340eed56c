"""The operator of the add-on's preferences."""

from bpy.types import Operator

from ..core import native
from ..data import preferences
from ..properties.preferences import RESET_WIDTHS


class ROADS_OT_reset_widths(Operator):
    """Set every class width and the lane width back to the native library's defaults"""

    bl_idname = RESET_WIDTHS
    bl_label = "Reset Widths to Defaults"
    bl_options = {'INTERNAL'}

    def execute(self, context):
        ggg = native.load_or_report(self)
        if ggg is None:
            return {'CANCELLED'}
        prefs = preferences.get(context)
        prefs.class_widths.clear()
        prefs.filled_for = ""
        prefs.lane_width = preferences.DEFAULT_LANE_WIDTH
        preferences.ensure_class_widths(prefs, ggg)
        context.preferences.is_dirty = True
        return {'FINISHED'}


classes = (ROADS_OT_reset_widths,)
