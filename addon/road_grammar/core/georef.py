"""The scene's georeference, kept in custom properties of the scene.

The keys of the BlenderGIS add-on: ``SRID`` (the CRS: "EPSG:xxxx" or a PROJ string),
``crs x`` / ``crs y`` (the CRS coordinates of the Blender origin) and ``latitude`` /
``longitude`` (the WGS84 position of the Blender origin); and ``lat`` / ``lon``, the same
position under the short names other tools and scripts use. The add-on writes all of them
and reads either pair.

The native library reads each graph into a transverse Mercator frame in metres. The first
graph made in a scene sets the scene's SRID to that frame (``Graph.crs``, PROJ's own
definition) with crs x = crs y = 0. Later graphs are read straight into the scene's frame
(``ggg.read_graph(..., origin_latlon=scene origin)``: PROJ reprojects them), so extracts
imported one after the other line up; there is no projection code in the add-on. A scene
whose origin is given only by ``lat`` / ``lon`` (set by hand or by a script) gets its frame
centred there.
"""

import math
import re

import numpy as np

KEY_SRID = "SRID"
KEY_CRS_X = "crs x"
KEY_CRS_Y = "crs y"
KEY_LATITUDE = "latitude"
KEY_LONGITUDE = "longitude"
KEY_LAT = "lat"
KEY_LON = "lon"

# Pairs of keys that give the scene origin in WGS84, in the order they are read.
_ORIGIN_KEYS = ((KEY_LAT, KEY_LON), (KEY_LATITUDE, KEY_LONGITUDE))

_PARAM = re.compile(r"\+(\w+)(?:=(\S+))?")


def _valid_latlon(lat, lon):
    try:
        lat, lon = float(lat), float(lon)
    except (TypeError, ValueError):
        return None
    if not (math.isfinite(lat) and math.isfinite(lon) and abs(lat) <= 90.0 and abs(lon) <= 180.0):
        return None
    return lat, lon


def origin(scene):
    """The scene origin (lat, lon) in WGS84 from ``lat``/``lon`` or ``latitude``/``longitude``,
    else None."""
    for lat_key, lon_key in _ORIGIN_KEYS:
        if lat_key in scene and lon_key in scene:
            latlon = _valid_latlon(scene[lat_key], scene[lon_key])
            if latlon is not None:
                return latlon
    return None


def has_georef(scene):
    return KEY_SRID in scene or origin(scene) is not None


def crs_string(ggg, lat, lon):
    """PROJ string of the native library's frame centred on (lat, lon) (``Graph.crs``)."""
    empty = ggg.Graph.from_arrays(np.zeros((0, 2)), np.zeros((0, 2), dtype=np.int64), origin_latlon=(lat, lon))
    return empty.crs


def write(scene, lat, lon, crs):
    """Make (lat, lon) the scene's origin, in the frame ``crs`` (a graph's ``Graph.crs``)."""
    scene[KEY_SRID] = str(crs)
    scene[KEY_CRS_X] = 0.0
    scene[KEY_CRS_Y] = 0.0
    scene[KEY_LATITUDE] = float(lat)
    scene[KEY_LONGITUDE] = float(lon)
    scene[KEY_LAT] = float(lat)
    scene[KEY_LON] = float(lon)


def parse_tmerc(srid):
    """(lat_0, lon_0, x_0, y_0) of a PROJ string for a WGS84 transverse Mercator in metres
    with scale factor 1 (a frame the native library can read into), else None."""
    if not isinstance(srid, str):
        return None
    params = {m.group(1): m.group(2) for m in _PARAM.finditer(srid)}
    if params.get("proj") != "tmerc":
        return None
    if params.get("ellps", "WGS84") != "WGS84" and params.get("datum") != "WGS84":
        return None
    if params.get("units", "m") != "m":
        return None
    try:
        k = float(params.get("k", params.get("k_0", 1.0)))
        values = (float(params.get("lat_0", 0.0)), float(params.get("lon_0", 0.0)),
                  float(params.get("x_0", 0.0)), float(params.get("y_0", 0.0)))
    except ValueError:
        return None
    if k != 1.0 or _valid_latlon(values[0], values[1]) is None:
        return None
    return values


class Target:
    """Where a graph goes in the scene: the origin to read it into (None: centred on its
    own data), the object's location, whether it sets the scene's georeference, and a
    warning for the user."""

    def __init__(self, origin=None, location=(0.0, 0.0), set_georef=False, warning=None):
        self.origin = origin
        self.location = location
        self.set_georef = set_georef
        self.warning = warning

    def finish(self, scene, graph):
        """After the graph is read: write the scene's georeference when it is the first."""
        if self.set_georef:
            lat, lon = (float(v) for v in graph.origin_latlon)
            write(scene, lat, lon, graph.crs)


def target(scene, fallback_origin=None, georeferenced=True):
    """The Target for a new graph in ``scene``.

    ``fallback_origin`` is the origin used when the scene has no georeference (None: the
    graph's own, centred on its data); it then becomes the scene's georeference, unless
    the graph is not ``georeferenced`` (an abstract grammar's, at origin_latlon [0, 0])."""
    srid = scene.get(KEY_SRID)
    scene_origin = origin(scene)
    if srid is None:
        if scene_origin is None:
            return Target(origin=fallback_origin, set_georef=georeferenced)
        # Only the origin is given (e.g. scene["lat"], scene["lon"] set by a script):
        # the frame centred there, and the other keys are filled in.
        return Target(origin=scene_origin, set_georef=True)
    frame = parse_tmerc(srid)
    if frame is None:
        return Target(
            origin=fallback_origin,
            warning="The scene is georeferenced in {} which this add-on cannot project to; the roads "
            "were placed at the scene origin in their own frame.".format(srid),
        )
    lat0, lon0, x0, y0 = frame
    try:
        crs_x = float(scene.get(KEY_CRS_X, 0.0))
        crs_y = float(scene.get(KEY_CRS_Y, 0.0))
    except (TypeError, ValueError):
        crs_x = crs_y = 0.0
    # Native coordinates are metres from (lat_0, lon_0); the CRS adds the false easting and
    # northing, and the Blender origin sits at (crs x, crs y) of the CRS.
    return Target(origin=(lat0, lon0), location=(x0 - crs_x, y0 - crs_y))


def reproject(ggg, graph, latlon):
    """``graph`` moved into the frame centred on ``latlon`` (PROJ, by the native library).

    The module reprojects only while reading a file (read_graph's origin_latlon), so the
    graph goes through a temporary .ggraph file, which keeps symbols and frames."""
    import os
    import tempfile

    if tuple(float(v) for v in graph.origin_latlon) == tuple(float(v) for v in latlon):
        return graph
    if graph.vertex_count == 0:
        return relabel(ggg, graph, latlon)
    with tempfile.TemporaryDirectory(prefix="road_grammar_") as folder:
        path = os.path.join(folder, "graph.ggraph")
        graph.write(path)
        return ggg.read_graph(path, origin_latlon=tuple(latlon))


def is_abstract(latlon):
    """True for the origin [0, 0] of grammars that are not placed on the earth."""
    return tuple(float(v) for v in latlon) == (0.0, 0.0)


def relabel(ggg, graph, latlon):
    """``graph`` (of an abstract grammar) declared to be in the frame centred on ``latlon``:
    same metres, no reprojection."""
    return ggg.Graph.from_arrays(graph.positions, graph.edges, origin_latlon=tuple(latlon),
                                 vertex_symbols=graph.vertex_symbols, vertex_frames=graph.vertex_frames,
                                 edge_highway=graph.edge_highway, more_rewrites=graph.more_rewrites)


def grammar_target(ggg, scene, grammar_origin):
    """(Target, place) for a graph of a grammar whose frame is centred on ``grammar_origin``:
    ``place(graph)`` returns the graph in the frame the Target reads into.

    A georeferenced grammar is reprojected into the scene's frame (or sets it, in a scene
    without one); an abstract grammar's metres are taken as the scene's, around its origin,
    and never set the scene's georeference."""
    abstract = is_abstract(grammar_origin)
    result = target(scene, fallback_origin=None if abstract else tuple(grammar_origin), georeferenced=not abstract)

    def place(graph):
        if result.origin is None:
            return graph
        return relabel(ggg, graph, result.origin) if abstract else reproject(ggg, graph, result.origin)

    return result, place
