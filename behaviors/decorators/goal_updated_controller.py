"""GoalUpdatedController (Nav2)."""

from __future__ import annotations

from behaviors.base import INVALID, RUNNING, DecoratorNode, PortInformation, Ticking
from navcore.types import Pose2D


class GoalUpdatedController(DecoratorNode):
    """Tick the child on the first tick of a run, while it is RUNNING, and whenever ``goal``
    changed; otherwise return the child's last result (Nav2 ``GoalUpdatedController``).

    Around ComputePathToPose this is move_base's ``planner_frequency: 0``: plan once, and again
    for a new goal.
    """

    INPUT_PORTS = {"goal": PortInformation(Pose2D, True, "the goal watched for changes")}
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    DEFAULT_KEYS = {"goal": "goal"}

    def tick_children(self) -> Ticking:
        goal = self.read("goal")
        if self.status is INVALID:
            self._last_status, self._goal = INVALID, goal
        changed = goal != self._goal
        self._goal = goal
        if self._last_status is INVALID or self.decorated.status is RUNNING or changed:
            if changed and self.decorated.status is RUNNING:
                self.halt_child()  # restart the child for the new goal
            yield from self.decorated.tick()
            self._last_status = self.decorated.status
        return self._last_status
