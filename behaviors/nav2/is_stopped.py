"""IsStopped (Nav2 Kilted condition)."""

from __future__ import annotations

from behaviors.base import FAILURE, RUNNING, SUCCESS, Port, PortInformation, Status
from behaviors.conditions.condition import Condition


class IsStopped(Condition):
    """SUCCESS once every velocity component (vx, vy, wz) has stayed below ``velocity_threshold``
    for ``duration_stopped`` milliseconds (Nav2's unit); RUNNING while it is below but not yet
    for that long; FAILURE when the robot moves (the count restarts). (Nav2 Kilted
    ``IsStopped``; unlike most conditions it can be RUNNING.)"""

    INPUT_PORTS = {
        "velocity_threshold": Port(float, False, "speed below which the robot is stopped, "
                                   "m/s and rad/s", 0.01, low=0.0),
        "duration_stopped": Port(int, False, "time it must stay stopped, ms", 1000, low=0),
    }
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def __init__(self, *args, **kwargs) -> None:  # noqa: D107
        super().__init__(*args, **kwargs)
        self._since: float | None = None

    def update(self) -> Status:
        v = self.robot.velocity()
        limit = self.get_input("velocity_threshold")
        now = self.clock.now()
        if abs(v.vx) < limit and abs(v.vy) < limit and abs(v.wz) < limit:
            if self._since is None:
                self._since = now
            if now - self._since > self.get_input("duration_stopped") / 1000.0:
                self._since = None
                return SUCCESS
            self.say("stopped for {:.2f} s", now - self._since)
            return RUNNING
        self._since = None
        return FAILURE
