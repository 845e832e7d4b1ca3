"""InitialPoseReceived (Nav2 condition)."""

from __future__ import annotations

from behaviors.base import FAILURE, SUCCESS, PortInformation, Status
from behaviors.conditions.condition import Condition


class InitialPoseReceived(Condition):
    """SUCCESS when ``initial_pose_received`` (a blackboard entry, by default the mission's
    ``initial_pose_received``) is true; FAILURE when it is false or unset (Nav2
    ``InitialPoseReceived``: whoever sets the initial pose writes the entry)."""

    INPUT_PORTS = {"initial_pose_received": PortInformation(bool, False, "whether an initial "
                                                            "pose was given")}
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    DEFAULT_KEYS = {"initial_pose_received": "initial_pose_received"}

    def update(self) -> Status:
        return SUCCESS if self.read("initial_pose_received") else FAILURE
