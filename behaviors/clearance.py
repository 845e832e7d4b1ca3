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


def _segment_distances(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Distance of points p (..., K, 2) to segments a->b (..., E, 2): shape (..., K, E)."""
    ab = b - a                                              # (..., E, 2)
    ap = p[..., :, None, :] - a[..., None, :, :]            # (..., K, E, 2)
    den = np.maximum(np.sum(ab * ab, axis=-1), 1e-18)[..., None, :]
    t = np.clip(np.sum(ap * ab[..., None, :, :], axis=-1) / den, 0.0, 1.0)
    d = ap - t[..., None] * ab[..., None, :, :]
    return np.sqrt(np.sum(d * d, axis=-1))


def _inside(p: np.ndarray, poly: np.ndarray) -> np.ndarray:
    """Crossing-number test of points p (..., K, 2) against polygons (..., N, 2): (..., K)."""
    a = poly[..., None, :, :]
    b = np.roll(poly, -1, axis=-2)[..., None, :, :]
    px = p[..., :, None, 0]
    py = p[..., :, None, 1]
    crosses = (a[..., 1] > py) != (b[..., 1] > py)
    with np.errstate(divide="ignore", invalid="ignore"):
        xi = a[..., 0] + (py - a[..., 1]) * (b[..., 0] - a[..., 0]) / (b[..., 1] - a[..., 1])
    return (np.sum(crosses & (px < xi), axis=-1) % 2) == 1


def footprint_clearances(footprint: np.ndarray, poses: np.ndarray, squares: np.ndarray,
                         half: float) -> np.ndarray:
    """Signed clearance (m) of the footprint polygon at each pose (P, 3) from the squares of
    half-side ``half`` centred at ``squares`` (M, 2): the gap to the nearest one, or minus the
    depth of the deepest square corner inside the footprint. +inf without squares."""
    poses = np.asarray(poses, dtype=float).reshape(-1, 3)
    if squares.shape[0] == 0:
        return np.full(poses.shape[0], np.inf)
    c, s = np.cos(poses[:, 2]), np.sin(poses[:, 2])
    fx, fy = footprint[:, 0], footprint[:, 1]
    poly = np.stack([poses[:, None, 0] + c[:, None] * fx - s[:, None] * fy,
                     poses[:, None, 1] + s[:, None] * fx + c[:, None] * fy], axis=-1)  # (P,N,2)
    nxt = np.roll(poly, -1, axis=1)
    offs = np.array([[-half, -half], [half, -half], [half, half], [-half, half]])
    corners = (squares[:, None, :] + offs[None, :, :]).reshape(-1, 2)          # (4M, 2)
    cp = np.broadcast_to(corners, (poses.shape[0],) + corners.shape)
    # corners of the squares to the footprint's edges
    d_corner = _segment_distances(cp, poly, nxt).min(axis=-1)                  # (P, 4M)
    inside = _inside(cp, poly)
    # footprint vertices to the squares (axis-aligned box distance)
    dx = np.abs(poly[:, :, None, 0] - squares[None, None, :, 0]) - half
    dy = np.abs(poly[:, :, None, 1] - squares[None, None, :, 1]) - half
    d_vertex = np.hypot(np.maximum(dx, 0.0), np.maximum(dy, 0.0))             # (P, N, M)
    gap = np.minimum(d_corner.min(axis=-1), d_vertex.reshape(poses.shape[0], -1).min(axis=-1))
    vertex_in = np.any((dx < 0.0) & (dy < 0.0), axis=(1, 2))
    depth = np.where(inside, d_corner, 0.0).max(axis=-1)
    return np.where(inside.any(axis=-1), -depth, np.where(vertex_in, 0.0, gap))


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
