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


class ProgressWindow:
    """Has the robot moved ``radius`` metres within the last ``window`` seconds?"""

    def __init__(self) -> None:
        self.anchor: Pose2D | None = None
        self.since = 0.0

    def reset(self, pose: Pose2D, now: float) -> None:
        self.anchor, self.since = pose, now

    def stalled(self, pose: Pose2D, now: float, radius: float, window: float) -> bool:
        if self.anchor is None or pose.distance_to(self.anchor) >= radius:
            self.reset(pose, now)
            return False
        return now - self.since > window
