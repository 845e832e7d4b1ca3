"""DistanceController (Nav2)."""

from __future__ import annotations

from typing import Any

from behaviors.base import (INVALID, RUNNING, SUCCESS, DecoratorNode, Port,
                            PortInformation, Ticking)


class UsesRobot(DecoratorNode):
    INPUT_PORTS: dict[str, PortInformation]
    OUTPUT_PORTS: dict[str, PortInformation]

    def setup(self, **kwargs: Any) -> None:
        self.clock = self.component(kwargs, "clock")
        self.robot = self.component(kwargs, "robot")


class DistanceController(UsesRobot):
    """Tick the child each time the robot has travelled ``distance`` metres (Nav2).

    Also on the first tick of a run and while the child is RUNNING; otherwise the child's last
    result. Distance is straight-line from where the child last succeeded.
    """

    INPUT_PORTS = {"distance": Port(float, False, "travel between ticks, m", 1.0, low=0.0)}
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def tick_children(self) -> Ticking:
        pose = self.robot.pose()
        if self.status is INVALID:
            self._last_status = INVALID
            self._anchor = pose
        far = pose.distance_to(self._anchor) >= self.get_input("distance")
        if self._last_status is INVALID or self.decorated.status is RUNNING or far:
            yield from self.decorated.tick()
            self._last_status = self.decorated.status
            if self._last_status is SUCCESS:
                self._anchor = pose
        return self._last_status
