"""DistanceController (Nav2)."""

from __future__ import annotations

from typing import Any

from behaviors.base import DecoratorNode, Port, PortInformation
from behaviors.decorators.throttle import Throttle


class UsesRobot(DecoratorNode):
    INPUT_PORTS: dict[str, PortInformation]
    OUTPUT_PORTS: dict[str, PortInformation]

    def setup(self, **kwargs: Any) -> None:
        self.clock = self.component(kwargs, "clock")
        self.robot = self.component(kwargs, "robot")


class DistanceController(Throttle, UsesRobot):
    """Tick the child each time the robot has travelled ``distance`` metres (Nav2).

    Also on the first tick of a run and while the child is RUNNING; otherwise RUNNING without
    ticking it (Nav2). Distance is straight-line from where the child last succeeded.
    """

    INPUT_PORTS = {"distance": Port(float, False, "travel between ticks, m", 1.0, low=0.0)}
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def start_run(self) -> None:
        self._anchor = self.robot.pose()

    def due(self) -> bool:
        self._pose = self.robot.pose()
        return self._pose.distance_to(self._anchor) >= self.get_input("distance")

    def child_succeeded(self) -> None:
        self._anchor = self._pose
