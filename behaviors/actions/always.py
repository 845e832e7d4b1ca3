"""AlwaysSuccess and AlwaysFailure (BT.CPP built-ins)."""

from __future__ import annotations

from behaviors.base import FAILURE, SUCCESS, Leaf, PortInformation, Status


class AlwaysSuccess(Leaf):
    """SUCCESS, every tick (BT.CPP built-in)."""

    INPUT_PORTS: dict[str, PortInformation] = {}
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def update(self) -> Status:
        return SUCCESS


class AlwaysFailure(Leaf):
    """FAILURE, every tick (BT.CPP built-in)."""

    INPUT_PORTS: dict[str, PortInformation] = {}
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def update(self) -> Status:
        return FAILURE
