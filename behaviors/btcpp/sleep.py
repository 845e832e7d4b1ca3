"""Sleep (BehaviorTree.CPP 4 action)."""

from __future__ import annotations

from typing import Any

from behaviors.base import RUNNING, SUCCESS, Leaf, Port, PortInformation, Status


class Sleep(Leaf):
    """RUNNING for ``msec`` milliseconds of the injected clock, then SUCCESS; a halt ends it
    (BT.CPP ``Sleep``)."""

    INPUT_PORTS = {"msec": Port(int, True, "how long, ms", low=0)}
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def setup(self, **kwargs: Any) -> None:
        self.clock = self.component(kwargs, "clock")

    def initialise(self) -> None:
        msec = self.read("msec")
        self._until = self.clock.now() + (msec or 0) / 1000.0

    def update(self) -> Status:
        left = self._until - self.clock.now()
        if left <= 1e-9:
            return SUCCESS
        self.say("{:.2f} s left", left)
        return RUNNING
