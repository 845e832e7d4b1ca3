"""IsOscillating (move_base's oscillation check)."""

from __future__ import annotations

import math
from typing import Any

from behaviors.base import FAILURE, Port, PortInformation, Status
from behaviors.conditions.condition import Condition, yes
from navcore.controllers.progress import ProgressChecker
from navcore.types import Pose2D


class IsOscillating(Condition):
    """move_base's oscillation check: SUCCESS when the robot has not moved
    ``oscillation_distance`` metres within ``oscillation_timeout`` seconds (0 = never).

    The timer restarts when the goal changes, and, like move_base after a recovery, when the
    node was not ticked for more than two control periods or it reported oscillation at its
    previous tick (the recovery that followed may have taken no time at all).
    """

    INPUT_PORTS = {
        "oscillation_timeout": Port(float, False, "s; 0 disables the check", 0.0, low=0.0),
        "oscillation_distance": Port(float, False, "m the robot must move", 0.5, low=0.0),
        "goal": PortInformation(Pose2D, False, "the timer restarts when this changes"),
    }
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    DEFAULT_KEYS = {"goal": "goal"}

    def setup(self, **kwargs: Any) -> None:
        super().setup(**kwargs)
        self._window = ProgressChecker()
        self._last_tick = -math.inf
        self._goal: Pose2D | None = None
        self._fired = False

    def update(self) -> Status:
        now, pose, goal = self.clock.now(), self.pose(), self.read("goal")
        new_goal = goal is not self._goal and goal != self._goal  # (same object: no dataclass ==)
        if new_goal or now - self._last_tick > 2.0 * self.control_period or self._fired:
            self._window.reset(pose, now)
            self._goal = goal
            self._fired = False
        self._last_tick = now
        timeout = self.get_input("oscillation_timeout")
        if timeout <= 0.0:
            return FAILURE
        osc = self._window.stalled(pose, now, self.get_input("oscillation_distance"), timeout)
        self._fired = osc
        if osc:
            self.say(f"oscillating: moved < {self.get_input('oscillation_distance')} m "
                     f"in {timeout} s")
        return yes(osc)
