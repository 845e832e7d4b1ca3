"""IsGoalNearby (Nav2)."""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from behaviors.base import FAILURE, Port, PortInformation, Status
from navcore.path_ops import closest_pose_index
from navcore.types import Path, Pose2D
from behaviors.conditions.condition import Condition, yes


def length_to_go(poses: np.ndarray) -> np.ndarray:
    """For each pose of an (N, 3) path, the path length from it to the end, m."""
    if len(poses) < 2:
        return np.zeros(1)
    return _length_to_go(poses)


@njit(cache=True)
def _length_to_go(poses: np.ndarray) -> np.ndarray:
    """Suffix sums of the step lengths, added from the end as a cumulative sum of the reversed
    steps does (so the same floats)."""
    n = poses.shape[0]
    out = np.empty(n)
    out[n - 1] = 0.0
    total = 0.0
    for i in range(n - 2, -1, -1):
        step = math.hypot(poses[i + 1, 0] - poses[i, 0], poses[i + 1, 1] - poses[i, 1])
        total = step if i == n - 2 else total + step
        out[i] = total
    return out


def remaining_length(path: Path, pose: Pose2D, to_go: np.ndarray | None = None) -> float:
    """Length of ``path`` from the pose closest to ``pose`` to its end, m (``to_go`` is
    ``length_to_go(path.poses)`` when the caller keeps it)."""
    if len(path) == 0:
        return 0.0
    if to_go is None:
        to_go = length_to_go(path.poses)
    return float(_closest_remaining(path.poses, float(pose.x), float(pose.y), to_go))


@njit(cache=True)
def _closest_remaining(poses: np.ndarray, x: float, y: float, to_go: np.ndarray) -> float:
    """Distance to the closest pose plus ``to_go`` from it (the first closest, as np.argmin;
    a NaN distance wins, as there). Checked every tick, so one pass without temporaries."""
    best, best_d = 0, math.inf
    for i in range(poses.shape[0]):
        d = math.hypot(poses[i, 0] - x, poses[i, 1] - y)
        if d != d:
            return d + to_go[i]
        if d < best_d:
            best, best_d = i, d
    if best_d == math.inf:  # every distance infinite: np.argmin takes the first
        best = 0
        best_d = math.hypot(poses[0, 0] - x, poses[0, 1] - y)
    return best_d + to_go[best]


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
