"""The pose to drive to when the goal itself is occupied: the free cell nearest to the goal within
a tolerance that the robot can reach.

This is the planners' ``default_tolerance`` (navfn, global_planner; Nav2 NavFn's ``tolerance``)
made explicit: the square of half-side ``tolerance`` around the goal is searched for cells whose
cost is below ``threshold`` (the planners' impassable cost, inscribed, by default; unknown counts
as occupied, since nobody has seen the robot could stand there), nearest to the goal first. The
free cells of the window are split into 4-connected pieces (the planners' wave is 4-connected):
one plan to the nearest cell of a piece tells whether the robot reaches any of it, so an
unreachable piece (the far side of a wall) costs one plan, not one per cell.

A costmap cannot tell a cell seen free from one never seen (the inside of a box whose near face
the laser marked is "free"): pieces the robot has a line of sight to (no lethal cell on the
segment) come first, nearest first, then the hidden ones. Without it a goal just inside a box
sends the robot round the box looking for a way into its unseen inside.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np
from numba import njit

from navcore.costmap.cost_values import INSCRIBED_INFLATED_OBSTACLE, LETHAL_OBSTACLE
from navcore.costmap.costmap2d import Costmap2D
from navcore.raycast import segment_blocked
from navcore.types import Pose2D


@njit(cache=True, nogil=True)
def label_free(free: np.ndarray) -> np.ndarray:
    """4-connected labels (1, 2, ... in row-major order of first cell) of the True cells of
    ``free`` (2-D bool); 0 where False."""
    ny, nx = free.shape
    labels = np.zeros((ny, nx), np.int32)
    stack = np.empty(ny * nx, np.int64)
    n = 0
    for y0 in range(ny):
        for x0 in range(nx):
            if not free[y0, x0] or labels[y0, x0] != 0:
                continue
            n += 1
            labels[y0, x0] = n
            top = 0
            stack[top] = y0 * nx + x0
            top += 1
            while top > 0:
                top -= 1
                k = stack[top]
                y = k // nx
                x = k - y * nx
                for d in range(4):
                    xx = x + (1 if d == 0 else (-1 if d == 1 else 0))
                    yy = y + (1 if d == 2 else (-1 if d == 3 else 0))
                    if 0 <= xx < nx and 0 <= yy < ny and free[yy, xx] and labels[yy, xx] == 0:
                        labels[yy, xx] = n
                        stack[top] = yy * nx + xx
                        top += 1
    return labels


def label_free_reference(free: np.ndarray) -> np.ndarray:
    """Plain reference of ``label_free`` (breadth-first, same numbering)."""
    ny, nx = free.shape
    labels = np.zeros((ny, nx), np.int32)
    n = 0
    for y0 in range(ny):
        for x0 in range(nx):
            if not free[y0, x0] or labels[y0, x0]:
                continue
            n += 1
            labels[y0, x0] = n
            todo = [(x0, y0)]
            while todo:
                x, y = todo.pop()
                for xx, yy in ((x + 1, y), (x - 1, y), (x, y + 1), (x, y - 1)):
                    if 0 <= xx < nx and 0 <= yy < ny and free[yy, xx] and not labels[yy, xx]:
                        labels[yy, xx] = n
                        todo.append((xx, yy))
    return labels


def is_occupied(grid: Costmap2D, x: float, y: float,
                threshold: int = INSCRIBED_INFLATED_OBSTACLE) -> bool:
    """Whether the cell of (x, y) costs ``threshold`` or more; False off the grid (the planner
    then says GOAL_OUTSIDE_MAP itself)."""
    cell = grid.world_to_map(x, y)
    return cell is not None and int(grid.costs[cell[1], cell[0]]) >= threshold


def free_candidates(grid: Costmap2D, goal: Pose2D, tolerance: float,
                    threshold: int = INSCRIBED_INFLATED_OBSTACLE,
                    seen_from: tuple[float, float] | None = None) -> list[tuple[float, float]]:
    """Per 4-connected piece of free cells in the tolerance square, the centre of its cell
    nearest to the goal; nearest pieces first (ties: row-major), those with a line of sight
    from ``seen_from`` (x, y) before the hidden ones when it is given. Empty when none."""
    if not tolerance > 0.0 or not (math.isfinite(goal.x) and math.isfinite(goal.y)):
        return []
    res = grid.resolution
    x0, y0 = grid.world_to_map_no_bounds(goal.x - tolerance, goal.y - tolerance)
    x1, y1 = grid.world_to_map_no_bounds(goal.x + tolerance, goal.y + tolerance)
    x0, y0 = max(x0, 0), max(y0, 0)
    x1, y1 = min(x1, grid.size_x - 1), min(y1, grid.size_y - 1)
    if x1 < x0 or y1 < y0:
        return []
    window = grid.costs[y0:y1 + 1, x0:x1 + 1]
    cx = grid.origin_x + (np.arange(x0, x1 + 1) + 0.5) * res
    cy = grid.origin_y + (np.arange(y0, y1 + 1) + 0.5) * res
    dx = np.abs(cx - goal.x)[None, :]
    dy = np.abs(cy - goal.y)[:, None]
    inside = (dx <= tolerance + 1e-9) & (dy <= tolerance + 1e-9)
    labels = label_free(np.ascontiguousarray((window < threshold) & inside))
    if not labels.any():
        return []
    d2 = np.where(labels > 0, dx * dx + dy * dy, np.inf)
    order = np.argsort(d2, axis=None, kind="stable")
    out, seen = [], set()
    for k in order:
        iy, ix = divmod(int(k), labels.shape[1])
        lab = int(labels[iy, ix])
        if lab == 0:
            break
        if lab not in seen:
            seen.add(lab)
            out.append((float(cx[ix]), float(cy[iy])))
    if seen_from is None or len(out) < 2:
        return out
    lethal = grid.costs == LETHAL_OBSTACLE
    hidden = [segment_blocked(lethal, grid.origin_x, grid.origin_y, grid.resolution,
                              seen_from[0], seen_from[1], x, y) for x, y in out]
    return [c for c, h in sorted(zip(out, hidden), key=lambda t: t[1])]   # stable


def needs_free_goal(planner: object) -> bool:
    """Whether ``planner`` plans onto the goal's cell (navfn, global_planner): carrot_planner
    already walks back from an occupied goal to the first acceptable pose itself."""
    from navcore.planners.global_planner import GlobalPlanner
    from navcore.planners.navfn import NavFn
    return isinstance(planner, (NavFn, GlobalPlanner))


@dataclass(frozen=True)
class FreeGoal:
    """``pose``: where to drive (the goal itself when its cell is free); ``substituted``: it is
    not the goal; ``plans``: reachability plans made; ``pose`` None: no reachable free cell."""

    pose: Pose2D | None
    substituted: bool
    plans: int


def nearest_reachable_free_goal(grid: Costmap2D, goal: Pose2D, tolerance: float,
                                reachable: Callable[[Pose2D], bool], max_plans: int = 8,
                                threshold: int = INSCRIBED_INFLATED_OBSTACLE,
                                seen_from: tuple[float, float] | None = None) -> FreeGoal:
    """The goal when its cell is free; else the nearest free cell within ``tolerance`` (square
    half-side, m) that ``reachable`` (a plan from the robot) accepts, those in sight of
    ``seen_from`` (the robot) first, keeping the goal's yaw, trying at most ``max_plans``
    pieces; ``pose`` None when there is none."""
    if not is_occupied(grid, goal.x, goal.y, threshold):
        return FreeGoal(goal, False, 0)
    plans = 0
    for x, y in free_candidates(grid, goal, tolerance, threshold, seen_from):
        if plans >= max_plans:
            break
        pose = Pose2D(x, y, goal.theta)
        plans += 1
        if reachable(pose):
            return FreeGoal(pose, True, plans)
    return FreeGoal(None, False, plans)
