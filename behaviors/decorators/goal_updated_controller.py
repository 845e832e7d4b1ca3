"""GoalUpdatedController (Nav2)."""

from __future__ import annotations

from behaviors.base import PortInformation
from behaviors.decorators.throttle import Throttle
from navcore.types import Pose2D


class GoalUpdatedController(Throttle):
    """Tick the child on the first tick of a run, while it is RUNNING, and whenever ``goal``
    changed; otherwise RUNNING without ticking it (Nav2 ``GoalUpdatedController``).

    Around ComputePathToPose this is move_base's ``planner_frequency: 0``: plan once, and again
    for a new goal.
    """

    INPUT_PORTS = {"goal": PortInformation(Pose2D, True, "the goal watched for changes")}
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    DEFAULT_KEYS = {"goal": "goal"}

    RESTART_WHEN_DUE = True  # a new goal restarts a child still planning for the old one

    def start_run(self) -> None:
        self._goal = self.read("goal")

    def due(self) -> bool:
        goal = self.read("goal")
        changed = goal is not self._goal and goal != self._goal  # (no dataclass == per tick)
        self._goal = goal
        return changed
