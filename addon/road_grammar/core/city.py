"""The city of a road graph without Blender: its ground plan (``ggg.city_layout``), the
road widths it is drawn with, and the rule for building heights. ``display.city`` makes
the meshes."""

import numpy as np

# Classes whose surface is paving rather than asphalt (footways, paths, tracks, steps, ...):
# the lowest importance ranks of the native library, from pedestrian (10) down.
PATH_RANK = 10
FLOOR_HEIGHT_M = 3.2


class CityError(Exception):
    """A city cannot be built from this input; the message says why."""


def building_heights(seed, points_xy, offsets, face_area, centre, radius):
    """Height in metres and facade tint in [0, 1) of each footprint.

    Floors grow towards the centre of the network and in small blocks (a dense core,
    low-rise suburbs), vary from lot to lot, and one lot in a hundred in the densest
    blocks is a tower.
    Deterministic for a given ``seed``."""
    rng = np.random.default_rng(int(seed))
    count = len(offsets) - 1
    if count == 0:
        return np.zeros(0), np.zeros(0)
    starts = np.asarray(offsets[:-1], dtype=np.int64)
    first = np.asarray(points_xy, dtype=np.float64).reshape(-1, 2)[starts]
    area = np.asarray(face_area, dtype=np.float64)
    # Base floors by block size: 5 in blocks under 0.3 ha, down to 1.5 in blocks over 25 ha.
    base = np.interp(np.log10(np.maximum(area, 1.0)), [3.5, 4.2, 4.8, 5.4], [4.0, 3.0, 2.0, 1.5])
    distance = np.hypot(first[:, 0] - centre[0], first[:, 1] - centre[1]) / max(radius, 1.0)
    central = 1.0 + 0.6 * np.clip(1.0 - 1.5 * distance, 0.0, 1.0) ** 2
    floors = base * central * rng.lognormal(0.0, 0.25, count)
    towers = (rng.random(count) < 0.01) & (base * central >= 5.0)
    floors = np.where(towers, floors * rng.uniform(1.8, 3.0, count), floors)
    floors = np.clip(np.rint(floors), 1, 60)
    heights = floors * FLOOR_HEIGHT_M + rng.uniform(0.3, 1.2, count)
    return heights, rng.random(count)


def road_widths(columns, ggg, graph):
    """Width of each edge of ``graph``: its `width` column in ``columns`` (the GraphColumns
    it was made from) where valid, else the class default of the native library."""
    widths = np.asarray(columns.columns.get("width", np.full(graph.edge_count, np.nan)), dtype=np.float64)
    defaults = ggg.default_widths()
    classes = list(ggg.highway_classes())
    by_class = np.array([defaults[name] for name in classes])
    fallback = by_class[np.clip(np.asarray(graph.edge_highway, dtype=np.int64), 0, len(by_class) - 1)]
    return np.where(np.isfinite(widths) & (widths > 0.0), widths, fallback)


class Plan:
    """Everything computed before the scene is touched (so an error changes nothing)."""

    def __init__(self, ggg, graph, widths, settings, progress=None):
        if graph.edge_count == 0:
            raise CityError("the road graph has no edges")
        self.layout = ggg.city_layout(
            graph, half_widths=widths / 2.0, sidewalk_m=settings.sidewalk_m, seed=settings.seed,
            progress=progress)
        faces = self.layout["faces"]
        self.face_count = len(faces["face_area"])
        if self.face_count == 0 or len(self.layout["block_face"]) == 0:
            raise CityError("the road graph has no city blocks: no roads enclose an area (a tree of streets, "
                            "or a single road)")
        ranks = np.asarray(graph.edge_rank, dtype=np.int64)
        road_edge = self.layout["road_edge"]
        self.road_is_path = ranks[road_edge] >= PATH_RANK if len(road_edge) else np.zeros(0, dtype=bool)
        positions = np.asarray(graph.positions, dtype=np.float64)
        low, high = positions.min(axis=0), positions.max(axis=0)
        self.low, self.high = low, high
        centre = np.median(positions, axis=0)
        radius = 0.5 * float(np.hypot(*(high - low)))
        building_face = self.layout["building_face"]
        face_area = faces["face_area"][building_face] if len(building_face) else np.zeros(0)
        self.heights, self.tints = building_heights(settings.seed, self.layout["building_points"],
                                                    self.layout["building_offsets"], face_area, centre, radius)
