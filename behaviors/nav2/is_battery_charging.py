"""IsBatteryCharging (Nav2 condition)."""

from __future__ import annotations

from behaviors.base import FAILURE, SUCCESS, PortInformation, Status
from behaviors.conditions.condition import Condition


class IsBatteryCharging(Condition):
    """SUCCESS while the robot's battery state says it is charging, FAILURE otherwise and when
    no battery state is known (Nav2 ``IsBatteryCharging``; its ``battery_topic`` is the
    robot's battery here)."""

    INPUT_PORTS = {"battery_topic": PortInformation(str, False, "Nav2's topic; the robot's "
                                                    "battery here", "/battery_status")}
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def update(self) -> Status:
        state = self.robot.battery() if self.robot is not None else None
        if state is None:
            self.say("no battery state")
            return FAILURE
        return SUCCESS if state.charging else FAILURE
