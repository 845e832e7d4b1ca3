"""CancelControl, CancelSpin, CancelBackUp, CancelDriveOnHeading, CancelWait (Nav2 actions)."""

from __future__ import annotations

from typing import Any

from behaviors.base import SUCCESS, Leaf, PortInformation, Status
from navcore.types import Twist


class CancelControl(Leaf):
    """Stop the robot: write a zero ``cmd_vel`` this tick and SUCCEED (Nav2's ``CancelControl``
    cancels the controller server's FollowPath goal, which stops the base; here the
    controller is a plain call, so cancelling means commanding zero). Nav2 uses it before a
    Wait when a new path is much longer near the goal (PathLongerOnApproach)."""

    INPUT_PORTS: dict[str, PortInformation] = {}
    OUTPUT_PORTS = {"cmd_vel": PortInformation(Twist, True, "zero velocity command")}
    DEFAULT_KEYS = {"cmd_vel": "cmd_vel"}

    def setup(self, **kwargs: Any) -> None:
        pass

    def update(self) -> Status:
        self.write("cmd_vel", Twist.zero())
        self.say("control cancelled: zero command")
        return SUCCESS


class CancelSpin(CancelControl):
    """Stop a Spin: zero ``cmd_vel`` this tick, SUCCESS (Nav2 ``CancelSpin`` cancels the
    behaviour server's spin goal)."""


class CancelBackUp(CancelControl):
    """Stop a BackUp: zero ``cmd_vel`` this tick, SUCCESS (Nav2 ``CancelBackUp``)."""


class CancelDriveOnHeading(CancelControl):
    """Stop a DriveOnHeading: zero ``cmd_vel`` this tick, SUCCESS (Nav2
    ``CancelDriveOnHeading``)."""


class CancelWait(CancelControl):
    """End a Wait early: SUCCESS at once (Nav2 ``CancelWait``); the base gets zero as after
    any wait."""
