"""Road Grammar: import OpenStreetMap road networks as graphs and road surfaces, grow road
graphs with geometric graph grammars, find and replace their repeated patterns, and learn
grammars from road graphs.

The add-on calls the native library only through its Python module ``ggg`` (see
native.py for where it is looked for). Registering never needs the module, so the
add-on enables even when the module is missing or built for another Python; the
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

    for _module in (native, georef, mesh_build, surface, frames, importer, preferences, region,  # noqa: F821
                    grammar, graph_edit, operators, grammar_ops, stitch_ops, city, flythrough, city_ops,  # noqa: F821
                    panels):  # noqa: F821
        importlib.reload(_module)
    del _module
else:
    from . import (native, georef, mesh_build, surface, frames, importer, preferences, region, grammar,
                   graph_edit, operators, grammar_ops, stitch_ops, city, flythrough, city_ops, panels)

# The graph analyzer (isogroups, find similar) and the replacement of its patterns (paper
# Fig. 1): their own modules, after the ones above.
if "analysis" in locals():
    import importlib

    for _module in (jobs, pattern_display, analysis, analysis_ops, replacement, replacement_ops,  # noqa: F821
                    analysis_panels):  # noqa: F821
        importlib.reload(_module)
    del _module
else:
    from . import jobs, pattern_display, analysis, analysis_ops, replacement, replacement_ops, analysis_panels

# Grammar learning (inverse procedural modelling): after the analyzer, whose parts it uses.
if "learning" in locals():
    import importlib

    for _module in (rule_display, learning, learning_ops, learning_panels):  # noqa: F821
        importlib.reload(_module)
    del _module
else:
    from . import rule_display, learning, learning_ops, learning_panels

import bpy

classes = (
    preferences.ROADS_PG_class_width,
    preferences.ROADS_AP_preferences,
    preferences.ROADS_OT_reset_widths,
    grammar.ROADS_PG_grammar,
    operators.ROADS_OT_import_osm,
    grammar_ops.ROADS_OT_load_grammar,
    grammar_ops.ROADS_OT_save_grammar,
    grammar_ops.ROADS_OT_add_axiom,
    grammar_ops.ROADS_OT_place_rule,
    grammar_ops.ROADS_OT_grow,
    grammar_ops.ROADS_OT_grow_region,
    stitch_ops.ROADS_OT_stitch_cities,
    panels.VIEW3D_PT_roads,
    panels.VIEW3D_PT_roads_grammar,
    city_ops.ROADS_PG_city,
    city_ops.ROADS_OT_build_city,
    city_ops.ROADS_OT_flythrough,
    city_ops.ROADS_OT_render_city,
    panels.VIEW3D_PT_roads_city,
    analysis.ROADS_PG_isogroup,
    analysis.ROADS_PG_analysis,
    analysis.ROADS_PG_analysis_settings,
    analysis_ops.ROADS_OT_find_similar,
    analysis_ops.ROADS_OT_analyze,
    analysis_ops.ROADS_OT_select_isogroup,
    analysis_ops.ROADS_OT_show_patterns,
    analysis_ops.ROADS_OT_clear_patterns,
    replacement.ROADS_PG_replacement,
    replacement_ops.ROADS_OT_store_replacement,
    replacement_ops.ROADS_OT_replace_isogroup,
    analysis_panels.ROADS_UL_isogroups,
    analysis_panels.VIEW3D_PT_roads_patterns,
    analysis_panels.VIEW3D_PT_roads_isogroups,
    analysis_panels.VIEW3D_PT_roads_replace,
    learning.ROADS_PG_learned_rule,
    learning.ROADS_PG_learning,
    learning.ROADS_PG_learning_settings,
    learning_ops.ROADS_OT_learn,
    learning_ops.ROADS_OT_show_level,
    learning_panels.ROADS_UL_learned_rules,
    learning_panels.VIEW3D_PT_roads_learn,
    learning_panels.VIEW3D_PT_roads_learned_rules,
)


def register():
    for cls in classes:
        bpy.utils.register_class(cls)
    grammar.register()
    city_ops.register()
    analysis.register()
    replacement.register()
    learning.register()
    bpy.types.TOPBAR_MT_file_import.append(operators.menu_import)


def unregister():
    bpy.types.TOPBAR_MT_file_import.remove(operators.menu_import)
    city_ops.unregister()
    learning_ops.stop_all()
    learning.unregister()
    analysis_ops.stop_all()
    analysis.forget()
    replacement.unregister()
    analysis.unregister()
    grammar.unregister()
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
