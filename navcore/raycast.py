"""Exact ray casting on occupancy grids and against simple shapes, as numba kernels.

The grid kernels walk the cells a ray crosses in order (Amanatides & Woo 1987, "A fast voxel
traversal algorithm") and return the distance at which the ray *enters* the first blocked cell, so
ranges are exact to the cell faces rather than quantised to cell centres. The simulator's laser, its
collision check and the AMCL beam model share them; all are ``@njit`` and callable from other njit
code.

Conventions: ``occ`` is a 2-D uint8/bool grid indexed ``[row = y, col = x]`` whose cell (0, 0) has
its lower-left corner at (``origin_x``, ``origin_y``) (no origin yaw); nonzero = blocked. Cells
outside the grid are free: a ray that leaves the grid hits nothing there. A ray starting inside a
blocked cell returns 0. Nothing hit within ``max_range`` returns ``max_range``.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from navcore.distance_transform import squared_edt

_INF = np.inf


@njit(cache=True)
def _axis_entry(g: float, d: float) -> int:
    """Index of the cell a ray sits in along one axis, looking in direction ``d`` (sign matters
    exactly on a cell face: moving towards -inf from face k means cell k-1)."""
    if d < 0.0:
        return int(math.ceil(g)) - 1
    return int(math.floor(g))


@njit(cache=True)
def _clip_to_grid(gx: float, gy: float, dx: float, dy: float, w: int, h: int,
                  t_end: float) -> tuple[float, float]:
    """Clip the ray (gx, gy) + t (dx, dy), 0 <= t <= ``t_end`` (grid units), to the grid
    rectangle [0, w] x [0, h] (slab method): the entry and exit parameters (t0, t1). The ray
    misses the grid when t0 > t1 or t0 >= t_end (a ray parallel to an axis and outside the grid
    along it gives t0 = inf)."""
    t0 = 0.0
    t1 = t_end
    if dx == 0.0:
        if gx < 0.0 or gx >= w:
            return _INF, _INF
    else:
        ta = (0.0 - gx) / dx
        tb = (w - gx) / dx
        if ta > tb:
            ta, tb = tb, ta
        t0 = max(t0, ta)
        t1 = min(t1, tb)
    if dy == 0.0:
        if gy < 0.0 or gy >= h:
            return _INF, _INF
    else:
        ta = (0.0 - gy) / dy
        tb = (h - gy) / dy
        if ta > tb:
            ta, tb = tb, ta
        t0 = max(t0, ta)
        t1 = min(t1, tb)
    return t0, t1


@njit(cache=True)
def cast_ray(occ: np.ndarray, origin_x: float, origin_y: float, resolution: float,
             x: float, y: float, angle: float, max_range: float) -> float:
    """Distance (m) from (x, y) along ``angle`` to the first blocked cell, else ``max_range``."""
    h, w = occ.shape
    dx = math.cos(angle)
    dy = math.sin(angle)
    gx = (x - origin_x) / resolution
    gy = (y - origin_y) / resolution
    t_end = max_range / resolution  # ray parameter in cells (|(dx, dy)| = 1)
    t0, t1 = _clip_to_grid(gx, gy, dx, dy, w, h, t_end)
    if t0 > t1 or t0 >= t_end:
        return max_range
    px = gx + t0 * dx
    py = gy + t0 * dy
    cx = min(max(_axis_entry(px, dx), 0), w - 1)
    cy = min(max(_axis_entry(py, dy), 0), h - 1)
    if dx > 0.0:
        step_x = 1
        t_max_x = (cx + 1 - gx) / dx
        t_delta_x = 1.0 / dx
    elif dx < 0.0:
        step_x = -1
        t_max_x = (cx - gx) / dx
        t_delta_x = -1.0 / dx
    else:
        step_x = 0
        t_max_x = _INF
        t_delta_x = _INF
    if dy > 0.0:
        step_y = 1
        t_max_y = (cy + 1 - gy) / dy
        t_delta_y = 1.0 / dy
    elif dy < 0.0:
        step_y = -1
        t_max_y = (cy - gy) / dy
        t_delta_y = -1.0 / dy
    else:
        step_y = 0
        t_max_y = _INF
        t_delta_y = _INF
    t = t0
    while True:
        if occ[cy, cx]:
            return t * resolution
        if t_max_x < t_max_y:
            t = t_max_x
            t_max_x += t_delta_x
            cx += step_x
            if cx < 0 or cx >= w:
                return max_range
        else:
            t = t_max_y
            t_max_y += t_delta_y
            cy += step_y
            if cy < 0 or cy >= h:
                return max_range
        if t >= t_end:
            return max_range


@njit(cache=True)
def cast_rays(occ: np.ndarray, origin_x: float, origin_y: float, resolution: float,
              x: float, y: float, angles: np.ndarray, max_range: float) -> np.ndarray:
    """``cast_ray`` for each of ``angles`` (float64[:], absolute world angles) from one point."""
    out = np.empty(angles.shape[0], np.float64)
    for i in range(angles.shape[0]):
        out[i] = cast_ray(occ, origin_x, origin_y, resolution, x, y, angles[i], max_range)
    return out


@njit(cache=True)
def distance_field(occ: np.ndarray) -> np.ndarray:
    """Exact Euclidean distance (in cells, float32) from each cell centre to the nearest blocked
    cell centre; 1e9 where the grid has no blocked cell at all. Computed once per static map, it
    lets ``cast_ray_df`` leap through open space."""
    h, w = occ.shape
    sq = squared_edt(occ)
    none = float(h * h + w * w)  # squared_edt's value when nothing is blocked exceeds this
    res = np.empty((h, w), np.float32)
    for r in range(h):
        for c in range(w):
            res[r, c] = math.sqrt(sq[r, c]) if sq[r, c] <= none else 1e9
    return res


@njit(cache=True)
def clearance_field(occ: np.ndarray) -> np.ndarray:
    """uint8 grid for ``cast_ray_clear``: 0 where blocked, else the distance in whole cells from
    the cell centre to the nearest blocked cell centre, rounded down and capped at 255. One byte a
    cell keeps the whole field in cache, which is what limits ray casting on large maps."""
    d = distance_field(occ)
    h, w = occ.shape
    out = np.empty((h, w), np.uint8)
    for r in range(h):
        for c in range(w):
            if occ[r, c]:
                out[r, c] = 0
            else:
                out[r, c] = np.uint8(min(max(math.floor(d[r, c]), 1.0), 255.0))
    return out


@njit(cache=True, inline="always")
def _march_clear(clear: np.ndarray, gx: float, gy: float, dx: float, dy: float, t_end: float,
                 t: float, t1: float, disks: np.ndarray, nd: int) -> tuple[float, int]:
    """Sphere tracing with the exact cell walk near obstacles, from parameter ``t`` (the ray is
    known to be clear up to there and inside the grid until ``t1``). Unless ``disks`` is None,
    each leap's clear disk is appended to it from row ``nd`` while there is room, as
    (ox, oy, k): the start minus the disk's centre and |o|^2 - radius^2, all a ray from this
    start needs to intersect it; returns (hit distance or ``t_end``, new disk count)."""
    h, w = clear.shape
    step_x = 1 if dx > 0.0 else (-1 if dx < 0.0 else 0)
    step_y = 1 if dy > 0.0 else (-1 if dy < 0.0 else 0)
    inv_x = 1.0 / dx if dx != 0.0 else _INF
    inv_y = 1.0 / dy if dy != 0.0 else _INF
    t_delta_x = abs(inv_x)
    t_delta_y = abs(inv_y)
    # the face ahead of cell c along x is at c + face_x (1 moving +x, 0 moving -x)
    face_x = 1.0 if dx > 0.0 else 0.0
    face_y = 1.0 if dy > 0.0 else 0.0
    while True:
        # (re)locate the cell holding the point at parameter t and its next faces
        cx = min(max(_axis_entry(gx + t * dx, dx), 0), w - 1)
        cy = min(max(_axis_entry(gy + t * dy, dy), 0), h - 1)
        t_max_x = (cx + face_x - gx) * inv_x if dx != 0.0 else _INF
        t_max_y = (cy + face_y - gy) * inv_y if dy != 0.0 else _INF
        while True:
            c = clear[np.uintp(cy), np.uintp(cx)]  # unsigned: no negative-index wraparound
            if c == 0:
                return t, nd
            if c >= 4:
                break  # far from everything: leap
            if t_max_x < t_max_y:
                t = t_max_x
                t_max_x += t_delta_x
                cx += step_x
                if not 0 <= cx < w:
                    return t_end, nd
            else:
                t = t_max_y
                t_max_y += t_delta_y
                cy += step_y
                if not 0 <= cy < h:
                    return t_end, nd
            if t >= t_end:
                return t_end, nd
        if disks is not None:  # pruned at compile time when None
            if nd < disks.shape[0]:
                # every point within c - 0.7072 of this cell's centre is clear (see
                # cast_ray_clear); 0.75 keeps a margin
                ox = gx - (cx + 0.5)
                oy = gy - (cy + 0.5)
                r = c - 0.75
                disks[nd, 0] = ox
                disks[nd, 1] = oy
                disks[nd, 2] = ox * ox + oy * oy - r * r
                nd += 1
        t += c - 1.5
        if t >= t1:
            return t_end, nd


@njit(cache=True)
def _exit_parameter(gx: float, gy: float, dx: float, dy: float, w: int, h: int,
                    t_end: float) -> float:
    """Where a ray starting inside the grid leaves it (capped at ``t_end``)."""
    t1 = t_end
    if dx > 0.0:
        t1 = min(t1, (w - gx) / dx)
    elif dx < 0.0:
        t1 = min(t1, -gx / dx)
    if dy > 0.0:
        t1 = min(t1, (h - gy) / dy)
    elif dy < 0.0:
        t1 = min(t1, -gy / dy)
    return t1


@njit(cache=True)
def cast_dir_clear(clear: np.ndarray, gx: float, gy: float, dx: float, dy: float,
                   t_end: float) -> float:
    """The core of ``cast_ray_clear`` in grid units: start (gx, gy) in cells, unit direction
    (dx, dy), range ``t_end`` in cells; returns the hit distance in cells or ``t_end``."""
    h, w = clear.shape
    if 0.0 <= gx < w and 0.0 <= gy < h:
        # inside (the usual case): only the exit parameter is needed
        t0 = 0.0
        t1 = _exit_parameter(gx, gy, dx, dy, w, h, t_end)
    else:
        t0, t1 = _clip_to_grid(gx, gy, dx, dy, w, h, t_end)
        if t0 > t1 or t0 >= t_end:
            return t_end
    return _march_clear(clear, gx, gy, dx, dy, t_end, t0, t1, None, 0)[0]


@njit(cache=True)
def cast_fan_clear(clear: np.ndarray, gx: float, gy: float, dirs: np.ndarray, t_end: float,
                   out: np.ndarray) -> None:
    """``cast_dir_clear`` for a fan of unit directions ``dirs`` (N, 2) from one start, in order
    of angle, into ``out`` (N,), with the same ranges (to rounding: the walk may start from
    another point of the same free stretch). Neighbouring beams pass through the same open
    space, so each beam first slides along the clear disks its predecessor leapt through (pure
    arithmetic) and only then reads the grid. Each leap is a chain of dependent steps (point,
    cell, load, next point), which is what a cast costs; on the Willow Garage map sliding
    replaces two leaps in three and a third of the time.
    The march is inlined (its call with array arguments cost more than the walk's mispredicted
    branches). Measurements and what was tried: docs/performance.md."""
    h, w = clear.shape
    n = dirs.shape[0]
    if not (0.0 <= gx < w and 0.0 <= gy < h):
        for i in range(n):
            out[i] = cast_dir_clear(clear, gx, gy, dirs[i, 0], dirs[i, 1], t_end)
        return
    # the disks of the previous beam; a beam keeps the prefix it slides through and appends
    # its own leaps after it, in place
    disks = np.empty((64, 3))
    nd = 0
    for i in range(n):
        dx = dirs[i, 0]
        dy = dirs[i, 1]
        t = 0.0
        kept = 0
        for j in range(nd):
            # the stretch of this ray inside disk j; slide to its end if it covers t, stop at
            # the first disk that does not (the rest lie farther along the previous beam)
            b = disks[j, 0] * dx + disks[j, 1] * dy
            disc = b * b - disks[j, 2]
            if not disc >= 0.0:  # the ray misses the disk
                break
            s = math.sqrt(disc)
            if not -b - s <= t < -b + s:
                break
            t = -b + s
            kept += 1
        t1 = _exit_parameter(gx, gy, dx, dy, w, h, t_end)
        if t >= t1:
            out[i] = t_end
            nd = kept
        else:
            out[i], nd = _march_clear(clear, gx, gy, dx, dy, t_end, t, t1, disks, kept)


@njit(cache=True)
def cast_ray_clear(clear: np.ndarray, origin_x: float, origin_y: float, resolution: float,
                   x: float, y: float, angle: float, max_range: float) -> float:
    """``cast_ray`` with the same exact result, on a ``clearance_field``: where the nearest blocked
    cell is far the ray leaps ahead by a distance that provably stays clear of every blocked cell
    (any point of a cell is within sqrt(2)/2 of its centre, so ``clearance - 1.5`` cells are
    safe), and walks cell by cell only near obstacles."""
    t_end = max_range / resolution
    t = cast_dir_clear(clear, (x - origin_x) / resolution, (y - origin_y) / resolution,
                       math.cos(angle), math.sin(angle), t_end)
    return max_range if t >= t_end else t * resolution


@njit(cache=True)
def cast_rays_clear(clear: np.ndarray, origin_x: float, origin_y: float, resolution: float,
                    x: float, y: float, angles: np.ndarray, max_range: float) -> np.ndarray:
    """``cast_ray_clear`` for each of ``angles`` from one point."""
    out = np.empty(angles.shape[0], np.float64)
    for i in range(angles.shape[0]):
        out[i] = cast_ray_clear(clear, origin_x, origin_y, resolution, x, y, angles[i],
                                max_range)
    return out


@njit(cache=True)
def segment_blocked(occ: np.ndarray, origin_x: float, origin_y: float, resolution: float,
                    x0: float, y0: float, x1: float, y1: float) -> bool:
    """True when the segment (x0, y0)-(x1, y1) touches a blocked cell (either end included)."""
    length = math.hypot(x1 - x0, y1 - y0)
    if length == 0.0:
        mx = int(math.floor((x0 - origin_x) / resolution))
        my = int(math.floor((y0 - origin_y) / resolution))
        if mx < 0 or my < 0 or my >= occ.shape[0] or mx >= occ.shape[1]:
            return False
        return bool(occ[my, mx])
    # a hair beyond the end so that a blocked cell starting exactly at the end point counts
    d = cast_ray(occ, origin_x, origin_y, resolution, x0, y0,
                 math.atan2(y1 - y0, x1 - x0), length * (1.0 + 1e-9) + 1e-12)
    return d <= length


@njit(cache=True)
def ray_circle(x: float, y: float, dx: float, dy: float, cx: float, cy: float, r: float) -> float:
    """Distance along the unit direction (dx, dy) from (x, y) to a circle's rim; inf if missed.

    A ray starting inside the circle returns 0 (the sensor is inside an object).
    """
    ox = x - cx
    oy = y - cy
    c = ox * ox + oy * oy - r * r
    if c <= 0.0:
        return 0.0
    b = ox * dx + oy * dy
    if b >= 0.0:
        return _INF
    disc = b * b - c
    if disc < 0.0:
        return _INF
    return -b - math.sqrt(disc)


@njit(cache=True)
def ray_segment(x: float, y: float, dx: float, dy: float,
                ax: float, ay: float, bx: float, by: float) -> float:
    """Distance along the unit direction (dx, dy) from (x, y) to segment a-b; inf if missed."""
    ex = bx - ax
    ey = by - ay
    den = dx * ey - dy * ex
    if den == 0.0:
        return _INF  # parallel: a zero-thickness segment seen edge-on returns nothing
    wx = ax - x
    wy = ay - y
    t = (wx * ey - wy * ex) / den
    u = (wx * dy - wy * dx) / den
    if t < 0.0 or u < 0.0 or u > 1.0:
        return _INF
    return t


@njit(cache=True)
def cast_rays_shapes(x: float, y: float, angles: np.ndarray, ranges: np.ndarray,
                     circles: np.ndarray, segments: np.ndarray) -> None:
    """Shorten ``ranges`` in place where a ray hits a circle (N, 3: cx, cy, r) or a segment
    (M, 4: ax, ay, bx, by) first. Used for objects the map does not know."""
    for i in range(angles.shape[0]):
        dx = math.cos(angles[i])
        dy = math.sin(angles[i])
        best = ranges[i]
        for k in range(circles.shape[0]):
            d = ray_circle(x, y, dx, dy, circles[k, 0], circles[k, 1], circles[k, 2])
            if d < best:
                best = d
        for k in range(segments.shape[0]):
            d = ray_segment(x, y, dx, dy, segments[k, 0], segments[k, 1],
                            segments[k, 2], segments[k, 3])
            if d < best:
                best = d
        ranges[i] = best
