"""IsPathValid (Nav2)."""

from __future__ import annotations

from typing import Any

from behaviors.base import FAILURE, SUCCESS, Port, PortInformation, Status
from behaviors.conditions.condition import Condition
from navcore.costmap.cost_values import INSCRIBED_INFLATED_OBSTACLE
from navcore.costmap.path_check import first_blocked
from navcore.types import Path


class IsPathValid(Condition):
    """SUCCESS when no pose of ``path`` lies on a lethal or inscribed cell of the global costmap.

    FAILURE also when there is no path. (Nav2 Humble ``IsPathValid``.)
    """

    INPUT_PORTS = {
        "path": PortInformation(Path, True, "path to check"),
        "max_cost": Port(int, False, "highest acceptable cell cost",
                                    INSCRIBED_INFLATED_OBSTACLE - 1, low=0, high=255),
        "consider_unknown_as_obstacle": PortInformation(bool, False, "unknown cells block", False),
    }
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    DEFAULT_KEYS = {"path": "path"}

    def setup(self, **kwargs: Any) -> None:
        super().setup(**kwargs)
        self.costmap = self.component(kwargs, "global_costmap")

    def update(self) -> Status:
        path = self.read("path")
        if path is None or len(path) == 0:
            self.say("no path")
            return FAILURE
        blocked = first_blocked(self.costmap.costmap, path.poses, self.get_input("max_cost"),
                                self.get_input("consider_unknown_as_obstacle"))
        if blocked is not None:
            x, y, _ = path.poses[blocked[0]]
            self.say(f"path blocked at ({x:.2f}, {y:.2f}), cost {blocked[1]}")
            return FAILURE
        return SUCCESS
