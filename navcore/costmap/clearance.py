"""Exact clearance between the robot footprint and the lethal cells of a costmap.

The costmap's footprint check is a conservative rasterisation: every cell the outline passes
through counts, so a robot a few centimetres from a wall "touches" it on the grid. That is the
right test for planning, but it leaves a robot that is already that close (pushed there, or
started there) unable to move at all. Escape motions therefore also ask the geometric question:
how far is the footprint polygon from the nearest lethal cell, treated as the square it is?
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from navcore.costmap.cost_values import LETHAL_OBSTACLE
from navcore.types import Pose2D


def lethal_squares(costs: np.ndarray, origin_x: float, origin_y: float, resolution: float,
                   cx: float, cy: float, radius: float) -> np.ndarray:
    """Centres (M, 2) of the lethal cells within ``radius`` metres (a square window) of
    (cx, cy)."""
    h, w = costs.shape
    x0 = max(0, int(math.floor((cx - radius - origin_x) / resolution)))
    x1 = min(w, int(math.ceil((cx + radius - origin_x) / resolution)) + 1)
    y0 = max(0, int(math.floor((cy - radius - origin_y) / resolution)))
    y1 = min(h, int(math.ceil((cy + radius - origin_y) / resolution)) + 1)
    if x0 >= x1 or y0 >= y1:
        return np.empty((0, 2))
    my, mx = np.nonzero(costs[y0:y1, x0:x1] >= LETHAL_OBSTACLE)
    return np.column_stack([origin_x + (mx + x0 + 0.5) * resolution,
                            origin_y + (my + y0 + 0.5) * resolution])


def footprint_clearances(footprint: np.ndarray, poses: np.ndarray, squares: np.ndarray,
                         half: float) -> np.ndarray:
    """Signed clearance (m) of the footprint polygon at each pose (P, 3) from the squares of
    half-side ``half`` centred at ``squares`` (M, 2): the gap to the nearest one, or minus the
    depth of the deepest square corner inside the footprint. +inf without squares."""
    poses = np.asarray(poses, dtype=float).reshape(-1, 3)
    if squares.shape[0] == 0:
        return np.full(poses.shape[0], np.inf)
    # numpy's cos/sin, as the poses' headings are elsewhere (numba's may differ in the last bit)
    return _clearances(np.ascontiguousarray(footprint, dtype=float),
                       np.ascontiguousarray(poses), np.cos(poses[:, 2]), np.sin(poses[:, 2]),
                       np.ascontiguousarray(squares, dtype=float), float(half))


@njit(cache=True)
def _clearances(footprint: np.ndarray, poses: np.ndarray, cos_t: np.ndarray, sin_t: np.ndarray,
                squares: np.ndarray, half: float) -> np.ndarray:
    """``footprint_clearances`` pose by pose, without the (P, 4M, N, 2) temporaries.

    Per pose: the distance of every square corner to the footprint's edges (and whether it is
    inside, by crossing number), and the box distance of every footprint vertex to every square.
    """
    n, m = footprint.shape[0], squares.shape[0]
    out = np.empty(poses.shape[0])
    px, py = np.empty(n), np.empty(n)
    abx, aby, den = np.empty(n), np.empty(n), np.empty(n)
    nxt = np.empty(n, np.int64)
    for i in range(n):
        nxt[i] = i + 1 if i + 1 < n else 0
    offs = ((-half, -half), (half, -half), (half, half), (-half, half))
    for k in range(poses.shape[0]):
        c, s = cos_t[k], sin_t[k]
        for i in range(n):
            px[i] = poses[k, 0] + c * footprint[i, 0] - s * footprint[i, 1]
            py[i] = poses[k, 1] + s * footprint[i, 0] + c * footprint[i, 1]
        for i in range(n):  # edge i runs from vertex i to vertex nxt[i]
            abx[i], aby[i] = px[nxt[i]] - px[i], py[nxt[i]] - py[i]
            den[i] = max(abx[i] * abx[i] + aby[i] * aby[i], 1e-18)
        gap = math.inf
        depth = 0.0
        any_inside = False
        for j in range(m):
            for o in range(4):
                qx = squares[j, 0] + offs[o][0]
                qy = squares[j, 1] + offs[o][1]
                d2_min = math.inf  # squared: sqrt is monotonic, so one sqrt of the minimum
                crossings = 0
                for i in range(n):
                    ax, ay = px[i], py[i]
                    apx, apy = qx - ax, qy - ay
                    t = min(max((apx * abx[i] + apy * aby[i]) / den[i], 0.0), 1.0)
                    dx, dy = apx - t * abx[i], apy - t * aby[i]
                    d2 = dx * dx + dy * dy
                    if d2 < d2_min:
                        d2_min = d2
                    if (ay > qy) != (py[nxt[i]] > qy):
                        if qx < ax + (qy - ay) * abx[i] / aby[i]:
                            crossings += 1
                d_min = math.sqrt(d2_min)
                if d_min < gap:
                    gap = d_min
                if crossings % 2 == 1:
                    any_inside = True
                    if d_min > depth:
                        depth = d_min
        vertex_in = False
        for i in range(n):
            for j in range(m):
                dx = abs(px[i] - squares[j, 0]) - half
                dy = abs(py[i] - squares[j, 1]) - half
                if dx < 0.0 and dy < 0.0:
                    vertex_in = True
                d = np.hypot(max(dx, 0.0), max(dy, 0.0))  # libm's in both modes, as in the test
                if d < gap:
                    gap = d
        out[k] = -depth if any_inside else (0.0 if vertex_in else gap)
    return out


def body_polygon(handle: object) -> np.ndarray | None:
    """The robot's own outline: the handle's footprint without its ``footprint_padding``
    (undoing costmap_2d's per-axis padding); None for a handle without a footprint polygon."""
    fp = getattr(handle, "footprint", None)
    if not isinstance(fp, np.ndarray) or fp.ndim != 2 or fp.shape[1] != 2:
        return None
    pad = float(getattr(getattr(handle, "params", None), "footprint_padding", 0.0) or 0.0)
    body = fp.astype(float).copy()
    body[:, 0] -= np.sign(body[:, 0]) * pad
    body[:, 1] -= np.sign(body[:, 1]) * pad
    return body


def clearances(handle: object, poses: list[Pose2D]) -> np.ndarray | None:
    """Signed clearance of the robot's body (the footprint without padding: in a tight spot
    the padding is the margin being spent) at each pose from the handle's lethal cells; None
    when the handle exposes no footprint polygon and grid (a scripted costmap)."""
    fp = body_polygon(handle)
    cm = getattr(handle, "costmap", None)
    if fp is None or cm is None or not poses:
        return None
    arr = np.array([[p.x, p.y, p.theta] for p in poses], dtype=float)
    reach = float(np.max(np.hypot(fp[:, 0], fp[:, 1]))) + 2.0 * cm.resolution
    lo, hi = arr[:, :2].min(axis=0), arr[:, :2].max(axis=0)
    mid = 0.5 * (lo + hi)
    radius = 0.5 * float(np.max(hi - lo)) + reach
    sq = lethal_squares(np.asarray(cm.costs), cm.origin_x, cm.origin_y, cm.resolution,
                        float(mid[0]), float(mid[1]), radius)
    return footprint_clearances(fp, arr, sq, 0.5 * cm.resolution)
