"""carrot_planner: the goal if the robot fits there, else the nearest pose back toward the robot
on the straight robot-goal line where it does. No search: the plan is [start, target].

Parameters ``step_size`` (default: the costmap resolution) and ``min_dist_from_robot`` are used as
their names say (the C++ reads them and walks in 1 % steps of the whole line instead): the walk
moves ``step_size`` metres at a time from the goal toward the robot and gives up once the candidate
is closer than ``min_dist_from_robot`` to the robot. Heading is interpolated from the goal's to the
robot's along the way, as in the C++. A pose is acceptable when its footprint cost is on the map
and neither lethal nor unknown (below 254; CostmapModel's test).
"""

from __future__ import annotations

import math
from typing import Callable

import numpy as np

from navcore.costmap.costmap2d import Costmap2D
from navcore.costmap.cost_values import LETHAL_OBSTACLE
from navcore.params import Param, Parameters
from navcore.planners.common import finite_pose
from navcore.planners.result import PlanReason, PlanResult
from navcore.types import Path, Pose2D, angle_diff, normalize_angle

FootprintCost = Callable[[float, float, float], int]


def costmap_footprint_cost(costmap: Costmap2D, footprint: np.ndarray) -> FootprintCost:
    """``footprint_cost(x, y, theta)`` over ``costmap`` as it is at call time (the costmap's
    ``navcore.costmap.footprint.footprint_cost``; -1 off the map)."""
    from navcore.costmap.footprint import footprint_cost

    fp = np.ascontiguousarray(footprint, dtype=np.float64)

    def cost(x: float, y: float, theta: float) -> int:
        return int(footprint_cost(costmap.costs, costmap.origin_x, costmap.origin_y,
                                  costmap.resolution, fp, float(x), float(y), float(theta)))

    return cost


# step_size defaults to the costmap's resolution (replaced per instance); the table is what a
# robot config's CarrotPlanner namespace is checked against at load time.
CARROT_PLANNER_PARAMS = (
    Param("step_size", 0.05, float, "m between candidate poses walking back from the goal "
          "(default: the costmap resolution)", min=1e-3, max=10.0),
    Param("min_dist_from_robot", 0.10, float,
          "m: give up once the candidate is this close to the robot", min=0.0, max=100.0),
)


class CarrotPlanner:
    """Straight-line planner; ``footprint_cost(x, y, theta)`` gives the max cost under the
    footprint at that pose (-1 off the map). ``make_plan`` gives a path or
    the reason there is none (an exception is a bug)."""

    def __init__(self, costmap: Costmap2D, footprint_cost: FootprintCost,
                 params: dict | None = None) -> None:
        if not callable(footprint_cost):
            raise TypeError("CarrotPlanner: footprint_cost must be callable (x, y, theta) -> int")
        self.costmap = costmap
        self.footprint_cost = footprint_cost
        step = CARROT_PLANNER_PARAMS[0]
        specs = (Param(step.name, float(costmap.resolution), float, step.doc, step.min, step.max),
                 *CARROT_PLANNER_PARAMS[1:])
        self.params = Parameters(specs, params, where="CarrotPlanner")

    def acceptable(self, x: float, y: float, theta: float) -> bool:
        c = int(self.footprint_cost(x, y, theta))
        return 0 <= c < LETHAL_OBSTACLE

    def make_plan(self, start: Pose2D, goal: Pose2D) -> PlanResult:
        """[start, goal or the closest acceptable pose before it], or the reason there is none."""
        return self._make_plan(start, goal)

    def _make_plan(self, start: Pose2D, goal: Pose2D) -> PlanResult:
        if not (finite_pose(start) and finite_pose(goal)):
            return PlanResult.failure(PlanReason.INVALID_POSE)
        cm = self.costmap
        if cm.world_to_map(start.x, start.y) is None:
            return PlanResult.failure(PlanReason.START_OUTSIDE_MAP)
        if cm.world_to_map(goal.x, goal.y) is None:
            return PlanResult.failure(PlanReason.GOAL_OUTSIDE_MAP)
        dist = start.distance_to(goal)
        dyaw = angle_diff(goal.theta, start.theta)
        step = self.params.step_size
        min_d = self.params.min_dist_from_robot
        k = 0
        while True:
            back = k * step
            remaining = dist - back
            if remaining < min_d or remaining < 0.0:
                break
            s = remaining / dist if dist > 0.0 else 1.0
            x = start.x + s * (goal.x - start.x)
            y = start.y + s * (goal.y - start.y)
            th = normalize_angle(start.theta + s * dyaw)
            if self.acceptable(x, y, th):
                poses = np.array([[start.x, start.y, start.theta], [x, y, th]])
                return PlanResult(True, Path(poses), PlanReason.NONE)
            k += 1
            if not math.isfinite(back):
                break
        return PlanResult.failure(PlanReason.GOAL_OCCUPIED)
