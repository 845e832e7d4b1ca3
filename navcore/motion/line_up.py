"""Tight goals: how much room the robot has across a goal pose, and where to line up before
driving straight in (a pre-pose on the goal's heading line, outside the narrow part).

A goal at the end of a bay a few centimetres wider than the robot is reached reliably by lining
up in front of the bay and entering straight, as a driver parks: the local planner's samples
approach such a goal at whatever angle scores best and then cannot turn inside. The room is
measured on a costmap grid (lethal cells and the map's edge are walls; unknown cells are not),
the pre-pose checked with a costmap handle's footprint cost.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from navcore.costmap.clearance import clearances
from navcore.costmap.cost_values import INSCRIBED_INFLATED_OBSTACLE, LETHAL_OBSTACLE
from navcore.costmap.costmap2d import Costmap2D
from navcore.motion.collision import CLEARANCE_TOLERANCE
from navcore.types import Pose2D

# farthest a side wall is looked for, m (a wider space is "open", whatever its width)
MAX_SIDE_RANGE = 2.0


@dataclass(frozen=True)
class GoalRoom:
    """Room across a goal: ``width`` (m) free between the walls either side of the robot's body
    at the goal, narrowest over its length (capped at twice ``MAX_SIDE_RANGE``), and ``margin``
    (m) per side beyond the body: (width - body width) / 2."""

    width: float
    margin: float


def footprint_of(handle: Any) -> np.ndarray | None:
    """The footprint polygon (N, 2) a costmap handle checks poses with (padded as it pads
    it); None for a handle without one (a scripted costmap)."""
    fp = getattr(handle, "footprint", None)
    if not isinstance(fp, np.ndarray) or fp.ndim != 2 or fp.shape[1] != 2:
        return None
    return fp.astype(float)


def body_extent(footprint: np.ndarray) -> tuple[float, float, float]:
    """(rear, front, half_width) of a footprint polygon in the robot frame, m."""
    fp = np.asarray(footprint, dtype=float).reshape(-1, 2)
    return float(fp[:, 0].min()), float(fp[:, 0].max()), float(np.abs(fp[:, 1]).max())


def side_distances(costmap: Costmap2D, pose: Pose2D, stations: np.ndarray,
                   max_range: float = MAX_SIDE_RANGE) -> tuple[np.ndarray, np.ndarray]:
    """Distance (m) from each station (metres along ``pose``'s heading from it) to the first
    wall cell to the left and to the right, sampled every half cell (the face taken halfway
    between the last free sample and the first wall one); ``max_range`` where none. A station
    whose own cell is a wall has 0 both ways."""
    res = costmap.resolution
    steps = np.arange(0.0, max_range + 1e-9, 0.5 * res)
    c, s = math.cos(pose.theta), math.sin(pose.theta)
    sx = pose.x + stations * c                                   # (S,)
    sy = pose.y + stations * s
    out = []
    for side in (1.0, -1.0):                                     # left, right
        px = sx[:, None] - side * s * steps[None, :]             # (S, T)
        py = sy[:, None] + side * c * steps[None, :]
        mx = np.floor((px - costmap.origin_x) / res).astype(np.int64)
        my = np.floor((py - costmap.origin_y) / res).astype(np.int64)
        inside = (mx >= 0) & (my >= 0) & (mx < costmap.size_x) & (my < costmap.size_y)
        wall = ~inside
        wall[inside] = costmap.costs[my[inside], mx[inside]] >= LETHAL_OBSTACLE
        wall[inside] &= costmap.costs[my[inside], mx[inside]] != 255   # unknown is no wall
        first = np.where(wall.any(axis=1), wall.argmax(axis=1), -1)
        # the wall's face lies between the last free sample and the first wall one
        face = np.maximum(steps[np.maximum(first, 0)] - 0.25 * res, 0.0)
        out.append(np.where(first >= 0, face, max_range))
    return out[0], out[1]


def goal_room(costmap: Costmap2D, goal: Pose2D, footprint: np.ndarray,
              max_range: float = MAX_SIDE_RANGE) -> GoalRoom:
    """The room across ``goal`` for a robot of ``footprint``: left plus right distance to the
    walls at stations every cell along its body, the narrowest of them."""
    rear, front, half = body_extent(footprint)
    stations = np.arange(rear, front + 1e-9, costmap.resolution)
    left, right = side_distances(costmap, goal, stations, max_range)
    width = float(np.min(left + right))
    return GoalRoom(width, 0.5 * width - half)


def entry_depth(costmap: Costmap2D, goal: Pose2D, footprint: np.ndarray, open_width: float,
                max_depth: float) -> float | None:
    """How far back from ``goal`` along its heading the robot's centre must be for its whole
    body to stand where the space is at least ``open_width`` wide (stepping a cell at a time):
    the depth of the narrow part. None if it is narrower all the way to ``max_depth``."""
    res = costmap.resolution
    for d in np.arange(0.0, max_depth + 1e-9, res):
        at = goal.compose(Pose2D(-float(d), 0.0, 0.0))
        if goal_room(costmap, at, footprint).width >= open_width:
            return float(d)
    return None


def segment_poses(a: Pose2D, b: Pose2D, step: float) -> np.ndarray:
    """(N, 3) poses every ``step`` m from ``a`` to ``b`` (both included), all at ``b``'s
    heading: what a straight entry sweeps."""
    d = a.distance_to(b)
    n = max(1, int(math.ceil(d / step)))
    t = np.linspace(0.0, 1.0, n + 1)
    return np.column_stack([a.x + t * (b.x - a.x), a.y + t * (b.y - a.y),
                            np.full(n + 1, b.theta)])


def footprint_costs_of(handle: Any, poses: np.ndarray) -> np.ndarray:
    """Footprint cost of each (x, y, theta) row on ``handle``: its batch kernel when it has
    one, else pose by pose."""
    batch = getattr(handle, "footprint_costs", None)
    if batch is not None:
        return np.asarray(batch(poses), dtype=np.int64)
    return np.array([int(handle.footprint_cost(*p)) for p in poses], dtype=np.int64)


def entry_blocked(handle: Any, poses: np.ndarray) -> int | None:
    """Index of the first of ``poses`` (N, 3) a straight entry may not pass: off the map, or
    the robot's body (the footprint without padding) overlapping a lethal cell, judged
    geometrically where the grid's footprint cost is lethal. Inscribed cost is what a narrow
    space is made of and does not block. None when every pose is passable."""
    costs = footprint_costs_of(handle, poses)
    bad = np.nonzero((costs < 0) | (costs == LETHAL_OBSTACLE))[0]
    if bad.size == 0:
        return None
    if costs[bad[0]] < 0:
        return int(bad[0])
    gaps = clearances(handle, [Pose2D(*poses[i]) for i in bad])
    for k, i in enumerate(bad):
        if costs[i] < 0 or gaps is None or gaps[k] < -CLEARANCE_TOLERANCE:
            return int(i)
    return None


def pre_pose(handle: Any, goal: Pose2D, footprint: np.ndarray, distance: float,
             narrow_margin: float, max_extra: float = 1.0) -> Pose2D | None:
    """Where to line up for a straight entry to ``goal``: on its heading line, facing it, at
    least ``distance`` m back and far enough that the robot turning on the spot there stays
    out of the narrow part (where the margin per side is below ``narrow_margin``); the first
    such pose, a cell at a time up to ``max_extra`` m farther, whose footprint is free (below
    the inscribed cost) and from which the straight line to the goal is passable
    (``entry_blocked``). None when there is none."""
    cm = handle.costmap
    rear, front, half = body_extent(footprint)
    circumscribed = float(np.max(np.hypot(footprint[:, 0], footprint[:, 1])))
    depth = entry_depth(cm, goal, footprint, 2.0 * (half + narrow_margin),
                        distance + max_extra)
    if depth is None:
        return None
    start = max(distance, depth + max(0.0, circumscribed - front))
    for d in np.arange(start, start + max_extra + 1e-9, cm.resolution):
        p = goal.compose(Pose2D(-float(d), 0.0, 0.0))
        cost = int(handle.footprint_cost(p.x, p.y, p.theta))
        if not 0 <= cost < INSCRIBED_INFLATED_OBSTACLE:
            continue
        if entry_blocked(handle, segment_poses(p, goal, 0.5 * cm.resolution)) is None:
            return p
    return None


def line_offsets(goal: Pose2D, pose: Pose2D) -> tuple[float, float, float]:
    """Where ``pose`` stands relative to the straight entry into ``goal``: (distance still to
    go along the goal's heading, lateral offset from the line (left positive), heading error
    (rad, pose minus goal))."""
    rel = pose.relative_to(goal)
    return -rel.x, rel.y, math.remainder(pose.theta - goal.theta, 2.0 * math.pi)
