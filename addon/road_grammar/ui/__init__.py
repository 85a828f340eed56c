"""The add-on's interface: the panels of the 3D view sidebar's "Roads" tab (and their
lists) and the File > Import menu entry. ``common`` holds what the panels share.

Each module lists its classes in ``classes`` (the panels appear in the order they are
registered) and, where it adds to a menu, ``menus`` ((menu, draw function), ...)."""

from . import city, comparison, grammar, learning, patterns, roads

modules = (roads, grammar, city, patterns, learning, comparison)
