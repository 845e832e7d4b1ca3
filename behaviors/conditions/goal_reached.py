"""GoalReached."""

from __future__ import annotations

from behaviors.base import FAILURE, Port, PortInformation, Status
from behaviors.conditions.condition import Condition, yes
from navcore.types import Pose2D


class GoalReached(Condition):
    """SUCCESS when the robot is within ``goal_reached_tol`` metres of ``goal``."""

    INPUT_PORTS = {
        "goal": PortInformation(Pose2D, True, "goal pose in map"),
        "goal_reached_tol": Port(float, False, "distance tolerance, m", 0.25, low=0.0),
    }
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    DEFAULT_KEYS = {"goal": "goal"}

    def update(self) -> Status:
        goal = self.read("goal")
        if goal is None:
            self.say("no goal")
            return FAILURE
        d = self.pose().distance_to(goal)
        self.say("{:.2f} m from the goal", d)
        return yes(d <= self.get_input("goal_reached_tol"))
