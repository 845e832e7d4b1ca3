"""Robot footprints (costmap_2d footprint.cpp semantics) and the footprint cost of a pose.

A footprint is an (N, 2) float64 polygon in the robot frame. ``footprint_cost`` is a numba kernel
meant to be called from other kernels (the local planner scores hundreds of thousands of poses per
cycle), so it allocates one tiny array per call and reads each covered cell once.
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


@njit(cache=True, nogil=True, inline="always")
def _vertex(footprint: np.ndarray, k: int, x: float, y: float, c: float, s: float,
            origin_x: float, origin_y: float, inv: float) -> tuple[float, float]:
    """Vertex k at the pose, in cell units from the grid origin."""
    return ((x + c * footprint[k, 0] - s * footprint[k, 1] - origin_x) * inv,
            (y + s * footprint[k, 0] + c * footprint[k, 1] - origin_y) * inv)


@njit(cache=True, nogil=True)
def _square_meets_polygon(u: np.ndarray, v: np.ndarray, i: int, j: int) -> bool:
    """Whether the closed cell square [i, i+1] x [j, j+1] meets the polygon (u, v) (cell units):
    a vertex inside the square, a square corner inside the polygon, or an edge crossing it."""
    n = u.shape[0]
    for k in range(n):
        if i <= u[k] <= i + 1 and j <= v[k] <= j + 1:
            return True
    for corner in range(4):
        cx = i + (corner & 1)
        cy = j + (corner >> 1)
        inside = False
        for k in range(n):
            au, av, bu, bv = u[k - 1], v[k - 1], u[k], v[k]
            if (av <= cy) != (bv <= cy):
                if au + (cy - av) * (bu - au) / (bv - av) > cx:
                    inside = not inside
        if inside:
            return True
    for k in range(n):  # clip each edge to the square (Liang-Barsky)
        au, av = u[k - 1], v[k - 1]
        du, dv = u[k] - au, v[k] - av
        t0, t1 = 0.0, 1.0
        ok = True
        for side in range(4):
            if side == 0:
                p, q = -du, au - i
            elif side == 1:
                p, q = du, i + 1 - au
            elif side == 2:
                p, q = -dv, av - j
            else:
                p, q = dv, j + 1 - av
            if p == 0.0:
                if q < 0.0:
                    ok = False
                    break
            elif p < 0.0:
                t0 = max(t0, q / p)
            else:
                t1 = min(t1, q / p)
            if t0 > t1:
                ok = False
                break
        if ok:
            return True
    return False


@njit(cache=True, nogil=True)
def footprint_cost(costs: np.ndarray, origin_x: float, origin_y: float, resolution: float,
                   footprint: np.ndarray, x: float, y: float, theta: float) -> int:
    """Max cost of the cells the footprint covers at pose (x, y, theta): every cell its outline
    passes through and every cell inside it (a conservative rasterisation: no cell the robot
    overlaps is missed). -1 if any vertex is off the map.

    Row by row: the part of each edge within a row band gives the row's x extent; for a convex
    footprint the covered cells of a row are that one span, read with a vectorised max. A
    non-convex footprint checks each cell of the span exactly. One small allocation per call.
    """
    n = footprint.shape[0]
    size_y = costs.shape[0]
    size_x = costs.shape[1]
    c = math.cos(theta)
    s = math.sin(theta)
    inv = 1.0 / resolution
    vmin = 1e300
    vmax = -1e300
    for k in range(n):
        a, b = _vertex(footprint, k, x, y, c, s, origin_x, origin_y, inv)
        if not (a >= 0.0 and b >= 0.0 and a < size_x and b < size_y):  # also catches NaN
            return -1
        vmin = min(vmin, b)
        vmax = max(vmax, b)
    r0 = int(vmin)
    rows = int(vmax) - r0 + 1
    span = np.empty(2 * rows, dtype=np.float64)  # x extent of row band r: [2r], [2r + 1]
    for r in range(rows):
        span[2 * r] = 1e300
        span[2 * r + 1] = -1e300
    convex = True
    turn = 0.0
    au, av = _vertex(footprint, n - 1, x, y, c, s, origin_x, origin_y, inv)
    bu, bv = _vertex(footprint, 0, x, y, c, s, origin_x, origin_y, inv)
    for k in range(n):
        cu, cv = _vertex(footprint, k + 1 if k + 1 < n else 0, x, y, c, s, origin_x, origin_y,
                         inv)
        cross = (bu - au) * (cv - bv) - (bv - av) * (cu - bu)
        if cross != 0.0:  # convex iff every turn has one sign
            if turn == 0.0:
                turn = cross
            elif (cross > 0.0) != (turn > 0.0):
                convex = False
        e0 = min(av, bv)
        e1 = max(av, bv)
        if e0 == e1:
            r = int(e0) - r0
            span[2 * r] = min(span[2 * r], min(au, bu))
            span[2 * r + 1] = max(span[2 * r + 1], max(au, bu))
        else:
            slope = (bu - au) / (bv - av)
            for band in range(int(e0), int(e1) + 1):
                xa = au + (max(e0, float(band)) - av) * slope
                xb = au + (min(e1, band + 1.0) - av) * slope
                r = band - r0
                span[2 * r] = min(span[2 * r], min(xa, xb))
                span[2 * r + 1] = max(span[2 * r + 1], max(xa, xb))
        au, av, bu, bv = bu, bv, cu, cv
    best = 0
    for r in range(rows):
        if span[2 * r] > span[2 * r + 1]:
            continue
        row = r0 + r
        m0 = int(span[2 * r])
        m1 = min(int(span[2 * r + 1]), size_x - 1)
        crow = costs[row]
        if convex:
            rb = np.uint8(0)
            for mx in range(m0, m1 + 1):
                rb = max(rb, crow[mx])  # branch-free, vectorisable
            best = max(best, np.int64(rb))
        else:
            u = np.empty(n, dtype=np.float64)
            v = np.empty(n, dtype=np.float64)
            for k in range(n):
                u[k], v[k] = _vertex(footprint, k, x, y, c, s, origin_x, origin_y, inv)
            for mx in range(m0, m1 + 1):
                if crow[mx] > best and _square_meets_polygon(u, v, mx, row):
                    best = np.int64(crow[mx])
    return best


@njit(cache=True, nogil=True)
def footprint_costs(costs: np.ndarray, origin_x: float, origin_y: float, resolution: float,
                    footprint: np.ndarray, poses: np.ndarray) -> np.ndarray:
    """``footprint_cost`` of each (x, y, theta) row of ``poses`` (N, 3), as an int64 array."""
    out = np.empty(poses.shape[0], dtype=np.int64)
    for i in range(poses.shape[0]):
        out[i] = footprint_cost(costs, origin_x, origin_y, resolution, footprint, poses[i, 0],
                                poses[i, 1], poses[i, 2])
    return out


def transform_footprint(fp: np.ndarray, x: float, y: float, theta: float) -> np.ndarray:
    """The footprint polygon placed at pose (x, y, theta) in the world frame, (N, 2)."""
    c, s = math.cos(theta), math.sin(theta)
    return np.stack([x + c * fp[:, 0] - s * fp[:, 1], y + s * fp[:, 0] + c * fp[:, 1]], axis=1)
