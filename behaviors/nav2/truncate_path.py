"""TruncatePath and TruncatePathLocal (Nav2 actions): a path cut near the goal, or
around the robot. The path arithmetic is in navcore.path_ops."""

from __future__ import annotations

import math
from typing import Any

from behaviors.base import FAILURE, SUCCESS, Leaf, PortInformation, Status
from navcore import path_ops
from navcore.types import Path, Pose2D


class TruncatePath(Leaf):
    """Write ``input_path`` less its poses within ``distance`` m of the goal (at least two
    kept), the new last pose facing the goal. SUCCESS, also for an empty path (written as is).
    (Nav2 ``TruncatePath``.)"""

    INPUT_PORTS = {
        "input_path": PortInformation(Path, True, "path to truncate"),
        "distance": PortInformation(float, False, "distance to the goal to cut, m", 1.0),
    }
    OUTPUT_PORTS = {"output_path": PortInformation(Path, True, "the truncated path")}

    def setup(self, **kwargs: Any) -> None:
        pass

    def update(self) -> Status:
        path = self.read("input_path")
        if path is None:
            path = Path.from_poses([])
        self.write("output_path", path_ops.truncate_end(path, self.get_input("distance")))
        return SUCCESS


class TruncatePathLocal(Leaf):
    """Write the part of ``input_path`` around the robot: ``distance_backward`` m behind the
    path pose closest to it and ``distance_forward`` m ahead (negative: to the end), measured
    along the path. The closest pose weighs heading by ``angular_distance_weight`` (m/rad);
    with ``max_robot_pose_search_dist`` >= 0 (Nav2: finite) the search starts at the previous
    closest pose and covers that much path (it restarts when the path changes). ``pose``
    overrides the robot pose. SUCCESS (an empty path gives an empty one). (Nav2
    ``TruncatePathLocal``.)"""

    INPUT_PORTS = {
        "input_path": PortInformation(Path, True, "original path"),
        "distance_forward": PortInformation(float, False, "kept ahead of the robot, m", 8.0),
        "distance_backward": PortInformation(float, False, "kept behind the robot, m", 4.0),
        "robot_base_frame": PortInformation(str, False, "Nav2's robot frame; the pose is the "
                                            "executive's here", "base_link"),
        "transform_tolerance": PortInformation(float, False, "Nav2's TF tolerance, s; unused",
                                               0.2),
        "pose": PortInformation(Pose2D, False, "pose to use instead of the robot's"),
        "angular_distance_weight": PortInformation(float, False, "weight of heading in the "
                                                   "closest-pose distance, m/rad", 0.0),
        "max_robot_pose_search_dist": PortInformation(float, False, "path length searched "
                                                      "for the closest pose, m; < 0 = all "
                                                      "(Nav2: infinity)", -1.0),
    }
    OUTPUT_PORTS = {"output_path": PortInformation(Path, True, "the path around the robot")}

    def __init__(self, *args, **kwargs) -> None:  # noqa: D107
        super().__init__(*args, **kwargs)
        self._path: Path | None = None
        self._begin = 0

    def setup(self, **kwargs: Any) -> None:
        self.robot = self.component(kwargs, "robot", optional=True)

    def update(self) -> Status:
        path = self.read("input_path")
        if path is None:
            path = Path.from_poses([])
        search = self.get_input("max_robot_pose_search_dist")
        pruning = 0.0 <= search < math.inf
        if not pruning:
            search = math.inf
        if not pruning or path is not self._path:
            self._path, self._begin = path, 0
        pose = self.read("pose")
        if pose is None:
            if self.robot is None:
                self.say("no pose given and no robot")
                return FAILURE
            pose = self.robot.pose()
        if len(path) == 0:
            self.write("output_path", path)
            return SUCCESS
        i = path_ops.closest_pose_index(path, pose, self._begin, search,
                                        self.get_input("angular_distance_weight"))
        if pruning:
            self._begin = i
        self.write("output_path", path_ops.window_around(
            path, i, self.get_input("distance_forward"), self.get_input("distance_backward")))
        return SUCCESS
