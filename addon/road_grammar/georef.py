"""The scene's georeference, kept in the custom properties the BlenderGIS add-on uses.

BlenderGIS stores on the scene: ``SRID`` (the CRS: "EPSG:xxxx" or a PROJ string),
``crs x`` / ``crs y`` (the CRS coordinates of the Blender origin) and ``latitude`` /
``longitude`` (the WGS84 position of the Blender origin). The native library projects
each graph into a transverse Mercator frame centred on its own origin, so the first
import sets SRID to that frame with crs x = crs y = 0. A later import into a scene that
already has a transverse Mercator georeference is moved and turned into that frame
(its origin projected with the formulas below, its grid north turned by the meridian
convergence), so that extracts imported one after the other line up.
"""

import math
import re

KEY_SRID = "SRID"
KEY_CRS_X = "crs x"
KEY_CRS_Y = "crs y"
KEY_LAT = "latitude"
KEY_LON = "longitude"

# WGS84 ellipsoid.
_A = 6378137.0
_F = 1.0 / 298.257223563


def proj_string(lat, lon):
    """The PROJ definition of the native library's local frame centred on (lat, lon)."""
    return "+proj=tmerc +lat_0={:.9f} +lon_0={:.9f} +k=1 +x_0=0 +y_0=0 +ellps=WGS84 +units=m".format(lat, lon)


_PARAM = re.compile(r"\+(\w+)(?:=(\S+))?")


def parse_tmerc(srid):
    """(lat_0, lon_0, k, x_0, y_0) of a WGS84 transverse Mercator PROJ string, else None."""
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
        return (
            float(params.get("lat_0", 0.0)),
            float(params.get("lon_0", 0.0)),
            float(params.get("k", params.get("k_0", 1.0))),
            float(params.get("x_0", 0.0)),
            float(params.get("y_0", 0.0)),
        )
    except ValueError:
        return None


def _series():
    n = _F / (2.0 - _F)
    n2, n3, n4 = n * n, n ** 3, n ** 4
    rectifying_radius = _A / (1.0 + n) * (1.0 + n2 / 4.0 + n4 / 64.0)
    alpha = (
        n / 2.0 - 2.0 * n2 / 3.0 + 5.0 * n3 / 16.0 + 41.0 * n4 / 180.0,
        13.0 * n2 / 48.0 - 3.0 * n3 / 5.0 + 557.0 * n4 / 1440.0,
        61.0 * n3 / 240.0 - 103.0 * n4 / 140.0,
        49561.0 * n4 / 161280.0,
    )
    return n, rectifying_radius, alpha


_N, _RECTIFYING_RADIUS, _ALPHA = _series()


def _gauss_krueger(lat, dlon):
    """(xi, eta) of Krueger's series (Karney 2011, to n^4: well below a millimetre)."""
    phi = math.radians(lat)
    lam = math.radians(dlon)
    e = 2.0 * math.sqrt(_N) / (1.0 + _N)  # first eccentricity
    sin_phi = math.sin(phi)
    t = math.sinh(math.atanh(sin_phi) - e * math.atanh(e * sin_phi))
    xi_prime = math.atan2(t, math.cos(lam))
    eta_prime = math.atanh(math.sin(lam) / math.sqrt(1.0 + t * t))
    xi, eta = xi_prime, eta_prime
    for j, a in enumerate(_ALPHA, start=1):
        xi += a * math.sin(2 * j * xi_prime) * math.cosh(2 * j * eta_prime)
        eta += a * math.cos(2 * j * xi_prime) * math.sinh(2 * j * eta_prime)
    return xi, eta


def tmerc_forward(lat, lon, frame):
    """Metres (x east, y north) of (lat, lon) in the frame (lat_0, lon_0, k, x_0, y_0)."""
    lat0, lon0, k, x0, y0 = frame
    dlon = (lon - lon0 + 180.0) % 360.0 - 180.0
    xi, eta = _gauss_krueger(lat, dlon)
    xi0, _ = _gauss_krueger(lat0, 0.0)
    return x0 + k * _RECTIFYING_RADIUS * eta, y0 + k * _RECTIFYING_RADIUS * (xi - xi0)


def has_georef(scene):
    return KEY_SRID in scene


def write(scene, lat, lon):
    """Make (lat, lon) the scene's origin, in the native library's frame centred there."""
    scene[KEY_SRID] = proj_string(lat, lon)
    scene[KEY_CRS_X] = 0.0
    scene[KEY_CRS_Y] = 0.0
    scene[KEY_LAT] = float(lat)
    scene[KEY_LON] = float(lon)


class Placement:
    """Where a graph whose frame is centred on (lat, lon) goes in the scene."""

    def __init__(self, location=(0.0, 0.0), rotation=0.0, set_georef=False, warning=None):
        self.location = location
        self.rotation = rotation
        self.set_georef = set_georef
        self.warning = warning


def placement(scene, lat, lon):
    """The Placement of a graph centred on (lat, lon) in ``scene``'s georeference."""
    if not has_georef(scene):
        return Placement(set_georef=True)
    srid = scene[KEY_SRID]
    if srid == proj_string(lat, lon) and not scene.get(KEY_CRS_X) and not scene.get(KEY_CRS_Y):
        return Placement()
    frame = parse_tmerc(srid)
    if frame is None:
        return Placement(
            warning="The scene is georeferenced in {} which this add-on cannot project to; the roads "
            "were placed at the scene origin in their own frame ({}).".format(srid, proj_string(lat, lon))
        )
    crs_x = float(scene.get(KEY_CRS_X, 0.0))
    crs_y = float(scene.get(KEY_CRS_Y, 0.0))
    x, y = tmerc_forward(lat, lon, frame)
    # Grid north of the graph's frame at its origin is true north; find its direction here.
    north_x, north_y = tmerc_forward(min(lat + 1e-4, 90.0), lon, frame)
    rotation = math.atan2(-(north_x - x), north_y - y)
    return Placement(location=(x - crs_x, y - crs_y), rotation=rotation)
