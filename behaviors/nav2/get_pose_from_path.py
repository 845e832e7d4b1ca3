"""GetPoseFromPath (Nav2 action)."""

from __future__ import annotations

from typing import Any

from behaviors.base import FAILURE, SUCCESS, Leaf, PortInformation, Status
from navcore.types import Path, Pose2D


class GetPoseFromPath(Leaf):
    """Write pose ``index`` of ``path`` (negative counts from the end: -1 is the goal).
    FAILURE for an empty path or an index outside it (Nav2 ``GetPoseFromPath``)."""

    INPUT_PORTS = {
        "path": PortInformation(Path, True, "path to read"),
        "index": PortInformation(int, False, "pose index; negative from the end", 0),
    }
    OUTPUT_PORTS = {"pose": PortInformation(Pose2D, True, "the pose at index")}

    def setup(self, **kwargs: Any) -> None:
        pass

    def update(self) -> Status:
        path = self.read("path")
        n = 0 if path is None else len(path)
        i = self.get_input("index")
        if i < 0:
            i += n
        if n == 0 or not 0 <= i < n:
            self.say(f"no pose {self.get_input('index')} in a path of {n}")
            return FAILURE
        self.write("pose", path.pose(i))
        return SUCCESS
