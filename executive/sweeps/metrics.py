"""Figures of a run's driven path that the tuning guide's studies compare: how close the robot
came to obstacles and how much it turned per metre.

Both come from the simulator's ground-truth poses, one per control cycle. Clearance is measured
from the robot's centre to the nearest occupied cell of the map or cell covered by a static
scenario object (moving obstacles are left out: they are not where the path was planned);
subtract the circumscribed radius for a footprint's clearance.
"""

from __future__ import annotations

import math
from typing import Any, Sequence

import numpy as np

from navcore.distance_transform import squared_distance_transform


def obstacle_mask(grid: Any, objects: Sequence[Any] = ()) -> np.ndarray:
    """Occupied cells (value >= 65, map_server's default occupied threshold) plus the cells whose
    centre lies inside a box or circle object."""
    mask = np.asarray(grid.data) >= 65
    h, w = mask.shape
    res = grid.resolution
    ox, oy = grid.origin.x, grid.origin.y
    xs = ox + (np.arange(w) + 0.5) * res
    ys = oy + (np.arange(h) + 0.5) * res
    for shape in objects:
        if shape.kind == "box":
            x0, y0, x1, y1 = shape.values
            cols = (xs >= x0) & (xs <= x1)
            rows = (ys >= y0) & (ys <= y1)
            mask[np.ix_(rows, cols)] = True
        elif shape.kind == "circle":
            cx, cy, r = shape.values
            inside = (xs[None, :] - cx) ** 2 + (ys[:, None] - cy) ** 2 <= r * r
            mask |= inside
    return mask


def min_clearance(poses: Sequence[tuple[float, float, float]], grid: Any,
                  objects: Sequence[Any] = ()) -> float | None:
    """Smallest distance (m) from the robot's centre to an obstacle cell centre over the run."""
    if not poses:
        return None
    mask = obstacle_mask(grid, objects)
    if not mask.any():
        return None
    dist = np.sqrt(squared_distance_transform(mask)) * grid.resolution
    h, w = mask.shape
    best = math.inf
    for x, y, _ in poses:
        c = int(math.floor((x - grid.origin.x) / grid.resolution))
        r = int(math.floor((y - grid.origin.y) / grid.resolution))
        if 0 <= r < h and 0 <= c < w:
            best = min(best, float(dist[r, c]))
    return None if best == math.inf else best


def turning_per_metre(poses: Sequence[tuple[float, float, float]]) -> float | None:
    """Total absolute heading change (rad) over the distance driven (m): 0 for a straight line,
    larger for a path that weaves. None when the robot did not move."""
    turn = 0.0
    dist = 0.0
    for (x0, y0, a0), (x1, y1, a1) in zip(poses, poses[1:]):
        dist += math.hypot(x1 - x0, y1 - y0)
        turn += abs(math.remainder(a1 - a0, 2 * math.pi))
    return turn / dist if dist > 0.05 else None
