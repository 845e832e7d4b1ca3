"""ValidatePath (Nav2 main action): the costmap check of IsPathValid, with the colliding
poses as output."""

from __future__ import annotations

from typing import Any

from behaviors.base import FAILURE, SUCCESS, PortInformation, Status
from behaviors.conditions.condition import Condition
from navcore.costmap.cost_values import LETHAL_OBSTACLE
from navcore.costmap.path_check import blocked_poses
from navcore.types import Path


class ValidatePath(Condition):
    """SUCCESS when no pose of ``path`` lies on a global-costmap cell costlier than
    ``max_cost`` (unknown cells count when ``consider_unknown_as_obstacle``); FAILURE
    otherwise, with the offending poses in ``collision_poses`` (all of them, or the first
    with ``stop_at_first_collision``; only within ``max_lookahead_distance`` m along the path
    when it is positive). (Nav2 main ``ValidatePath``; ``layer_name``/``footprint`` are
    accepted, the master costmap and the path points are checked.)"""

    CATEGORY = "Action"
    INPUT_PORTS = {
        "path": PortInformation(Path, True, "path to check"),
        "max_cost": PortInformation(int, False, "highest acceptable cell cost",
                                    LETHAL_OBSTACLE),  # Nav2: 254
        "consider_unknown_as_obstacle": PortInformation(bool, False, "unknown cells block",
                                                        False),
        "layer_name": PortInformation(str, False, "Nav2's costmap layer; the master here", ""),
        "footprint": PortInformation(str, False, "Nav2's footprint string; unused", ""),
        "stop_at_first_collision": PortInformation(bool, False, "report only the first", True),
        "max_lookahead_distance": PortInformation(float, False, "path length checked, m; "
                                                  "<= 0 = all", -1.0),
    }
    OUTPUT_PORTS = {"collision_poses": PortInformation(list, False, "Pose2D that collide")}
    DEFAULT_KEYS = {"path": "path"}

    def setup(self, **kwargs: Any) -> None:
        super().setup(**kwargs)
        self.costmap = self.component(kwargs, "global_costmap")

    def update(self) -> Status:
        path = self.read("path")
        if path is None or len(path) == 0:
            self.say("no path")
            self.write("collision_poses", [])
            return FAILURE
        hits = blocked_poses(self.costmap.costmap, path.poses, self.get_input("max_cost"),
                             self.get_input("consider_unknown_as_obstacle"),
                             self.get_input("max_lookahead_distance"),
                             self.get_input("stop_at_first_collision"))
        bad = [path.pose(i) for i, _ in hits]
        self.write("collision_poses", bad)
        if bad:
            self.say(f"{len(bad)} path poses collide, first at ({bad[0].x:.2f}, {bad[0].y:.2f})")
        return FAILURE if bad else SUCCESS
