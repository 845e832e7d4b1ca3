"""SetBlackboard and UnsetBlackboard (BehaviorTree.CPP 4 actions)."""

from __future__ import annotations

from typing import Any

from behaviors.base import FAILURE, SUCCESS, Leaf, PortInformation, Status
from behaviors.btcpp.scripted import STORAGE, Scripted


class SetBlackboard(Leaf):
    """Write ``value`` (a literal, or ``{key}`` to copy another entry) to the entry that
    ``output_key`` names (``"{key}"``); SUCCESS (BT.CPP ``SetBlackboard``)."""

    INPUT_PORTS = {"value": PortInformation(object, True, "value to write, or {key} to copy")}
    OUTPUT_PORTS = {"output_key": PortInformation(object, True, "the entry to write, {key}")}

    def setup(self, **kwargs: Any) -> None:
        pass

    def update(self) -> Status:
        value = self.read("value")
        if value is None:
            self.say("nothing to copy: value's entry is empty")
            return FAILURE
        self.write("output_key", value)
        return SUCCESS


class UnsetBlackboard(Scripted, Leaf):
    """Remove the entry named by ``key`` (a plain name); SUCCESS, also when it was not there
    (BT.CPP ``UnsetBlackboard``)."""

    INPUT_PORTS = {"key": PortInformation(str, True, "name of the entry to remove")}
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    KEY_PORTS = ("key",)

    def update(self) -> Status:
        key = self.bound_key("key")
        if key is not None:
            STORAGE.pop(key, None)
        return SUCCESS
