"""DistanceTraveled (Nav2)."""

from __future__ import annotations

from behaviors.base import FAILURE, INVALID, SUCCESS, Port, PortInformation, Status
from behaviors.conditions.condition import Condition


class DistanceTraveled(Condition):
    """SUCCESS each time the robot has moved ``distance`` metres since the run started or it
    last fired (straight-line)."""

    INPUT_PORTS = {"distance": Port(float, False, "m", 1.0, low=0.0)}
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def update(self) -> Status:
        pose = self.pose()
        if self.status is INVALID:
            self._anchor = pose
            return FAILURE
        if pose.distance_to(self._anchor) >= self.get_input("distance"):
            self._anchor = pose
            return SUCCESS
        return FAILURE
