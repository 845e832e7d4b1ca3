"""KeepRunningUntilFailure (BT.CPP)."""

from __future__ import annotations

from behaviors.base import INVALID, RUNNING, SUCCESS, DecoratorNode, PortInformation, tick_child


class KeepRunningUntilFailure(DecoratorNode):
    """RUNNING while the child succeeds (it runs again next tick); FAILURE when it fails."""

    INPUT_PORTS: dict[str, PortInformation] = {}
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def tick_now(self) -> None:
        tick_child(self.decorated)
        status = self.decorated.status
        if status is SUCCESS:
            self.decorated.stop(INVALID)
            status = RUNNING
        self._finish(status)
