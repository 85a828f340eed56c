"""core.georef: the scene's georeference (a scene is read as a mapping of custom properties)."""

import pytest

from road_grammar.core import georef

TMERC = "+proj=tmerc +lat_0=48.85 +lon_0=2.35 +k=1 +x_0=0 +y_0=0 +ellps=WGS84 +units=m +no_defs"


def test_parse_tmerc():
    assert georef.parse_tmerc(TMERC) == (48.85, 2.35, 0.0, 0.0)
    assert georef.parse_tmerc(TMERC.replace("+x_0=0", "+x_0=500")) == (48.85, 2.35, 500.0, 0.0)
    assert georef.parse_tmerc("EPSG:3857") is None
    assert georef.parse_tmerc(TMERC.replace("+k=1", "+k=0.9996")) is None
    assert georef.parse_tmerc(TMERC.replace("+units=m", "+units=ft")) is None
    assert georef.parse_tmerc(None) is None


def test_origin():
    assert georef.origin({}) is None
    assert georef.origin({"lat": 46.0, "lon": 8.9}) == (46.0, 8.9)
    assert georef.origin({"latitude": 46.0, "longitude": 8.9}) == (46.0, 8.9)
    assert georef.origin({"lat": 95.0, "lon": 8.9}) is None
    assert georef.origin({"lat": "x", "lon": 8.9, "latitude": 1.0, "longitude": 2.0}) == (1.0, 2.0)
    assert not georef.has_georef({}) and georef.has_georef({"SRID": "EPSG:4326"})


def test_write_and_target():
    scene = {}
    first = georef.target(scene, fallback_origin=(46.0, 8.9))
    assert first.origin == (46.0, 8.9) and first.set_georef and first.warning is None
    georef.write(scene, 46.0, 8.9, TMERC)
    assert scene["lat"] == scene["latitude"] == 46.0 and scene["crs x"] == 0.0
    later = georef.target(scene)
    assert later.origin == (48.85, 2.35) and not later.set_georef and later.location == (0.0, 0.0)
    scene["crs x"], scene["crs y"] = 100.0, -50.0
    assert georef.target(scene).location == (-100.0, 50.0)
    foreign = georef.target({"SRID": "EPSG:3857"})
    assert "cannot project" in foreign.warning
    only_origin = georef.target({"lat": 1.0, "lon": 2.0})
    assert only_origin.origin == (1.0, 2.0) and only_origin.set_georef
    abstract = georef.target({}, georeferenced=False)
    assert abstract.origin is None and not abstract.set_georef
    assert georef.is_abstract((0, 0)) and not georef.is_abstract((46.0, 8.9))


def test_crs_string(ggg):
    assert georef.parse_tmerc(georef.crs_string(ggg, 46.0, 8.9))[:2] == pytest.approx((46.0, 8.9))
