"""The add-on's pure-Python core: what it computes without Blender.

Nothing in this package imports ``bpy`` (or anything outside the package but numpy and
the standard library), so it runs, and is unit-tested (``addon/tests``), in any Python:
geometry of polylines and polygons, the columns of a road graph and the surgery on
them, georeferencing, names, colours, messages, stored analysis results, the building
heights and ground plan of a city, fly-through paths, and the worker threads of long
native calls. The native module ``ggg`` is passed in where it is needed (``native.load``
finds it)."""
