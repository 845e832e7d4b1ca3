"""Costmap2D: a uint8 cost grid with costmap_2d's world <-> map geometry.

``costs`` is indexed ``[my, mx]`` (row = y), row 0 at ``origin_y``. ``world_to_map`` truncates
toward the cell corner at the origin and fails outside the grid; ``map_to_world`` gives the cell
centre: exactly costmap_2d's ``worldToMap`` / ``mapToWorld``.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from navcore.costmap.cost_values import NO_INFORMATION


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

    def world_to_map_enforce_bounds(self, wx: float, wy: float) -> tuple[int, int]:
        """costmap_2d worldToMapEnforceBounds: the cell of a world point, clamped into the grid."""
        def clamp(w: float, o: float, n: int) -> int:
            if w < o:
                return 0
            if w >= self.resolution * n + o:
                return n - 1
            return int((w - o) / self.resolution)
        return clamp(wx, self.origin_x, self.size_x), clamp(wy, self.origin_y, self.size_y)

    def update_origin(self, new_origin_x: float, new_origin_y: float) -> None:
        """Move the grid (rolling window) keeping world-aligned content, as costmap_2d updateOrigin.

        The new origin snaps to whole cells from the old one; the cells that come into view get
        the default value.
        """
        cell_ox = int((new_origin_x - self.origin_x) / self.resolution)
        cell_oy = int((new_origin_y - self.origin_y) / self.resolution)
        if cell_ox == 0 and cell_oy == 0:
            return
        self.costs = shift_grid(self.costs, cell_ox, cell_oy, self.default_value)
        self.origin_x += cell_ox * self.resolution
        self.origin_y += cell_oy * self.resolution

    def clear_area(self, x0: int, y0: int, x1: int, y1: int, invert: bool = False) -> None:
        """costmap_2d clearArea: NO_INFORMATION on every cell outside the open rectangle
        (x0, x1) x (y0, y1), or on the cells inside it when ``invert``."""
        ys, xs = np.arange(self.size_y)[:, None], np.arange(self.size_x)[None, :]
        inside = (xs > x0) & (xs < x1) & (ys > y0) & (ys < y1)
        self.costs[inside if invert else ~inside] = NO_INFORMATION

    def set_convex_polygon_cost(self, polygon: np.ndarray, cost: int) -> bool:
        """Set ``cost`` on the cells of a convex world polygon (outline and inside, costmap_2d
        convexFillCells). False, touching nothing, if a vertex is off the grid."""
        poly = np.asarray(polygon, dtype=np.float64).reshape(-1, 2)
        cells = []
        for wx, wy in poly:
            c = self.world_to_map(float(wx), float(wy))
            if c is None:
                return False
            cells.append(c)
        _fill_convex_cells(self.costs, np.asarray(cells, dtype=np.int64), np.uint8(cost))
        return True

    def copy_window(self, src: "Costmap2D", sx0: int, sy0: int, sxn: int, syn: int, dx0: int,
                    dy0: int) -> None:
        """Copy cells [sx0, sxn) x [sy0, syn) of ``src`` to this grid at (dx0, dy0)."""
        w, h = sxn - sx0, syn - sy0
        if w <= 0 or h <= 0:
            return
        self.costs[dy0:dy0 + h, dx0:dx0 + w] = src.costs[sy0:syn, sx0:sxn]


def shift_grid(grid: np.ndarray, cell_ox: int, cell_oy: int, fill) -> np.ndarray:
    """A grid like ``grid`` whose origin moved by (cell_ox, cell_oy) cells: overlapping content
    keeps its world position, the rest is ``fill``."""
    h, w = grid.shape[:2]
    out = np.empty_like(grid)
    out[...] = fill
    # overlap in old-grid coordinates
    lx, ly = max(0, cell_ox), max(0, cell_oy)
    ux, uy = min(w, w + cell_ox), min(h, h + cell_oy)
    if ux > lx and uy > ly:
        out[ly - cell_oy:uy - cell_oy, lx - cell_ox:ux - cell_ox] = grid[ly:uy, lx:ux]
    return out


@njit(cache=True, nogil=True)
def _fill_convex_cells(costs: np.ndarray, cells: np.ndarray, value: np.uint8) -> None:
    """Outline cells by Bresenham between consecutive vertex cells, then every cell between the
    lowest and highest outline cell of each column (convexFillCells)."""
    n = cells.shape[0]
    mx0 = cells[:, 0].min()
    mx1 = cells[:, 0].max()
    lo = np.full(mx1 - mx0 + 1, 1 << 30, dtype=np.int64)
    hi = np.full(mx1 - mx0 + 1, -1, dtype=np.int64)
    for i in range(n):
        x0, y0 = cells[i - 1, 0], cells[i - 1, 1]
        x1, y1 = cells[i, 0], cells[i, 1]
        dx = abs(x1 - x0)
        dy = abs(y1 - y0)
        sx = 1 if x1 >= x0 else -1
        sy = 1 if y1 >= y0 else -1
        x, y = x0, y0
        major = dx if dx >= dy else dy
        minor = dy if dx >= dy else dx
        num = major // 2
        for _ in range(major + 1):
            c = x - mx0
            if y < lo[c]:
                lo[c] = y
            if y > hi[c]:
                hi[c] = y
            num += minor
            step = num >= major
            if step:
                num -= major
            if dx >= dy:
                x += sx
                if step:
                    y += sy
            else:
                y += sy
                if step:
                    x += sx
    for c in range(mx1 - mx0 + 1):
        for y in range(lo[c], hi[c] + 1):
            costs[y, mx0 + c] = value


@njit(cache=True, nogil=True)
def combine_true_overwrite(master: np.ndarray, layer: np.ndarray, x0: int, y0: int, xn: int,
                           yn: int) -> None:
    """updateWithTrueOverwrite: copy every cell of the window."""
    for y in range(y0, yn):
        for x in range(x0, xn):
            master[y, x] = layer[y, x]


@njit(cache=True, nogil=True)
def combine_overwrite(master: np.ndarray, layer: np.ndarray, x0: int, y0: int, xn: int,
                      yn: int) -> None:
    """updateWithOverwrite: copy the cells the layer knows (not NO_INFORMATION)."""
    for y in range(y0, yn):
        for x in range(x0, xn):
            v = layer[y, x]
            if v != NO_INFORMATION:
                master[y, x] = v


@njit(cache=True, nogil=True)
def combine_max(master: np.ndarray, layer: np.ndarray, x0: int, y0: int, xn: int,
                yn: int) -> None:
    """updateWithMax: skip unknown layer cells; write where the master is unknown or lower."""
    for y in range(y0, yn):
        for x in range(x0, xn):
            v = layer[y, x]
            if v == NO_INFORMATION:
                continue
            m = master[y, x]
            if m == NO_INFORMATION or m < v:
                master[y, x] = v


@njit(cache=True, nogil=True)
def combine_addition(master: np.ndarray, layer: np.ndarray, x0: int, y0: int, xn: int,
                     yn: int) -> None:
    """updateWithAddition: skip unknown layer cells; unknown master takes the layer's value,
    others the sum capped at MAX_NON_OBSTACLE (252)."""
    for y in range(y0, yn):
        for x in range(x0, xn):
            v = layer[y, x]
            if v == NO_INFORMATION:
                continue
            m = master[y, x]
            if m == NO_INFORMATION:
                master[y, x] = v
            else:
                t = np.int64(m) + np.int64(v)
                master[y, x] = 252 if t > 252 else t
