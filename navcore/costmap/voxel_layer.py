"""costmap_2d::VoxelLayer: 3-D marking and clearing in a column-bit voxel grid, projected to 2-D.

Each (x, y) column is one uint32: bit z says "seen" and bit z + 16 says "marked" for voxel z
(both set: marked; neither: free; one: unknown). A column starts all unknown. A 2-D cell is
LETHAL once more than ``mark_threshold`` voxels of its column are marked; a clearing ray frees
the voxels it crosses and sets the cell FREE (or NO_INFORMATION when more than
``unknown_threshold`` voxels stay unknown) if no more than ``mark_threshold`` stay marked.
"""

from __future__ import annotations

import math
from typing import Any, Mapping

import numpy as np
from numba import njit

from navcore.clock import Clock
from navcore.costmap.cost_values import FREE_SPACE, LETHAL_OBSTACLE, NO_INFORMATION
from navcore.costmap.costmap2d import shift_grid
from navcore.costmap.layer import grow_bounds
from navcore.costmap.obstacle_layer import OBSTACLE_PARAMS, ObstacleLayer, grow_bounds_to_ray_end
from navcore.params import Param

VOXEL_BITS = 16
UNKNOWN_COLUMN = np.uint32(0x0000FFFF)  # every voxel seen-bit set, none marked: all unknown

VOXEL_PARAMS = (
    Param("origin_z", 0.0, float, "height (m) of the bottom of the voxel grid"),
    Param("z_resolution", 0.2, float, "height (m) of one voxel", min=1e-6),
    Param("z_voxels", 10, int, "voxels per column", min=1, max=16),
    Param("unknown_threshold", 15, int, "unknown voxels a column may keep and count as free",
          min=0, max=16),
    Param("mark_threshold", 0, int, "marked voxels a column may hold and count as free",
          min=0, max=16),
    Param("publish_voxel_map", False, bool, "kept for config compatibility"),
)


@njit(cache=True, nogil=True)
def _popcount(v: np.uint32) -> int:
    n = 0
    while v:
        v &= v - np.uint32(1)
        n += 1
    return n


@njit(cache=True, nogil=True)
def _clear_voxel(voxels: np.ndarray, costs: np.ndarray, x: int, y: int, z: int,
                 mark_threshold: int, unknown_threshold: int) -> None:
    col = voxels[y, x] & ~(np.uint32(0x10001) << np.uint32(z))
    voxels[y, x] = col
    marked = col >> np.uint32(16)
    unknown = (col >> np.uint32(16)) ^ (col & np.uint32(0xFFFF))
    if _popcount(marked) <= mark_threshold:
        if _popcount(unknown) <= unknown_threshold:
            costs[y, x] = FREE_SPACE
        else:
            costs[y, x] = NO_INFORMATION


@njit(cache=True, nogil=True)
def _voxel_raytrace(voxels: np.ndarray, costs: np.ndarray, origin_x: float, origin_y: float,
                    resolution: float, origin_z: float, z_resolution: float, size_z: int,
                    o: np.ndarray, points: np.ndarray, raytrace_range: float,
                    mark_threshold: int, unknown_threshold: int, bounds: np.ndarray) -> None:
    """Clear voxel lines from the sensor origin ``o`` to each point (range-limited, clipped to
    the grid), as VoxelLayer raytraceFreespace + clearVoxelLineInMap."""
    size_y, size_x = costs.shape
    ox, oy, oz = o[0], o[1], o[2]
    sx = (ox - origin_x) / resolution
    sy = (oy - origin_y) / resolution
    sz = (oz - origin_z) / z_resolution
    if sx < 0 or sy < 0 or sz < 0 or sx >= size_x or sy >= size_y or sz >= size_z:
        return
    end_x = origin_x + size_x * resolution
    end_y = origin_y + size_y * resolution
    end_z = origin_z + size_z * z_resolution
    cell_range = max(0, int(math.ceil(raytrace_range / resolution)))
    grow_bounds(bounds, ox, oy)
    for i in range(points.shape[0]):
        wx, wy, wz = points[i, 0], points[i, 1], points[i, 2]
        dist = math.sqrt((wx - ox) ** 2 + (wy - oy) ** 2 + (wz - oz) ** 2)
        f = 1.0 if dist == 0.0 else min(1.0, raytrace_range / dist)
        wx = ox + f * (wx - ox)
        wy = oy + f * (wy - oy)
        wz = oz + f * (wz - oz)
        a, b, c = wx - ox, wy - oy, wz - oz
        if wz > end_z:
            t = (end_z - 0.01 - oz) / c
            wx, wy, wz = ox + a * t, oy + b * t, end_z - 0.01
        elif wz < origin_z:
            t = (origin_z - oz) / c
            wx, wy, wz = ox + a * t, oy + b * t, origin_z
        if wx < origin_x:
            t = (origin_x - ox) / a
            wx, wy, wz = origin_x, oy + b * t, oz + c * t
        if wy < origin_y:
            t = (origin_y - oy) / b
            wx, wy, wz = ox + a * t, origin_y, oz + c * t
        if wx > end_x:
            t = (end_x - ox) / a
            wx, wy, wz = end_x - 0.001, oy + b * t, oz + c * t
        if wy > end_y:
            t = (end_y - oy) / b
            wx, wy, wz = ox + a * t, end_y - 0.001, oz + c * t
        px = (wx - origin_x) / resolution
        py = (wy - origin_y) / resolution
        pz = (wz - origin_z) / z_resolution
        if px < 0 or py < 0 or pz < 0 or px >= size_x or py >= size_y or pz >= size_z:
            continue
        # 3-D Bresenham on the integer cells, dominant axis first
        x0, y0, z0 = int(sx), int(sy), int(sz)
        dx, dy, dz = int(px) - x0, int(py) - y0, int(pz) - z0
        adx, ady, adz = abs(dx), abs(dy), abs(dz)
        stx = 1 if dx > 0 else (-1 if dx < 0 else 0)
        sty = 1 if dy > 0 else (-1 if dy < 0 else 0)
        stz = 1 if dz > 0 else (-1 if dz < 0 else 0)
        d = math.sqrt((sx - px) ** 2 + (sy - py) ** 2 + (sz - pz) ** 2)
        scale = 1.0 if d == 0.0 else min(1.0, cell_range / d)
        x, y, z = x0, y0, z0
        if adx >= ady and adx >= adz:
            eb, ec = adx // 2, adx // 2
            n = min(int(scale * adx), adx)
            for _ in range(n):
                _clear_voxel(voxels, costs, x, y, z, mark_threshold, unknown_threshold)
                x += stx
                eb += ady
                ec += adz
                if eb >= adx:
                    y += sty
                    eb -= adx
                if ec >= adx:
                    z += stz
                    ec -= adx
        elif ady >= adz:
            eb, ec = ady // 2, ady // 2
            n = min(int(scale * ady), ady)
            for _ in range(n):
                _clear_voxel(voxels, costs, x, y, z, mark_threshold, unknown_threshold)
                y += sty
                eb += adx
                ec += adz
                if eb >= ady:
                    x += stx
                    eb -= ady
                if ec >= ady:
                    z += stz
                    ec -= ady
        else:
            eb, ec = adz // 2, adz // 2
            n = min(int(scale * adz), adz)
            for _ in range(n):
                _clear_voxel(voxels, costs, x, y, z, mark_threshold, unknown_threshold)
                z += stz
                eb += adx
                ec += ady
                if eb >= adz:
                    x += stx
                    eb -= adz
                if ec >= adz:
                    y += sty
                    ec -= adz
        _clear_voxel(voxels, costs, x, y, z, mark_threshold, unknown_threshold)
        grow_bounds_to_ray_end(bounds, ox, oy, wx, wy, raytrace_range)


@njit(cache=True, nogil=True)
def _voxel_mark(voxels: np.ndarray, costs: np.ndarray, origin_x: float, origin_y: float,
                resolution: float, origin_z: float, z_resolution: float, size_z: int,
                o: np.ndarray, points: np.ndarray, obstacle_range: float, max_height: float,
                mark_threshold: int, bounds: np.ndarray) -> None:
    size_y, size_x = costs.shape
    sq = obstacle_range * obstacle_range
    for i in range(points.shape[0]):
        px, py, pz = points[i, 0], points[i, 1], points[i, 2]
        if pz > max_height:
            continue
        if (px - o[0]) ** 2 + (py - o[1]) ** 2 + (pz - o[2]) ** 2 >= sq:
            continue
        if px < origin_x or py < origin_y or pz < origin_z:
            continue
        mx = int((px - origin_x) / resolution)
        my = int((py - origin_y) / resolution)
        mz = int((pz - origin_z) / z_resolution)
        if mx >= size_x or my >= size_y or mz >= size_z:
            continue
        col = voxels[my, mx] | (np.uint32(0x10001) << np.uint32(mz))
        voxels[my, mx] = col
        if _popcount(col >> np.uint32(16)) > mark_threshold:
            costs[my, mx] = LETHAL_OBSTACLE
            grow_bounds(bounds, px, py)


class VoxelLayer(ObstacleLayer):
    """costmap_2d::VoxelLayer: the obstacle layer's sources and combination, with a voxel grid.

    The effective unknown threshold is ``unknown_threshold + (16 - z_voxels)``, since the unused
    bits of a column always read unknown.
    """

    kind = "voxel"
    PARAMS = OBSTACLE_PARAMS

    def __init__(self, name: str, params: Mapping[str, Any] | None = None,
                 clock: Clock | None = None, inherited: Mapping[str, Any] | None = None) -> None:
        super().__init__(name, params, clock, inherited, extra_specs=VOXEL_PARAMS)
        self.voxels = np.full((1, 1), UNKNOWN_COLUMN, dtype=np.uint32)

    @property
    def effective_unknown_threshold(self) -> int:
        return self.params.unknown_threshold + (VOXEL_BITS - self.params.z_voxels)

    def match_size(self, size_x: int, size_y: int, resolution: float, origin_x: float,
                   origin_y: float) -> None:
        super().match_size(size_x, size_y, resolution, origin_x, origin_y)
        self.voxels = np.full((size_y, size_x), UNKNOWN_COLUMN, dtype=np.uint32)

    def update_origin(self, origin_x: float, origin_y: float) -> None:
        g = self.grid
        cx = int((origin_x - g.origin_x) / g.resolution)
        cy = int((origin_y - g.origin_y) / g.resolution)
        if cx or cy:
            self.voxels = shift_grid(self.voxels, cx, cy, UNKNOWN_COLUMN)
        super().update_origin(origin_x, origin_y)

    def reset(self) -> None:
        super().reset()
        self.voxels[...] = UNKNOWN_COLUMN

    def clear_area(self, x0: int, y0: int, x1: int, y1: int, invert: bool) -> None:
        """Clear the 2-D grid as costmap_2d does, and the voxel columns with it (so that old
        marks cannot add up with new ones after a clearing recovery)."""
        ys = np.arange(self.voxels.shape[0])[:, None]
        xs = np.arange(self.voxels.shape[1])[None, :]
        inside = (xs > x0) & (xs < x1) & (ys > y0) & (ys < y1)
        self.voxels[inside if invert else ~inside] = UNKNOWN_COLUMN
        super().clear_area(x0, y0, x1, y1, invert)

    def _raytrace_and_mark(self, b: np.ndarray) -> None:
        g, p = self.grid, self.params
        for buf in self.buffers.values():
            if buf.params.clearing:
                for o in buf.observations():
                    _voxel_raytrace(self.voxels, g.costs, g.origin_x, g.origin_y, g.resolution,
                                    p.origin_z, p.z_resolution, p.z_voxels, o.origin, o.points,
                                    o.raytrace_range, p.mark_threshold,
                                    self.effective_unknown_threshold, b)
        for buf in self.buffers.values():
            if buf.params.marking:
                for o in buf.observations():
                    _voxel_mark(self.voxels, g.costs, g.origin_x, g.origin_y, g.resolution,
                                p.origin_z, p.z_resolution, p.z_voxels, o.origin, o.points,
                                o.obstacle_range, p.max_obstacle_height, p.mark_threshold, b)
