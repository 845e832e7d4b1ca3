"""The straightest way out of inflated space: of straight motions forwards and backwards and
short arcs either way, the one that brings the footprint below the inscribed cost in the least
travel, checked with the footprint cost kernel and, along the way, with the tight-spot
collision rule (``navcore.motion.collision``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from navcore.costmap.clearance import clearances
from navcore.costmap.cost_values import INSCRIBED_INFLATED_OBSTACLE
from navcore.motion.collision import CLEARANCE_TOLERANCE, first_collision
from navcore.motion.line_up import footprint_costs_of
from navcore.types import Pose2D

# m: the body may come this near a lethal cell on the way out, if it started farther
ESCAPE_MARGIN = 0.05
# curvatures (1/m) of the arcs tried after the straight motions: radii 2, 1 and 0.5 m
ARC_CURVATURES = (0.5, 1.0, 2.0)


@dataclass(frozen=True)
class EscapeMotion:
    """A constant-curvature motion: ``direction`` +1 forwards / -1 backwards, ``curvature``
    (1/m, left positive, w = v * curvature), ``distance`` (m of travel until the footprint is
    free) and the pose reached there."""

    direction: float
    curvature: float
    distance: float
    end: Pose2D


def motion_poses(pose: Pose2D, direction: float, curvature: float, step: float,
                 n: int) -> np.ndarray:
    """(n, 3) poses every ``step`` m of travel along the motion from ``pose`` (not included)."""
    s = direction * step * np.arange(1, n + 1)
    if abs(curvature) < 1e-12:
        lx, ly, a = s, np.zeros(n), np.zeros(n)
    else:
        a = curvature * s
        lx, ly = np.sin(a) / curvature, (1.0 - np.cos(a)) / curvature
    c, si = math.cos(pose.theta), math.sin(pose.theta)
    th = np.remainder(pose.theta + a + math.pi, 2.0 * math.pi) - math.pi
    return np.column_stack([pose.x + c * lx - si * ly, pose.y + si * lx + c * ly, th])


def start_gap(handle: Any, pose: Pose2D) -> float | None:
    """The body's clearance (m) from the lethal cells at ``pose`` (negative: overlap on the
    grid); None without a footprint polygon and grid (a scripted costmap)."""
    gaps = clearances(handle, [pose])
    return None if gaps is None else float(gaps[0])


def nearer_than(handle: Any, poses: list[Pose2D], gap: float | None) -> int | None:
    """Index of the first of ``poses`` where the body comes nearer a lethal cell than ``gap``
    (its clearance where the motion began) or ``ESCAPE_MARGIN``, whichever is less: a turning
    body's corner sweeps towards the wall it leaves, and a costmap mark inside the real gap
    makes that gap look smaller than it is, so an escape never closes in. None if none does,
    or without geometry."""
    if gap is None or not poses:
        return None
    gaps = clearances(handle, poses)
    if gaps is None:
        return None
    low = np.nonzero(gaps < min(gap, ESCAPE_MARGIN) - CLEARANCE_TOLERANCE)[0]
    return int(low[0]) if low.size else None


def straightest_escape(handle: Any, pose: Pose2D, max_distance: float, step: float = 0.02,
                       curvatures: tuple[float, ...] = ARC_CURVATURES) -> EscapeMotion | None:
    """The motion that frees the footprint (cost below inscribed) in the least travel, at most
    ``max_distance`` m: straight forwards or backwards first, then arcs of growing curvature
    either way; among equally short ones (to a ``step``) the straighter wins. A motion counts
    only if ``first_collision`` passes every pose up to the free one and the body never comes
    nearer a lethal cell than at the start (``nearer_than``). None when none frees it."""
    n = max(1, int(math.ceil(max_distance / step)))
    kinds = [(d, 0.0) for d in (1.0, -1.0)]
    kinds += [(d, side * k) for k in curvatures for d in (1.0, -1.0) for side in (1.0, -1.0)]
    found = []
    for rank, (direction, curvature) in enumerate(kinds):
        poses = motion_poses(pose, direction, curvature, step, n)
        costs = footprint_costs_of(handle, poses)
        free = np.nonzero((costs >= 0) & (costs < INSCRIBED_INFLATED_OBSTACLE))[0]
        if free.size:
            found.append((int(free[0]), rank, direction, curvature, poses[:free[0] + 1]))
    found.sort(key=lambda t: t[:2])
    gap = start_gap(handle, pose)
    for i, _, direction, curvature, poses in found:
        way = [Pose2D(*p) for p in poses]
        if first_collision(handle, way, pose) is None and nearer_than(handle, way, gap) is None:
            return EscapeMotion(direction, curvature, (i + 1) * step, way[-1])
    return None
