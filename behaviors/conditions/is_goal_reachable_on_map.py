"""IsGoalReachableOnMap: the static map alone leaves a route to the goal."""

from __future__ import annotations

from typing import Any

from behaviors.base import FAILURE, SUCCESS, PortInformation, Status
from behaviors.conditions.condition import Condition
from navcore.planners.map_route import MapOnlyRoute
from navcore.planners.result import PlanReason
from navcore.types import Pose2D


class IsGoalReachableOnMap(Condition):
    """FAILURE when a plan from the robot to ``goal`` on the global costmap's static layers and
    inflation alone (what the sensors added left out) finds no path (NO_VALID_PATH), the goal
    inside a map obstacle beyond the planner's tolerance (GOAL_OCCUPIED) or off the map: no
    clearing or motion recovery can reach it, so a tree should give up with the planner's reason
    rather than recover. SUCCESS otherwise: also when the map-only plan fails for a reason a
    recovery can change (a start inside inflation), with a costmap without layers, and with a
    planner other than navfn or global_planner (carrot_planner's idea of reachable differs)."""

    INPUT_PORTS = {
        "goal": PortInformation(Pose2D, True, "goal pose in map"),
        "planner_id": PortInformation(str, False, "whose kind and parameters the map-only "
                                      "plan uses", "GridBased"),
    }
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    DEFAULT_KEYS = {"goal": "goal"}

    def setup(self, **kwargs: Any) -> None:
        super().setup(**kwargs)
        costmap = self.component(kwargs, "global_costmap")
        planners = kwargs.get("planners") or {}
        self.route = MapOnlyRoute(costmap, planners.get(self.get_input("planner_id")))

    def update(self) -> Status:
        goal = self.read("goal")
        if goal is None:
            self.say("no goal")
            return FAILURE
        if not self.route.available:
            self.say("the global costmap has no layers: cannot tell the map apart")
            return SUCCESS
        if not self.route.same_kind:
            self.say("not navfn or global_planner: cannot judge reachability")
            return SUCCESS
        result = self.route.plan(self.pose(), goal)
        if not result.ok and result.reason in (PlanReason.NO_PATH, PlanReason.GOAL_OCCUPIED,
                                               PlanReason.GOAL_OUTSIDE_MAP):
            self.say(f"no route on the map alone: {result.reason}")
            return FAILURE
        return SUCCESS
