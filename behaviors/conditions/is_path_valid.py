"""IsPathValid (Nav2)."""

from __future__ import annotations

from typing import Any

from behaviors.base import FAILURE, SUCCESS, Port, PortInformation, Status
from navcore.costmap.cost_values import INSCRIBED_INFLATED_OBSTACLE, NO_INFORMATION
from navcore.types import Path
from behaviors.conditions.condition import Condition


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
        grid = self.costmap.costmap
        max_cost = self.get_input("max_cost")
        unknown_blocks = self.get_input("consider_unknown_as_obstacle")
        for x, y, _ in path.poses:
            cell = grid.world_to_map(float(x), float(y))
            if cell is None:
                continue
            cost = int(grid.costs[cell[1], cell[0]])
            if cost == NO_INFORMATION and not unknown_blocks:
                continue
            if cost > max_cost:
                self.say(f"path blocked at ({x:.2f}, {y:.2f}), cost {cost}")
                return FAILURE
        return SUCCESS
