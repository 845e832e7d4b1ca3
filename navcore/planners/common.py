"""Helpers shared by the grid planners: validation, goal tolerance search, failure diagnosis."""

from __future__ import annotations

import math

import numpy as np

from navcore.costmap.costmap2d import Costmap2D
from navcore.planners.result import PlanReason
from navcore.planners.wavefront import POT_HIGH
from navcore.types import Pose2D


def finite_pose(p: Pose2D) -> bool:
    return all(math.isfinite(v) for v in (p.x, p.y, p.theta))


def search_tolerance(costmap: Costmap2D, pot: np.ndarray, goal: Pose2D, tolerance: float
                     ) -> tuple[float, float] | None:
    """navfn's goal tolerance: sample the square of half-side ``tolerance`` around the goal in
    ``resolution`` steps and return the sample closest to the goal whose cell has a potential
    (``pot`` flat, row-major)."""
    res = costmap.resolution
    if tolerance <= 0.0:
        # the one sample is the goal itself (the arrays below cost ~0.1 ms for it)
        gx, gy = goal.x + 0.0, goal.y + 0.0  # + 0.0 as the sampling adds its offset
        cell = costmap.world_to_map(gx, gy)
        if cell is None:
            return None
        return (gx, gy) if pot[cell[1] * costmap.size_x + cell[0]] < POT_HIGH else None
    n = int(math.floor((2.0 * tolerance) / res + 1e-9)) + 1
    offs = -tolerance + res * np.arange(n)
    offs = offs[offs <= tolerance + 1e-12]
    px = goal.x + offs
    py = goal.y + offs
    gx, gy = np.meshgrid(px, py)
    mx = np.floor((gx - costmap.origin_x) / res).astype(np.int64)
    my = np.floor((gy - costmap.origin_y) / res).astype(np.int64)
    inside = ((gx >= costmap.origin_x) & (gy >= costmap.origin_y) & (mx < costmap.size_x)
              & (my < costmap.size_y))
    if not inside.any():
        return None
    p = np.full(gx.shape, np.inf)
    p[inside] = pot[my[inside] * costmap.size_x + mx[inside]]
    ok = p < POT_HIGH
    if not ok.any():
        return None
    d2 = np.where(ok, (gx - goal.x) ** 2 + (gy - goal.y) ** 2, np.inf)
    k = int(np.argmin(d2))  # first minimum in row-major order, as the C++ loops find it
    return float(gx.flat[k]), float(gy.flat[k])


def diagnose(passable: np.ndarray, goal_cell: tuple[int, int] | None,
             updates: int) -> PlanReason:
    """Why no plan: the goal cell impassable (the map's outer border counts: the planners never
    enter it), the wave never left the start, or no connection."""
    if goal_cell is not None:
        gx, gy = goal_cell
        ny, nx = passable.shape
        if not passable[gy, gx] or gx in (0, nx - 1) or gy in (0, ny - 1):
            return PlanReason.GOAL_OCCUPIED
    return PlanReason.NO_PATH if updates > 0 else PlanReason.START_OCCUPIED
