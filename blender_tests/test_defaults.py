"""The add-on starts from the library's defaults: every setting of the Analyze, Find Similar
and Learn panels that the library also has defaults to the library's value (ggg.option_defaults),
so a user gets the same answer from the same input in Blender, in Python and on the command line."""

import bpy
import pytest

from road_grammar.properties.analysis import ROADS_PG_analysis_settings
from road_grammar.properties.learning import ROADS_PG_learning_settings


def _defaults(rna):
    return {p.identifier: p.default for p in rna.properties if hasattr(p, "default") and p.identifier != "rna_type"}


@pytest.mark.parametrize("group, properties", [
    ("analysis", lambda: _defaults(ROADS_PG_analysis_settings.bl_rna)),
    ("analysis", lambda: _defaults(bpy.ops.roads.find_similar.get_rna_type())),
    ("learning", lambda: _defaults(ROADS_PG_learning_settings.bl_rna)),
    ("learning", lambda: _defaults(bpy.ops.roads.learn.get_rna_type())),
])
def test_settings_default_to_the_library(ggg, group, properties):
    library = ggg.option_defaults()[group]
    blender = properties()
    shared = sorted(set(library) & set(blender))
    assert len(shared) >= 2, "too few shared settings to compare: {}".format(shared)
    for name in shared:
        assert blender[name] == pytest.approx(library[name]), "{} ({}): Blender {} vs the library {}".format(
            name, group, blender[name], library[name])



def test_city_settings_default_to_the_library(ggg):
    from road_grammar.data.preferences import DEFAULT_LANE_WIDTH
    from road_grammar.properties.city import ROADS_PG_city
    library = ggg.option_defaults()["city"]
    assert DEFAULT_LANE_WIDTH == pytest.approx(library["lane_width"])
    assert _defaults(ROADS_PG_city.bl_rna)["sidewalk_m"] == pytest.approx(library["sidewalk_m"])


def test_grammar_settings_default_to_the_library(ggg):
    """Grow and Grow into Region start where ggg.derive and ggg.grow_region do."""
    from road_grammar.properties import grammar
    growth, derive = ggg.option_defaults()["growth"], ggg.option_defaults()["derive"]
    assert grammar.DEFAULT_REGION_SEED == growth["seed"]
    assert grammar.DEFAULT_MAX_PLACEMENTS == growth["max_placements"]
    assert grammar.DEFAULT_REGION_MAX_VERTICES == growth["max_vertices"]
    assert grammar.DEFAULT_PATIENCE == growth["patience"]
    assert grammar.DEFAULT_STEPS == derive["steps"]
    assert grammar.DEFAULT_MAX_VERTICES == derive["max_vertices"]
    assert grammar.DEFAULT_TOLERANCE == pytest.approx(derive["tolerance"])
