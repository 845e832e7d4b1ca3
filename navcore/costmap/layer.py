"""What every costmap layer shares: its own grid the size of the master, bounds, combination.

A layer follows costmap_2d's two-phase update: ``update_bounds`` grows the window (world metres,
``bounds = [min_x, min_y, max_x, max_y]``) that changed, then ``update_costs`` writes that window
(cells ``[x0, xn) x [y0, yn)``) into the master grid with the layer's combination method.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from navcore.costmap.cost_values import FREE_SPACE, NO_INFORMATION
from navcore.costmap.costmap2d import (Costmap2D, combine_addition, combine_max, combine_overwrite,
                                       combine_true_overwrite)

COMBINATION_OVERWRITE = 0   # updateWithOverwrite
COMBINATION_MAXIMUM = 1     # updateWithMax
COMBINATION_NOTHING = 99    # the layer's grid is not copied

_COMBINE = {"true_overwrite": combine_true_overwrite, "overwrite": combine_overwrite,
            "max": combine_max, "addition": combine_addition}


@njit(cache=True, nogil=True)
def grow_bounds(bounds: np.ndarray, x: float, y: float) -> None:
    """Grow ``bounds`` [min_x, min_y, max_x, max_y] to include the world point (x, y)."""
    if x < bounds[0]:
        bounds[0] = x
    if y < bounds[1]:
        bounds[1] = y
    if x > bounds[2]:
        bounds[2] = x
    if y > bounds[3]:
        bounds[3] = y


# the same rule for the layers' Python-list bounds (the njit kernels use ``grow_bounds``)
touch = getattr(grow_bounds, "py_func", grow_bounds)  # plain already under NUMBA_DISABLE_JIT


class CostmapLayer:
    """A layer that keeps a grid of its own, aligned with the master (costmap_2d::CostmapLayer)."""

    kind = "layer"
    clearable = False  # whether clear_costmap recoveries reset it

    def __init__(self, name: str, track_unknown_space: bool) -> None:
        self.name = name
        self.current = True
        default = NO_INFORMATION if track_unknown_space else FREE_SPACE
        self.grid = Costmap2D(1, 1, 0.05, 0.0, 0.0, default)
        self.rolling = False
        self._extra: list[float] | None = None

    @property
    def enabled(self) -> bool:
        return bool(self.params.enabled)

    def match_size(self, size_x: int, size_y: int, resolution: float, origin_x: float,
                   origin_y: float) -> None:
        """Follow the master's geometry (costmap_2d matchSize); content is lost."""
        self.grid.resize(size_x, size_y, resolution, origin_x, origin_y)

    def update_origin(self, origin_x: float, origin_y: float) -> None:
        self.grid.update_origin(origin_x, origin_y)

    def reset(self) -> None:
        self.grid.reset()
        self.current = True

    def on_footprint_changed(self, inscribed_radius: float, circumscribed_radius: float) -> None:
        """Most layers do not care about the footprint."""

    def add_extra_bounds(self, min_x: float, min_y: float, max_x: float, max_y: float) -> None:
        """Make the next update include this window (costmap_2d addExtraBounds)."""
        if self._extra is None:
            self._extra = [min_x, min_y, max_x, max_y]
        else:
            self._extra = [min(self._extra[0], min_x), min(self._extra[1], min_y),
                           max(self._extra[2], max_x), max(self._extra[3], max_y)]

    def use_extra_bounds(self, bounds: list[float]) -> None:
        if self._extra is not None:
            touch(bounds, self._extra[0], self._extra[1])
            touch(bounds, self._extra[2], self._extra[3])
            self._extra = None

    def clear_area(self, x0: int, y0: int, x1: int, y1: int, invert: bool) -> None:
        """costmap_2d clearArea on this layer's grid, then redraw the whole layer next update."""
        self.grid.clear_area(x0, y0, x1, y1, invert)
        g = self.grid
        self.add_extra_bounds(g.origin_x, g.origin_y, g.origin_x + g.size_x * g.resolution,
                              g.origin_y + g.size_y * g.resolution)

    def combine(self, method: str, master: Costmap2D, x0: int, y0: int, xn: int, yn: int) -> None:
        """Write this layer's window into ``master`` with a costmap_2d combination method."""
        if xn <= x0 or yn <= y0:
            return
        _COMBINE[method](master.costs, self.grid.costs, x0, y0, xn, yn)


def combination_name(method: int) -> str | None:
    """The combination of an obstacle/voxel ``combination_method`` value (None: nothing)."""
    if method == COMBINATION_OVERWRITE:
        return "overwrite"
    if method == COMBINATION_MAXIMUM:
        return "max"
    return None


def window_world(grid: Costmap2D) -> tuple[float, float, float, float]:
    """The world rectangle a grid covers."""
    return (grid.origin_x, grid.origin_y, grid.origin_x + grid.size_x * grid.resolution,
            grid.origin_y + grid.size_y * grid.resolution)
