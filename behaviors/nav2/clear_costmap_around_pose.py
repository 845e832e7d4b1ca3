"""ClearCostmapAroundPose (Nav2 Jazzy+ action)."""

from __future__ import annotations

from typing import Any

from behaviors.actions.clear_costmap import ClearCostmap
from behaviors.base import FAILURE, Port, PortInformation, Status
from navcore.types import Pose2D


class ClearCostmapAroundPose(ClearCostmap):
    """Reset clearable layers inside a square of side ``reset_distance`` metres centred on
    ``pose`` (Nav2 ``ClearCostmapAroundPose``). SUCCESS in one tick; FAILURE without a pose."""

    INPUT_PORTS = {
        "pose": PortInformation(Pose2D, True, "centre of the cleared square"),
        "costmap": PortInformation(str, False, "local, global or both", "local"),
        "reset_distance": Port(float, False, "side of the cleared square, m", 1.0, low=0.0),
    }
    NEEDS_ROBOT = False

    def update(self) -> Status:
        if self.read("pose") is None:
            self.say("no pose")
            return FAILURE
        return super().update()

    def clear(self, handle: Any, pose: Pose2D | None) -> None:
        centre = self.read("pose")
        handle.clear_inside(centre.x, centre.y, self.get_input("reset_distance"))
