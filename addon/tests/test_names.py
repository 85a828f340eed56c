"""core.names and core.palette."""

import pytest

from road_grammar.core import names, palette


@pytest.mark.parametrize("path, name", [
    ("/data/paris_marais.osm.pbf", "paris_marais"), ("town.OSM", "town"), ("//rel/city.osm.bz2", "city"),
    ("grid.geojson", "grid"), ("a.ggraph", "a"), (".osm", ".osm"), ("plain", "plain"),
])
def test_object_name(path, name):
    assert names.object_name(path) == name


def test_palette():
    assert palette.slot_color_srgb(0) == palette.NO_COLOR
    assert palette.slot_color_srgb(1) == pytest.approx((0xe6 / 255, 0x19 / 255, 0x4b / 255))
    assert palette.slot_color_srgb(palette.SEED_SLOT) == palette.srgb("ff3dcc")
    assert palette.slot_color_srgb(palette.SEED_SLOT + 1) == palette.NO_COLOR
    assert palette.to_linear(0.0) == 0.0 and palette.to_linear(1.0) == pytest.approx(1.0)
    assert all(0.0 <= c <= 1.0 for c in palette.slot_color_linear(4))
    assert [palette.rule_slot(i) for i in (0, 11, 12)] == [1, 12, 1]
    assert palette.rule_color_srgb(palette.DIMMED_SLOT) == palette.NO_COLOR
    assert palette.rule_color_srgb(2) == palette.slot_color_srgb(2)
    assert palette.rank_color(0) == palette.RANK_COLORS[0] and palette.rank_color(99) == palette.RANK_COLORS[-1]
