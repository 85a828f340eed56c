"""Road Grammar: import OpenStreetMap road networks as graphs and road surfaces, grow road
graphs with geometric graph grammars, find and replace their repeated patterns, and learn
grammars from road graphs.

The add-on is laid out as Blender's bundled add-ons are:

* ``core``: what it computes without Blender (no ``bpy``), unit-tested in any Python;
  ``core.native`` finds the native module ``ggg``, the only way the add-on calls the
  library;
* ``data``: road graph objects, grammar texts and the results kept in the .blend;
* ``display``: the node groups, modifiers and materials that draw them;
* ``properties``: preferences and the property groups of scenes and objects;
* ``operators``: the ``roads.*`` operators;
* ``ui``: the sidebar panels and the menu entry.

Registration follows the ``classes`` of the modules of ``properties``, ``operators`` and
``ui``, in that order (the property groups first); then the pointer properties of
``properties`` and the menu entries of ``ui``. Registering never needs the native module,
so the add-on enables even when the module is missing or built for another Python; the
import operator and the sidebar panel then say what to do.
"""

bl_info = {
    "name": "Road Grammar",
    "author": "Road Grammar contributors",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "File > Import > OpenStreetMap Roads; 3D View > Sidebar > Roads",
    "description": "Import OpenStreetMap roads as a road graph mesh with flat road surfaces; "
    "grow road graphs with geometric graph grammars, learn grammars from them; build, fly through and render 3-D "
    "cities",
    "category": "Import-Export",
}

if "bpy" in locals():
    import importlib
    import sys

    # Reload Scripts: every module of the add-on again, layer by layer (core first, ui last).
    _LAYERS = ("core", "data", "display", "properties", "operators", "ui")
    for _name in sorted((name for name in sys.modules if name.startswith(__name__ + ".")),
                        key=lambda name: (_LAYERS.index(name.split(".")[1]) if name.split(".")[1] in _LAYERS
                                          else len(_LAYERS), name)):
        importlib.reload(sys.modules[_name])
    del _name, _LAYERS

import bpy
from bpy.props import PointerProperty

from . import operators, properties, ui
from .data import analysis, texts
from .display import rules
from .operators import jobs

PACKAGES = (properties, operators, ui)


def _classes():
    return [cls for package in PACKAGES for module in package.modules for cls in module.classes]


def _pointers():
    return [pointer for module in properties.modules for pointer in getattr(module, "pointers", ())]


def _menus():
    return [menu for module in ui.modules for menu in getattr(module, "menus", ())]


def register():
    for cls in _classes():
        bpy.utils.register_class(cls)
    for owner, name, group in _pointers():
        setattr(owner, name, PointerProperty(type=group))
    for menu, draw in _menus():
        menu.append(draw)


def unregister():
    for menu, draw in reversed(_menus()):
        menu.remove(draw)
    # The jobs running in the UI first: none may finish into unregistered properties.
    jobs.stop_all()
    for owner, name, _group in reversed(_pointers()):
        delattr(owner, name)
    for cls in reversed(_classes()):
        bpy.utils.unregister_class(cls)
    # What is kept in memory besides the .blend.
    analysis.forget()
    rules.forget()
    texts.forget()
