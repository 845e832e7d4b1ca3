"""RecordPoseHistory: the trail BackOffToPreviousPose drives back on."""

from __future__ import annotations

from typing import Any

from behaviors.base import SUCCESS, Leaf, Port, PortInformation, Status
from navcore.types import Pose2D


class RecordPoseHistory(Leaf):
    """Append the robot pose to ``pose_history`` whenever it moved ``spacing`` metres; keep the
    last ``max_length`` metres of trail. Always SUCCESS; put it first in the navigation
    pipeline so the trail grows while the robot drives. The history survives recoveries."""

    INPUT_PORTS = {
        "spacing": Port(float, False, "distance between stored poses, m", 0.05, low=0.001),
        "max_length": Port(float, False, "trail length kept, m", 5.0, low=0.0, high=1000.0),
    }
    OUTPUT_PORTS = {"pose_history": PortInformation(list, True, "Pose2D, oldest first")}
    DEFAULT_KEYS = {"pose_history": "pose_history"}

    def setup(self, **kwargs: Any) -> None:
        self.robot = self.component(kwargs, "robot")
        self._trail: list[Pose2D] = []
        self._length = 0.0

    def update(self) -> Status:
        pose = self.robot.pose()
        trail = self._trail
        if trail:
            step = pose.distance_to(trail[-1])
            if step < self.get_input("spacing"):
                return SUCCESS
            self._length += step
        trail.append(pose)
        max_length = self.get_input("max_length")
        while len(trail) > 2:
            first = trail[0].distance_to(trail[1])
            if not self._length - first >= max_length:  # (NaN-safe as the loop condition was)
                break
            self._length -= first
            trail.pop(0)
        self.write("pose_history", list(self._trail))
        return SUCCESS
