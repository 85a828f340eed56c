"""Road widths by class, for drawing what has no width of its own (a rule's streets). The
width of a road of a graph is ``ggg.road_widths``: its `width` tag, else its lanes times the
lane width, else the width of its class."""

import numpy as np


def class_default_widths(highway, defaults, classes, fallback=6.0):
    """The default width of each edge's class (``highway``: class codes; ``defaults``:
    {class name: width}, a class without one gets ``fallback``; ``classes``: the class
    names by code)."""
    table = np.array([defaults.get(name, fallback) for name in classes], dtype=np.float64)
    if len(table) == 0:
        return np.full(len(highway), fallback)
    return table[np.clip(np.asarray(highway, dtype=np.int64), 0, len(table) - 1)]
