"""Inverter, ForceSuccess, ForceFailure (BT.CPP)."""

from __future__ import annotations

from behaviors.base import (FAILURE, RUNNING, SUCCESS, DecoratorNode, PortInformation, Status,
                            Ticking)


class Passthrough(DecoratorNode):
    """Tick the child every tick and map its status through ``convert``."""

    INPUT_PORTS: dict[str, PortInformation]
    OUTPUT_PORTS: dict[str, PortInformation]

    def convert(self, status: Status) -> Status:
        raise NotImplementedError

    def tick(self) -> Ticking:
        self.begin_tick()
        yield from self.decorated.tick()
        yield self.finish(self.convert(self.decorated.status))


class Inverter(Passthrough):
    """SUCCESS <-> FAILURE of the child; RUNNING passes through."""

    INPUT_PORTS: dict[str, PortInformation] = {}
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def convert(self, status: Status) -> Status:
        if status is SUCCESS:  # comparisons, not a dict: Enum hashes in Python
            return FAILURE
        return SUCCESS if status is FAILURE else status


class ForceSuccess(Passthrough):
    """SUCCESS whenever the child finishes (either way); RUNNING passes through."""

    INPUT_PORTS: dict[str, PortInformation] = {}
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def convert(self, status: Status) -> Status:
        return RUNNING if status is RUNNING else SUCCESS


class ForceFailure(Passthrough):
    """FAILURE whenever the child finishes (either way); RUNNING passes through."""

    INPUT_PORTS: dict[str, PortInformation] = {}
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def convert(self, status: Status) -> Status:
        return RUNNING if status is RUNNING else FAILURE
