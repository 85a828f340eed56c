"""The city of a road graph without Blender: its ground plan (``ggg.city_layout``, which also
decides the building heights; the road widths are ``ggg.road_widths``). ``display.city`` makes
the meshes."""

import numpy as np

# Classes whose surface is paving rather than asphalt (footways, paths, tracks, steps, ...):
# the lowest importance ranks of the native library, from pedestrian (10) down.
PATH_RANK = 10


class CityError(Exception):
    """A city cannot be built from this input; the message says why."""


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
        self.heights, self.tints = self.layout["building_height"], self.layout["building_tint"]
