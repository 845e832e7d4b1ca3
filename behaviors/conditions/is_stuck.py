"""IsStuck."""

from __future__ import annotations

from behaviors.base import INVALID, Port, PortInformation, Status
from behaviors.conditions.condition import Condition, yes
from navcore.controllers.progress import ProgressChecker


class IsStuck(Condition):
    """SUCCESS when the robot has not moved ``required_movement_radius`` metres within the last
    ``movement_time_allowance`` seconds (real progress checking, like Nav2's
    SimpleProgressChecker, rather than Nav2's deceleration-only ``IsStuck``)."""

    INPUT_PORTS = {
        "required_movement_radius": Port(float, False, "progress radius, m", 0.5, low=0.0),
        "movement_time_allowance": Port(float, False, "time to make progress, s", 10.0, low=0.0),
    }
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def update(self) -> Status:
        now, pose = self.clock.now(), self.pose()
        if self.status is INVALID:
            self._window = ProgressChecker()
            self._window.reset(pose, now)
        stuck = self._window.stalled(pose, now, self.get_input("required_movement_radius"),
                                     self.get_input("movement_time_allowance"))
        if stuck:
            self.say("no progress for {:.1f} s", now - self._window.since)
        return yes(stuck)
