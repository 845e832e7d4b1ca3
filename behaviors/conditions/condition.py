"""The base of the condition nodes."""

from __future__ import annotations

from typing import Any

from behaviors.base import FAILURE, SUCCESS, Leaf, PortInformation, Status
from navcore.types import Pose2D


def yes(flag: bool) -> Status:
    return SUCCESS if flag else FAILURE


class Condition(Leaf):
    """Base: a condition with access to the clock and the robot."""

    CATEGORY = "Condition"
    INPUT_PORTS: dict[str, PortInformation]
    OUTPUT_PORTS: dict[str, PortInformation]

    def setup(self, **kwargs: Any) -> None:
        self.clock = self.component(kwargs, "clock")
        self.robot = self.component(kwargs, "robot", optional=True)
        self.control_period = float(kwargs.get("control_period") or 0.05)

    def pose(self) -> Pose2D:
        if self.robot is None:
            raise RuntimeError(f"{type(self).__name__} '{self.name}': setup() got no 'robot'")
        return self.robot.pose()
