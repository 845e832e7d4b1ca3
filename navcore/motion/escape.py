"""The way out of a tight spot (TemporaryGoal): which free poses near the robot to try, and the
best pose one collision-free circular arc away.

``handle`` scores candidates (``footprint_cost``, and a grid with a footprint polygon for the
clearance of an arc); ``collision`` is the costmap motions are checked on (None: unchecked).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from navcore.costmap.clearance import clearances
from navcore.costmap.cost_values import INSCRIBED_INFLATED_OBSTACLE
from navcore.motion.collision import first_collision
from navcore.motion.geometry import arc_poses, heading_to
from navcore.types import Pose2D, angle_diff

# spacing of the footprint checks along a candidate arc while searching, m
ARC_SEARCH_STEP = 0.03
# clear arcs compared for clearance, and the clearance (m) beyond which any arc will do
ARC_CHOICES = 8
ARC_GAP_ENOUGH = 0.1


def rank_candidates(handle: Any, pose: Pose2D, candidates: list[Pose2D]) -> list[Pose2D]:
    """The candidates whose footprint cost is below the inscribed cost, most open and least
    turning first (cost/253 + turn/90 degrees, where a pose straight ahead or behind needs no
    turn), then nearest; all of them, unranked by cost, without a ``handle``."""
    scored = []
    for c in candidates:
        cost = int(handle.footprint_cost(c.x, c.y, c.theta)) if handle is not None else 0
        if 0 <= cost < INSCRIBED_INFLATED_OBSTACLE:
            # A differential drive reaches poses ahead or behind with gentle arcs, while a
            # pose abeam needs a sharp turn that sweeps a corner into whatever is beside it.
            bearing = abs(angle_diff(heading_to(pose, c), pose.theta))
            turn = min(bearing, math.pi - bearing)
            score = cost / INSCRIBED_INFLATED_OBSTACLE + turn / (0.5 * math.pi)
            scored.append((round(score, 2), c.distance_to(pose), c))
    scored.sort(key=lambda t: t[:2])
    return [t[2] for t in scored]


def arc_goal(handle: Any, collision: Any, pose: Pose2D, candidates: list[Pose2D],
             goal: Pose2D | None, check_collisions: bool = True, observed: Any = None,
             since: float = -math.inf, allow_unknown: bool = False) -> Pose2D | None:
    """The best pose one arc away (forwards or backwards, turning at most 90 degrees) toward
    one of ``candidates``, whose footprint is free at the arc's end and clear all along it
    (and, given an ``observed`` space memory, all along it on space observed free since
    ``since``, or with ``allow_unknown`` on space not last seen occupied); None if there is
    none. Ranked by openness at the end (in tenths of the inscribed cost),
    then by the distance left to ``goal`` (tenths of a metre; when one is known), then arc
    length; of the first few clear arcs, the one that keeps farthest from lethal cells."""
    ends = []
    for c in candidates:
        last = arc_poses(pose, c.x, c.y, ARC_SEARCH_STEP, end_only=True)
        if last is None:
            continue
        end = last[0]
        cost = int(handle.footprint_cost(end.x, end.y, end.theta)) if handle else 0
        if 0 <= cost < INSCRIBED_INFLATED_OBSTACLE:
            half = 0.5 * abs(angle_diff(end.theta, pose.theta))   # arc from its chord
            length = pose.distance_to(end) * (half / math.sin(half) if half > 1e-9 else 1.0)
            to_goal = round(end.distance_to(goal), 1) if isinstance(goal, Pose2D) else 0.0
            ends.append((round(cost / INSCRIBED_INFLATED_OBSTACLE, 1), to_goal,
                         round(length, 3), end, c))
    ends.sort(key=lambda t: t[:3])
    if not check_collisions:
        return ends[0][3] if ends else None
    # Of the first few clear arcs, take the one that keeps farthest from lethal cells
    # (the gentlest way out of a tight spot).
    best, best_gap, clear = None, -math.inf, 0
    for _, _, _, end, c in ends:
        arc = arc_poses(pose, c.x, c.y, ARC_SEARCH_STEP) or []
        if collision is not None and first_collision(collision, arc, pose) is not None:
            continue
        if observed is not None and observed.first_unobserved(arc, pose, since,
                                                              allow_unknown) is not None:
            continue
        gaps = clearances(handle, arc) if handle is not None else None
        gap = min(float(np.min(gaps)), ARC_GAP_ENOUGH) if gaps is not None else 0.0
        if gap > best_gap + 1e-3:
            best, best_gap = end, gap
        clear += 1
        if clear >= ARC_CHOICES or best_gap >= ARC_GAP_ENOUGH:
            break
    return best
