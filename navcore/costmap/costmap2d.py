"""Costmap2D: a uint8 cost grid with costmap_2d's world <-> map geometry.

``costs`` is indexed ``[my, mx]`` (row = y), row 0 at ``origin_y``. ``world_to_map`` truncates
toward the cell corner at the origin and fails outside the grid; ``map_to_world`` gives the cell
centre: exactly costmap_2d's ``worldToMap`` / ``mapToWorld``.
"""

from __future__ import annotations

import math

import numpy as np


class Costmap2D:
    """A cost grid of ``size_x`` x ``size_y`` cells of ``resolution`` metres."""

    def __init__(self, size_x: int, size_y: int, resolution: float, origin_x: float = 0.0,
                 origin_y: float = 0.0, default_value: int = 0) -> None:
        if size_x <= 0 or size_y <= 0:
            raise ValueError(f"Costmap2D: size must be positive, got {size_x} x {size_y}")
        if not resolution > 0:
            raise ValueError(f"Costmap2D: resolution must be > 0, got {resolution}")
        self.resolution = float(resolution)
        self.origin_x = float(origin_x)
        self.origin_y = float(origin_y)
        self.default_value = int(default_value)
        self.costs = np.full((int(size_y), int(size_x)), self.default_value, dtype=np.uint8)

    @property
    def size_x(self) -> int:
        return int(self.costs.shape[1])

    @property
    def size_y(self) -> int:
        return int(self.costs.shape[0])

    def world_to_map(self, wx: float, wy: float) -> tuple[int, int] | None:
        if wx < self.origin_x or wy < self.origin_y:
            return None
        mx = int((wx - self.origin_x) / self.resolution)
        my = int((wy - self.origin_y) / self.resolution)
        if mx >= self.size_x or my >= self.size_y:
            return None
        return mx, my

    def world_to_map_no_bounds(self, wx: float, wy: float) -> tuple[int, int]:
        """Cell indices of a world point, possibly outside the grid (floor, like costmap_2d)."""
        return (int(math.floor((wx - self.origin_x) / self.resolution)),
                int(math.floor((wy - self.origin_y) / self.resolution)))

    def map_to_world(self, mx: float, my: float) -> tuple[float, float]:
        return (self.origin_x + (mx + 0.5) * self.resolution,
                self.origin_y + (my + 0.5) * self.resolution)

    def cell_distance(self, d: float) -> int:
        """costmap_2d cellDistance: whole cells covering ``d`` metres."""
        return max(0, int(math.ceil(d / self.resolution)))

    def get_cost(self, mx: int, my: int) -> int:
        return int(self.costs[my, mx])

    def set_cost(self, mx: int, my: int, cost: int) -> None:
        self.costs[my, mx] = cost

    def reset(self, x0: int = 0, y0: int = 0, xn: int | None = None, yn: int | None = None) -> None:
        """Fill cells [x0, xn) x [y0, yn) with the default value."""
        self.costs[y0:self.size_y if yn is None else yn,
                   x0:self.size_x if xn is None else xn] = self.default_value

    def resize(self, size_x: int, size_y: int, resolution: float, origin_x: float,
               origin_y: float) -> None:
        self.resolution, self.origin_x, self.origin_y = float(resolution), float(origin_x), float(origin_y)
        self.costs = np.full((int(size_y), int(size_x)), self.default_value, dtype=np.uint8)

    def size_in_meters(self) -> tuple[float, float]:
        return self.size_x * self.resolution, self.size_y * self.resolution
