"""GoalUpdated (Nav2)."""

from __future__ import annotations

from behaviors.base import FAILURE, INVALID, PortInformation, Status
from behaviors.conditions.condition import Condition, yes
from navcore.types import Pose2D


class GoalUpdated(Condition):
    """SUCCESS on the tick in which ``goal`` differs from the goal seen on the previous tick.

    The first tick of a run only remembers the goal (FAILURE). (Nav2 ``GoalUpdated``.)
    """

    INPUT_PORTS = {"goal": PortInformation(Pose2D, True, "goal pose in map")}
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    DEFAULT_KEYS = {"goal": "goal"}

    def update(self) -> Status:
        goal = self.read("goal")
        if self.status is INVALID:
            self._seen = goal
            return FAILURE
        changed = goal != self._seen
        self._seen = goal
        if changed:
            self.say("goal changed")
        return yes(changed)
