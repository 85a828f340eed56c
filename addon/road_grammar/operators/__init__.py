"""The add-on's operators (``roads.*``), one module per workflow: the preferences' widths,
importing roads, the grammar (load, save, axiom, place, grow), growing into a region,
stitching two cities, the 3-D city, the analyzer, replacement, learning and comparing two
road graphs. ``common`` holds what they share and ``jobs`` the modal running of long native
calls and of Blender's render job.

Each module lists its operator classes in ``classes``."""

from . import (analysis, city, comparison, grammar, importer, learning, preferences, region, replacement,
               stitch)

modules = (preferences, importer, grammar, region, stitch, city, analysis, replacement, learning, comparison)
