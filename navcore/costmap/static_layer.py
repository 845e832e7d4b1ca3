"""costmap_2d::StaticLayer: the map_server map as costs."""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from navcore.costmap.cost_values import FREE_SPACE, LETHAL_OBSTACLE, NO_INFORMATION
from navcore.costmap.costmap2d import Costmap2D
from navcore.costmap.layer import CostmapLayer, touch, window_world
from navcore.maps import OccupancyGrid
from navcore.params import Param, Parameters

STATIC_PARAMS = (
    Param("enabled", True, bool, "whether the layer contributes"),
    Param("map_topic", "map", str, "topic of the map (kept for config compatibility)"),
    Param("first_map_only", False, bool, "ignore later maps (kept for config compatibility)"),
    Param("subscribe_to_updates", False, bool, "map updates topic (kept for config compatibility)"),
    Param("track_unknown_space", True, bool, "unknown map cells stay NO_INFORMATION, else FREE"),
    Param("use_maximum", False, bool, "combine by maximum instead of overwriting (static size)"),
    Param("lethal_cost_threshold", 100, int, "map value from which a cell is lethal"),
    Param("unknown_cost_value", -1, int, "map value that means unknown"),
    Param("trinary_costmap", True, bool, "map to free/lethal/unknown only, else scale"),
)


def interpret_map(data: np.ndarray, lethal_cost_threshold: int = 100, unknown_cost_value: int = -1,
                  track_unknown_space: bool = True, trinary_costmap: bool = True) -> np.ndarray:
    """Occupancy values -> costs, as StaticLayer interpretValue (values compared as uint8).

    The rule is applied to the 256 possible byte values once and the map is read through that
    table: one gather instead of several full-size int64 temporaries."""
    v = np.arange(256, dtype=np.int64)
    lethal = max(min(int(lethal_cost_threshold), 100), 0)
    unknown = int(unknown_cost_value) & 0xFF
    if trinary_costmap:
        table = np.where(v >= lethal, LETHAL_OBSTACLE, FREE_SPACE)
    else:
        scaled = (v / lethal * LETHAL_OBSTACLE) if lethal > 0 else np.full(v.shape, 254.0)
        table = np.where(v >= lethal, LETHAL_OBSTACLE, scaled.astype(np.int64))
    table[unknown] = NO_INFORMATION if track_unknown_space else FREE_SPACE
    # astype(uint8) wraps signed and wide integers modulo 256, the same as "& 0xFF"
    return table.astype(np.uint8)[np.asarray(data).astype(np.uint8)]


class StaticLayer(CostmapLayer):
    """The static map. With a static-size costmap it sets the master's size, resolution and
    origin (the map's yaw is ignored, as in costmap_2d) and is drawn once per new map; with a
    rolling window every update samples it under the window."""

    kind = "static"

    def __init__(self, name: str, params: dict | None = None) -> None:
        values = dict(params or {})
        self.params = Parameters(STATIC_PARAMS, values, where=name)
        super().__init__(name, self.params.track_unknown_space)
        self.map: Costmap2D | None = None
        self._has_updated_data = False

    def set_map(self, grid: OccupancyGrid) -> Costmap2D:
        """Take a new map; returns its cost grid (the layered costmap resizes the master to it)."""
        p = self.params
        costs = interpret_map(grid.data, p.lethal_cost_threshold, p.unknown_cost_value,
                              p.track_unknown_space, p.trinary_costmap)
        m = Costmap2D(grid.width, grid.height, grid.resolution, grid.origin.x, grid.origin.y,
                      NO_INFORMATION if p.track_unknown_space else FREE_SPACE)
        m.costs = costs
        self.map = m
        self._has_updated_data = True
        return m

    def match_size(self, size_x: int, size_y: int, resolution: float, origin_x: float,
                   origin_y: float) -> None:
        """The static layer keeps the map grid itself; a static-size master is the map's size."""

    def update_origin(self, origin_x: float, origin_y: float) -> None:
        """The map does not move."""

    def reset(self) -> None:
        self._has_updated_data = self.map is not None

    def clear_area(self, x0: int, y0: int, x1: int, y1: int, invert: bool) -> None:
        """Not clearable: the map comes back anyway."""

    def update_bounds(self, robot_x: float, robot_y: float, robot_yaw: float,
                      bounds: list[float]) -> None:
        if self.map is None or not self.enabled:
            return
        if not self.rolling and not self._has_updated_data:
            return
        x0, y0, x1, y1 = window_world(self.map)
        touch(bounds, x0, y0)
        touch(bounds, x1, y1)
        self._has_updated_data = False

    def update_costs(self, master: Costmap2D, x0: int, y0: int, xn: int, yn: int) -> None:
        if self.map is None or not self.enabled or xn <= x0 or yn <= y0:
            return
        if not self.rolling:
            if (master.size_x, master.size_y) != (self.map.size_x, self.map.size_y):
                return
            self.grid = self.map
            self.combine("max" if self.params.use_maximum else "true_overwrite", master,
                         x0, y0, xn, yn)
            return
        # rolling window: sample the map at each master cell centre; cells off the map stay as is
        m = self.map
        sample_map(master.costs, x0, y0, xn, yn, master.origin_x, master.origin_y,
                   master.resolution, m.costs, m.origin_x, m.origin_y, m.resolution)


@njit(cache=True, nogil=True)
def sample_map(costs: np.ndarray, x0: int, y0: int, xn: int, yn: int, origin_x: float,
               origin_y: float, resolution: float, map_costs: np.ndarray, map_origin_x: float,
               map_origin_y: float, map_resolution: float) -> None:
    """Set each cell [y0, yn) x [x0, xn) of ``costs`` to the map cell under its centre; a cell
    whose centre is off the map keeps its cost (the rolling window's static layer)."""
    map_h, map_w = map_costs.shape
    for j in range(y0, yn):
        my = math.floor((origin_y + (j + 0.5) * resolution - map_origin_y) / map_resolution)
        if not 0 <= my < map_h:
            continue
        for i in range(x0, xn):
            mx = math.floor((origin_x + (i + 0.5) * resolution - map_origin_x) / map_resolution)
            if 0 <= mx < map_w:
                costs[j, i] = map_costs[int(my), int(mx)]
