"""GetCurrentPose (Nav2 action)."""

from __future__ import annotations

from typing import Any

from behaviors.base import SUCCESS, Leaf, PortInformation, Status
from navcore.types import Pose2D


class GetCurrentPose(Leaf):
    """Write the robot's pose in map to ``current_pose``; SUCCESS (Nav2 ``GetCurrentPose``;
    the frames are the executive's)."""

    INPUT_PORTS = {
        "global_frame": PortInformation(str, False, "Nav2's global frame; map here", "map"),
        "robot_base_frame": PortInformation(str, False, "Nav2's robot frame; unused",
                                            "base_link"),
    }
    OUTPUT_PORTS = {"current_pose": PortInformation(Pose2D, True, "robot pose in map")}

    def setup(self, **kwargs: Any) -> None:
        self.robot = self.component(kwargs, "robot")

    def update(self) -> Status:
        self.write("current_pose", self.robot.pose())
        return SUCCESS
