"""The add-on's properties: its preferences, and the property groups kept on scenes and
objects (``scene.road_grammar``, ``scene.road_analysis`` and ``object.road_analysis``,
``scene.road_replacement``, ``scene.road_learning`` and ``object.road_learning``,
``scene.road_city``, ``object.road_compare``).

Each module lists its classes in ``classes`` (registered in that order) and the pointer
properties that hold its groups in ``pointers`` ((type, attribute, group), set once every
class is registered)."""

from . import analysis, city, comparison, grammar, learning, preferences, replacement

modules = (preferences, grammar, city, analysis, replacement, learning, comparison)
