"""ConcatenatePaths (Nav2 action)."""

from __future__ import annotations

from typing import Any

from behaviors.base import FAILURE, SUCCESS, Leaf, PortInformation, Status
from navcore import path_ops
from navcore.types import Path


class ConcatenatePaths(Leaf):
    """Write ``input_path1`` followed by ``input_path2``; FAILURE when both are empty or
    missing (Nav2 ``ConcatenatePaths``)."""

    INPUT_PORTS = {
        "input_path1": PortInformation(Path, False, "first part"),
        "input_path2": PortInformation(Path, False, "second part"),
    }
    OUTPUT_PORTS = {"output_path": PortInformation(Path, True, "both parts in order")}

    def setup(self, **kwargs: Any) -> None:
        pass

    def update(self) -> Status:
        joined = path_ops.concatenate(self.read("input_path1"), self.read("input_path2"))
        if joined is None:
            self.say("both paths are empty")
            return FAILURE
        self.write("output_path", joined)
        return SUCCESS
