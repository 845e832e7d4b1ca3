"""Robot footprints (costmap_2d footprint.cpp semantics) and the footprint cost of a pose.

A footprint is an (N, 2) float64 polygon in the robot frame. ``footprint_cost`` is a numba kernel
meant to be called from other kernels (the local planner scores hundreds of thousands of poses per
cycle), so it allocates only two tiny arrays per call and visits each covered cell about once.
"""

from __future__ import annotations

import ast
import math
from typing import Any

import numpy as np
from numba import njit

NUM_RADIUS_VERTICES = 16  # makeFootprintFromRadius uses a 16-gon


def _sign0(v: float) -> float:
    return 1.0 if v > 0 else (-1.0 if v < 0 else 0.0)


def parse_footprint(footprint: Any) -> np.ndarray:
    """An (N, 2) float64 polygon from a list of [x, y] pairs or its ROS string form "[[x,y],...]".

    Raises ValueError naming what is wrong (fewer than 3 points, a non-pair, a non-number).
    """
    if isinstance(footprint, str):
        try:
            footprint = ast.literal_eval(footprint.strip())
        except (ValueError, SyntaxError) as e:
            raise ValueError(f"footprint: cannot parse {footprint!r} as [[x, y], ...]: {e}"
                             ) from None
    try:
        fp = np.asarray(footprint, dtype=np.float64)
    except (TypeError, ValueError):
        raise ValueError(f"footprint: expected a list of [x, y] pairs, got {footprint!r}") from None
    if fp.ndim != 2 or fp.shape[1] != 2:
        raise ValueError(f"footprint: expected a list of [x, y] pairs, got shape {fp.shape}")
    if fp.shape[0] < 3:
        raise ValueError(f"footprint: a polygon needs at least 3 points, got {fp.shape[0]}")
    if not np.all(np.isfinite(fp)):
        raise ValueError("footprint: every coordinate must be finite")
    return fp


def make_footprint(footprint: Any = None, robot_radius: float = 0.46,
                   footprint_padding: float = 0.01) -> np.ndarray:
    """The padded footprint polygon, (N, 2) float64, as Costmap2DROS builds it.

    A given ``footprint`` polygon wins; otherwise ``robot_radius`` gives a 16-gon. Padding then
    moves each vertex outward per axis (x += sign0(x) * pad, y += sign0(y) * pad), like padFootprint.
    An empty list or string counts as "not given", as in ROS.
    """
    given = footprint is not None
    if isinstance(footprint, str):
        given = footprint.strip() not in ("", "[]")
    elif isinstance(footprint, (list, tuple)):
        given = len(footprint) > 0
    if given:
        fp = parse_footprint(footprint).copy()
    else:
        if not robot_radius > 0:
            raise ValueError(f"robot_radius: must be > 0 without a footprint, got {robot_radius}")
        a = np.arange(NUM_RADIUS_VERTICES) * (2.0 * math.pi / NUM_RADIUS_VERTICES)
        fp = np.stack([robot_radius * np.cos(a), robot_radius * np.sin(a)], axis=1)
    pad = float(footprint_padding)
    fp[:, 0] += np.sign(fp[:, 0]) * pad
    fp[:, 1] += np.sign(fp[:, 1]) * pad
    return np.ascontiguousarray(fp, dtype=np.float64)


def _min_max_distances(fp: np.ndarray) -> tuple[float, float]:
    """costmap_2d calculateMinAndMaxDistances: over every edge, the vertex distance and the
    distance from the origin to the edge segment; min and max of all of them."""
    fp = np.asarray(fp, dtype=np.float64)
    lo, hi = math.inf, -math.inf
    n = len(fp)
    for i in range(n):
        x0, y0 = fp[i]
        x1, y1 = fp[(i + 1) % n]
        vertex = math.hypot(x0, y0)
        dx, dy = x1 - x0, y1 - y0
        seg2 = dx * dx + dy * dy
        t = 0.0 if seg2 == 0.0 else min(1.0, max(0.0, -(x0 * dx + y0 * dy) / seg2))
        edge = math.hypot(x0 + t * dx, y0 + t * dy)
        lo = min(lo, vertex, edge)
        hi = max(hi, vertex, edge)
    return lo, hi


def inscribed_radius(fp: np.ndarray) -> float:
    """Radius of the largest origin-centred circle inside the footprint (costmap_2d definition)."""
    return _min_max_distances(fp)[0]


def circumscribed_radius(fp: np.ndarray) -> float:
    """Radius of the smallest origin-centred circle holding the footprint."""
    return _min_max_distances(fp)[1]


@njit(cache=True, nogil=True)
def _line_max(costs: np.ndarray, x0: int, y0: int, x1: int, y1: int, best: int) -> int:
    """Max of ``best`` and the costs on the line from (x0, y0) to (x1, y1), both ends included.

    Bresenham stepping as base_local_planner's LineIterator: the error starts at half the major
    delta and a minor step happens when it reaches the major delta.
    """
    dx = abs(x1 - x0)
    dy = abs(y1 - y0)
    sx = 1 if x1 >= x0 else -1
    sy = 1 if y1 >= y0 else -1
    x = x0
    y = y0
    if dx >= dy:
        num = dx // 2
        for _ in range(dx + 1):
            c = costs[y, x]
            if c > best:
                best = c
            num += dy
            if num >= dx:
                num -= dx
                y += sy
            x += sx
    else:
        num = dy // 2
        for _ in range(dy + 1):
            c = costs[y, x]
            if c > best:
                best = c
            num += dx
            if num >= dy:
                num -= dy
                x += sx
            y += sy
    return best


@njit(cache=True, nogil=True)
def footprint_cost(costs: np.ndarray, origin_x: float, origin_y: float, resolution: float,
                   footprint: np.ndarray, x: float, y: float, theta: float) -> int:
    """Max cost of the cells under the footprint outline and inside it at pose (x, y, theta).

    The outline is the Bresenham line between the cells of consecutive vertices (ends included);
    the inside is every cell whose centre lies in the polygon (even-odd rule, so non-convex
    footprints work too). Returns -1 if any vertex is off the map. Scan conversion is edge
    driven: each edge only visits the rows it spans.
    """
    n = footprint.shape[0]
    size_y = costs.shape[0]
    size_x = costs.shape[1]
    c = math.cos(theta)
    s = math.sin(theta)
    inv = 1.0 / resolution
    # vertices in the world, and their cells; any vertex off the map -> -1
    vw = np.empty((n, 2), dtype=np.float64)
    min_my = size_y
    max_my = -1
    for i in range(n):
        wx = x + c * footprint[i, 0] - s * footprint[i, 1]
        wy = y + s * footprint[i, 0] + c * footprint[i, 1]
        vw[i, 0] = wx
        vw[i, 1] = wy
        mx = int(math.floor((wx - origin_x) * inv))
        my = int(math.floor((wy - origin_y) * inv))
        if mx < 0 or my < 0 or mx >= size_x or my >= size_y:
            return -1
        if my < min_my:
            min_my = my
        if my > max_my:
            max_my = my
    # outline
    best = 0
    pmx = int(math.floor((vw[n - 1, 0] - origin_x) * inv))
    pmy = int(math.floor((vw[n - 1, 1] - origin_y) * inv))
    for i in range(n):
        mx = int(math.floor((vw[i, 0] - origin_x) * inv))
        my = int(math.floor((vw[i, 1] - origin_y) * inv))
        best = _line_max(costs, pmx, pmy, mx, my, best)
        pmx = mx
        pmy = my
    if best == 255:
        return best
    # inside: per row, the leftmost and rightmost edge crossing at the cell-centre height
    rows = max_my - min_my + 1
    span = np.empty((rows, 2), dtype=np.float64)
    count = np.zeros(rows, dtype=np.int64)
    for r in range(rows):
        span[r, 0] = 1e300
        span[r, 1] = -1e300
    for i in range(n):
        ax = vw[i - 1, 0]
        ay = vw[i - 1, 1]
        bx = vw[i, 0]
        by = vw[i, 1]
        if ay == by:
            continue
        ylo = min(ay, by)
        yhi = max(ay, by)
        slope = (bx - ax) / (by - ay)
        r0 = max(int(math.floor((ylo - origin_y) * inv - 0.5)), min_my)
        r1 = min(int(math.floor((yhi - origin_y) * inv - 0.5)) + 1, max_my)
        for row in range(r0, r1 + 1):
            yc = origin_y + (row + 0.5) * resolution
            if yc < ylo or yc >= yhi:
                continue
            xc = ax + (yc - ay) * slope
            k = row - min_my
            count[k] += 1
            if xc < span[k, 0]:
                span[k, 0] = xc
            if xc > span[k, 1]:
                span[k, 1] = xc
    for k in range(rows):
        if count[k] < 2:
            continue
        row = min_my + k
        yc = origin_y + (row + 0.5) * resolution
        # centres cx = origin_x + (mx + 0.5) * res within [xl, xr]
        m0 = max(int(math.ceil((span[k, 0] - origin_x) * inv - 0.5)), 0)
        m1 = min(int(math.floor((span[k, 1] - origin_x) * inv - 0.5)), size_x - 1)
        crow = costs[row]
        if count[k] == 2:  # one span (every row of a convex footprint)
            rb = np.uint8(0)
            for mx in range(m0, m1 + 1):
                rb = max(rb, crow[mx])  # branch-free, vectorisable
            if rb > best:
                best = rb
        else:  # non-convex row: even-odd test per cell centre
            for mx in range(m0, m1 + 1):
                xc0 = origin_x + (mx + 0.5) * resolution
                inside = False
                for i in range(n):
                    ax = vw[i - 1, 0]
                    ay = vw[i - 1, 1]
                    bx = vw[i, 0]
                    by = vw[i, 1]
                    if (ay <= yc < by) or (by <= yc < ay):
                        if ax + (yc - ay) * (bx - ax) / (by - ay) > xc0:
                            inside = not inside
                if inside:
                    v = crow[mx]
                    if v > best:
                        best = v
        if best == 255:
            return best
    return best


def transform_footprint(fp: np.ndarray, x: float, y: float, theta: float) -> np.ndarray:
    """The footprint polygon placed at pose (x, y, theta) in the world frame, (N, 2)."""
    c, s = math.cos(theta), math.sin(theta)
    return np.stack([x + c * fp[:, 0] - s * fp[:, 1], y + s * fp[:, 0] + c * fp[:, 1]], axis=1)
