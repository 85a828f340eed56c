"""Road widths: a road's own `width` tag, else its lanes times the lane width, else the
default of its class."""

import numpy as np


def road_widths(highway, width_tag, lanes, class_widths, lane_width):
    """Width in metres of each edge: its `width` tag if tagged, else lanes x lane width,
    else the default of its class (``class_widths`` is indexed by class code)."""
    highway = np.asarray(highway, dtype=np.int64)
    widths = np.array(width_tag, dtype=np.float64, copy=True)
    lanes = np.asarray(lanes, dtype=np.int64)
    defaults = np.asarray(class_widths, dtype=np.float64)
    tagged = np.isfinite(widths) & (widths > 0.0)
    by_lanes = ~tagged & (lanes > 0)
    widths[by_lanes] = lanes[by_lanes] * float(lane_width)
    rest = ~(tagged | by_lanes)
    widths[rest] = defaults[np.clip(highway[rest], 0, len(defaults) - 1)]
    return widths


def class_default_widths(highway, defaults, classes, fallback=6.0):
    """The default width of each edge's class (``highway``: class codes; ``defaults``:
    {class name: width}, a class without one gets ``fallback``; ``classes``: the class
    names by code)."""
    table = np.array([defaults.get(name, fallback) for name in classes], dtype=np.float64)
    if len(table) == 0:
        return np.full(len(highway), fallback)
    return table[np.clip(np.asarray(highway, dtype=np.int64), 0, len(table) - 1)]
