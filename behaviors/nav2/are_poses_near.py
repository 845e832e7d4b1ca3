"""ArePosesNear (Nav2 condition)."""

from __future__ import annotations

from behaviors.base import FAILURE, SUCCESS, PortInformation, Status
from behaviors.conditions.condition import Condition
from navcore.types import Pose2D


class ArePosesNear(Condition):
    """SUCCESS when ``ref_pose`` and ``target_pose`` are within ``tolerance`` m (positions
    only; Nav2 ``ArePosesNear``)."""

    INPUT_PORTS = {
        "ref_pose": PortInformation(Pose2D, True, "first pose"),
        "target_pose": PortInformation(Pose2D, True, "second pose"),
        "global_frame": PortInformation(str, False, "Nav2's frame to compare in; map here",
                                        "map"),
        "tolerance": PortInformation(float, False, "distance, m", 0.5),
    }
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def update(self) -> Status:
        a, b = self.read("ref_pose"), self.read("target_pose")
        if a is None or b is None:
            self.say("a pose is missing")
            return FAILURE
        tol = self.get_input("tolerance")
        dx, dy = a.x - b.x, a.y - b.y
        return SUCCESS if dx * dx + dy * dy <= tol * tol else FAILURE
