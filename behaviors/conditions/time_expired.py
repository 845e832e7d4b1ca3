"""TimeExpired (Nav2)."""

from __future__ import annotations

from behaviors.base import FAILURE, INVALID, SUCCESS, Port, PortInformation, Status
from behaviors.conditions.condition import Condition


class TimeExpired(Condition):
    """SUCCESS each time ``seconds`` have passed since the run started or it last fired."""

    INPUT_PORTS = {"seconds": Port(float, False, "period, s", 1.0, low=0.0)}
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def update(self) -> Status:
        now = self.clock.now()
        if self.status is INVALID:
            self._start = now
            return FAILURE
        if now - self._start >= self.get_input("seconds") - 1e-9:  # float sums of periods
            self._start = now
            return SUCCESS
        return FAILURE
