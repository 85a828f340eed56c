"""What the operators share: finding the road graph, the native module with a feature, the
scene's grammar and a file to read, each reporting an ERROR when it cannot; road widths from
the preferences; the redo panel and parameters of Analyze and Learn."""

import os

import bpy

from ..core import native
from ..core.text import plural
from ..data import roads, texts
from ..data import preferences


def input_file_or_report(operator):
    """The operator's filepath made absolute when it names a file; else None after an ERROR
    report that says what is wrong with it."""
    path = bpy.path.abspath(operator.filepath)
    if not os.path.isfile(path):
        problem = "is a folder, not a file" if os.path.isdir(path) else "no such file"
        operator.report({'ERROR'}, "{}: {}".format(path or "(no file given)", problem))
        return None
    return path


def graph_or_report(op, context):
    """The road graph object of the active object, or None after an ERROR report."""
    obj = roads.road_graph_object(context.active_object)
    if obj is None or obj.type != 'MESH':
        op.report({'ERROR'}, "Select a road graph (import OpenStreetMap roads first); the active object is {}"
                  .format("'{}', not a road graph".format(context.active_object.name)
                          if context.active_object is not None else "none"))
        return None
    return obj


def analyzer_or_report(op):
    """The module ggg with the analyzer, or None after an ERROR report."""
    ggg = native.load_or_report(op)
    if ggg is None:
        return None
    missing = [name for name in ("analyze", "find_similar", "Cancelled", "UsageError") if not hasattr(ggg, name)]
    if missing:
        op.report({'ERROR'}, "The native module {} has no analyzer (it lacks {}); rebuild it".format(
            getattr(ggg, "__file__", "ggg"), ", ".join(missing)))
        return None
    return ggg


def grammar_or_report(op, context):
    """(ggg, Text, ggg.Grammar), or None after an ERROR report."""
    try:
        ggg = native.load()
        text, parsed = texts.active(context)
    except (native.NativeModuleError, texts.GrammarUnavailable) as ex:
        op.report({'ERROR'}, str(ex))
        return None
    return ggg, text, parsed


def class_widths(context, ggg, graph):
    """The width of each edge of ``graph``: tagged, else by lanes, else its class's in the
    preferences."""
    prefs = preferences.get(context)
    return ggg.road_widths(graph, class_widths=preferences.class_width_table(prefs, ggg), lane_width=prefs.lane_width)


def isogroup_index_or_report(op, obj):
    """The place in the list of the analysis of ``obj`` of the isogroup ``op.index`` (-1:
    the active one), or None after an ERROR report."""
    isogroups = obj.road_analysis.isogroups
    index = obj.road_analysis.active_index if op.index < 0 else op.index
    if not 0 <= index < len(isogroups):
        op.report({'ERROR'}, "Choose an isogroup in the list first" if op.index < 0 else
                  "{} has {}: there is no isogroup {}".format(obj.name, plural(len(isogroups), "isogroup"), index))
        return None
    return index


def draw_settings(op, names):
    """The redo panel of Analyze or Learn ``op``: the grid on one row, then the properties
    ``names``."""
    layout = op.layout
    layout.use_property_split = True
    layout.use_property_decorate = False
    row = layout.row(align=True)
    row.prop(op, "angle_cells", text="Grid")
    row.prop(op, "distance_cells", text="")
    for name in names:
        layout.prop(op, name)


def constraint_parameters(op):
    """The constraints of Analyze or Learn ``op`` that are set, as parts of its parameters text."""
    parts = []
    if op.min_aspect > 0:
        parts.append("min aspect {:g}".format(op.min_aspect))
    if op.min_leaves > 0:
        parts.append("min leaves {}".format(op.min_leaves))
    if op.min_irregularity > 0:
        parts.append("min irregularity {:g}\u00b0".format(op.min_irregularity))
    return parts
