"""Reading the add-on's preferences (properties.preferences.ROADS_AP_preferences): the road
widths used when OpenStreetMap does not tag one."""

# The add-on's name (the package this subpackage belongs to), under which Blender keeps
# its preferences.
ADDON = __package__.partition(".")[0]
DEFAULT_LANE_WIDTH = 3.25


def get(context):
    """The add-on's preferences."""
    return context.preferences.addons[ADDON].preferences


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
