"""Costmap clearing: ClearEntireCostmap, ClearCostmapExceptRegion, ClearCostmapAroundRobot."""

from __future__ import annotations

from typing import Any

from behaviors.actions.recovery_action import COSTMAP_CHOICES, RecoveryAction
from behaviors.base import FAILURE, SUCCESS, Port, PortInformation, Status
from navcore.costmap.clear_memory import memory_of
from navcore.types import Pose2D

# navbt's own ports of every clearing node (Nav2's clears erase everything: the default)
CONFIRM_PORTS = {
    "keep_confirmed": PortInformation(bool, False, "keep obstacles the sensors marked again "
                                      "within confirm_window s of the previous clear", False),
    "confirm_window": Port(float, False, "s after a clear in which a re-marked cell counts "
                           "as confirmed", 10.0, low=0.0),
}


class ClearCostmap(RecoveryAction):
    INPUT_PORTS: dict[str, PortInformation]
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    CHOICES = {"costmap": COSTMAP_CHOICES}

    def clear(self, handle: Any, pose: Pose2D | None) -> None:
        raise NotImplementedError

    def update(self) -> Status:
        which = self.get_input("costmap")
        if which not in COSTMAP_CHOICES:
            self.say(f"costmap must be one of {COSTMAP_CHOICES}, got {which!r}")
            return FAILURE
        handles = self.costmap_handles(which)
        if not handles:
            self.say(f"no {which} costmap was set up")
            return FAILURE
        pose = self.robot.pose() if self.robot is not None else None
        kept = 0
        for h in handles:
            if self.get_input("keep_confirmed") and hasattr(h, "obstacle_layers"):
                mem = memory_of(h, self.get_input("confirm_window"))
                kept += mem.clear(h, self.clock.now(), lambda h=h: self.clear(h, pose))
            else:
                self.clear(h, pose)
        self.say(f"cleared {which}" + (f", kept {kept} confirmed obstacle cells" if kept else ""))
        return SUCCESS


class ClearEntireCostmap(ClearCostmap):
    """Reset every layer of the ``costmap`` (local, global or both) in one tick. SUCCESS.
    With ``keep_confirmed`` (every clearing node has it) obstacle cells the sensors marked again
    within ``confirm_window`` s of the previous clear stay (navcore.costmap.clear_memory)."""

    INPUT_PORTS = {"costmap": PortInformation(str, False, "local, global or both", "both"),
                   **CONFIRM_PORTS}
    NEEDS_ROBOT = False

    def clear(self, handle: Any, pose: Pose2D | None) -> None:
        handle.reset_layers()


class ClearCostmapExceptRegion(ClearCostmap):
    """clear_costmap_recovery: reset clearable layers outside a square of side
    ``reset_distance`` metres centred on the robot (move_base's conservative/aggressive reset).
    SUCCESS in one tick."""

    INPUT_PORTS = {
        "costmap": PortInformation(str, False, "local, global or both", "both"),
        "reset_distance": Port(float, False, "side of the kept square, m", 1.0, low=0.0),
        **CONFIRM_PORTS,
    }

    def clear(self, handle: Any, pose: Pose2D | None) -> None:
        if pose is None:
            raise RuntimeError(f"{self.name}: needs the robot pose")
        handle.clear_outside(pose.x, pose.y, self.get_input("reset_distance"))


class ClearCostmapAroundRobot(ClearCostmap):
    """Reset clearable layers inside a square of side ``reset_distance`` metres centred on the
    robot. SUCCESS in one tick."""

    INPUT_PORTS = {
        "costmap": PortInformation(str, False, "local, global or both", "local"),
        "reset_distance": Port(float, False, "side of the cleared square, m", 1.0, low=0.0),
        **CONFIRM_PORTS,
    }

    def clear(self, handle: Any, pose: Pose2D | None) -> None:
        if pose is None:
            raise RuntimeError(f"{self.name}: needs the robot pose")
        handle.clear_inside(pose.x, pose.y, self.get_input("reset_distance"))
