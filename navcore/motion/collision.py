"""Is a motion free? The robot footprint checked on a costmap along the poses of a motion.

``handle`` is a costmap handle (``footprint_cost(x, y, theta) -> int``, -1 off the map; with a
``costmap`` grid and a ``footprint`` polygon, tight spots are judged geometrically too).
"""

from __future__ import annotations

from typing import Any, Iterable

from navcore.costmap.clearance import clearances
from navcore.costmap.cost_values import INSCRIBED_INFLATED_OBSTACLE, LETHAL_OBSTACLE, NO_INFORMATION
from navcore.types import Pose2D

# metres a tight-spot motion may close in on a lethal cell beyond the start (numerical slack)
CLEARANCE_TOLERANCE = 0.002


def is_collision(cost: int, start_cost: int = 0) -> bool:
    """A footprint cost that forbids the pose: off the map (-1), touching a lethal cell, or
    entering inscribed cost from a pose that was not already there. (A robot already in a
    tight spot may move through inscribed cells to get out; unknown cells do not block.)"""
    if cost < 0 or cost == LETHAL_OBSTACLE:
        return True
    return cost == INSCRIBED_INFLATED_OBSTACLE and start_cost < INSCRIBED_INFLATED_OBSTACLE


def first_collision(handle: Any, poses: Iterable[Pose2D], start: Pose2D | None = None
                    ) -> tuple[Pose2D, int] | None:
    """First pose whose footprint is in collision on ``handle`` (see ``is_collision``;
    ``start`` is where the robot is now), with its cost; None if all are clear.

    From a tight spot (the footprint already in inscribed or lethal cost) the grid's
    conservative rasterisation cannot tell a near miss from contact, so a lethal cost is then
    judged geometrically: the footprint polygon may not overlap a lethal cell (as the square it
    is) more than it already does at ``start``."""
    start_cost = 0 if start is None else int(handle.footprint_cost(start.x, start.y,
                                                                    start.theta))
    if start_cost == NO_INFORMATION:
        start_cost = 0
    poses = list(poses)
    tight = start is not None and start_cost >= INSCRIBED_INFLATED_OBSTACLE
    gaps: Any = None
    for i, p in enumerate(poses):
        cost = int(handle.footprint_cost(p.x, p.y, p.theta))
        if not is_collision(cost, start_cost):
            continue
        if tight and cost == LETHAL_OBSTACLE:
            if gaps is None:
                gaps = clearances(handle, [start] + poses)
            if gaps is not None and gaps[i + 1] >= min(0.0, gaps[0]) - CLEARANCE_TOLERANCE:
                continue
        return p, cost
    return None
