"""SpeedController (Nav2)."""

from __future__ import annotations

import math

from behaviors.base import Port, PortInformation
from behaviors.decorators.distance_controller import UsesRobot
from behaviors.decorators.throttle import Throttle


class SpeedController(Throttle, UsesRobot):
    """Tick the child at a rate that grows with the robot's speed (Nav2 ``SpeedController``).

    Rate = min_rate + (max_rate - min_rate) * (v - min_speed) / (max_speed - min_speed), clamped;
    first tick of a run, RUNNING child, or period elapsed tick the child; otherwise RUNNING
    without ticking it (Nav2).
    """

    INPUT_PORTS = {
        "min_rate": Port(float, False, "rate at min_speed, Hz", 0.1, low=0.0),
        "max_rate": Port(float, False, "rate at max_speed, Hz", 1.0, low=0.0),
        "min_speed": Port(float, False, "speed giving min_rate, m/s", 0.0, low=0.0),
        "max_speed": Port(float, False, "speed giving max_rate, m/s", 0.5, low=0.0),
    }
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def rate(self, speed: float) -> float:
        lo, hi = self.get_input("min_speed"), self.get_input("max_speed")
        r0, r1 = self.get_input("min_rate"), self.get_input("max_rate")
        f = 0.0 if hi <= lo else min(1.0, max(0.0, (speed - lo) / (hi - lo)))
        return r0 + (r1 - r0) * f

    def start_run(self) -> None:
        self._last_ok = -math.inf

    def due(self) -> bool:
        self._now = self.clock.now()
        v = self.robot.velocity()
        rate = self.rate(math.hypot(v.vx, v.vy))
        return rate > 0.0 and self._now - self._last_ok >= 1.0 / rate - 1e-9

    def child_succeeded(self) -> None:
        self._last_ok = self._now
