"""KeepRunningUntilFailure (BT.CPP)."""

from __future__ import annotations

from behaviors.base import INVALID, RUNNING, SUCCESS, DecoratorNode, PortInformation, Ticking


class KeepRunningUntilFailure(DecoratorNode):
    """RUNNING while the child succeeds (it runs again next tick); FAILURE when it fails."""

    INPUT_PORTS: dict[str, PortInformation] = {}
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def tick(self) -> Ticking:
        self.begin_tick()
        yield from self.decorated.tick()
        status = self.decorated.status
        if status is SUCCESS:
            self.decorated.stop(INVALID)
            status = RUNNING
        yield self.finish(status)
