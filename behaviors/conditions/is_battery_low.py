"""IsBatteryLow (Nav2)."""

from __future__ import annotations

from behaviors.base import FAILURE, Port, PortInformation, Status
from behaviors.conditions.condition import Condition, yes


class IsBatteryLow(Condition):
    """SUCCESS when the battery is at or below ``min_battery`` (fraction 0..1, or volts when
    ``is_voltage``). FAILURE when no battery state is known. (Nav2 ``IsBatteryLow``.)"""

    INPUT_PORTS = {
        "min_battery": Port(float, False, "threshold, fraction 0..1 or V", 0.2, low=0.0),
        "is_voltage": PortInformation(bool, False, "compare volts instead of charge", False),
    }
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def update(self) -> Status:
        state = self.robot.battery() if self.robot is not None else None
        if state is None:
            self.say("no battery state")
            return FAILURE
        value = state.voltage if self.get_input("is_voltage") else state.percentage
        return yes(value <= self.get_input("min_battery"))
