"""IsGoalNearby (Nav2)."""

from __future__ import annotations

from behaviors.base import FAILURE, Port, PortInformation, Status
from behaviors.conditions.condition import Condition, yes
from navcore.motion.path_progress import length_to_go, remaining_length
from navcore.path_ops import closest_pose_index
from navcore.types import Path


class IsGoalNearby(Condition):
    """SUCCESS when what is left of ``path`` (from the robot) is shorter than
    ``proximity_threshold`` metres (Nav2 ``IsGoalNearby``). With ``max_robot_pose_search_dist``
    >= 0 the closest pose is searched from the previous one over that much path (a new path
    restarts it) and the length counts from that pose, as Nav2 does."""

    INPUT_PORTS = {
        "path": PortInformation(Path, True, "current global path"),
        "proximity_threshold": Port(float, False, "remaining path length, m", 1.0, low=0.0),
        "max_robot_pose_search_dist": PortInformation(float, False, "path length searched for "
                                                      "the closest pose, m; < 0 = all", -1.0),
    }
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    DEFAULT_KEYS = {"path": "path"}

    def update(self) -> Status:
        path = self.read("path")
        if path is None:
            return FAILURE
        if path is not getattr(self, "_path", None):  # a new plan: sum its lengths once
            self._path, self._to_go, self._begin = path, length_to_go(path.poses), 0
        search = self.get_input("max_robot_pose_search_dist")
        if search >= 0.0 and len(path) > 0:
            self._begin = closest_pose_index(path, self.pose(), self._begin, search)
            left = float(self._to_go[self._begin])
        else:
            left = remaining_length(path, self.pose(), self._to_go)
        self.say("{:.2f} m of path left", left)
        return yes(left < self.get_input("proximity_threshold"))
