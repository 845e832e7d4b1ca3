"""TruncatePath, TruncatePathLocal, ConcatenatePaths, GetPoseFromPath, SmoothPath (Nav2
actions on paths). Each takes one tick; the path arithmetic is in navcore.path_ops."""

from __future__ import annotations

import math
from typing import Any

from behaviors.base import FAILURE, SUCCESS, Leaf, PortInformation, Status
from navcore import path_ops
from navcore.error_codes import SmootherError
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


class SmoothPath(Leaf):
    """Smooth ``unsmoothed_path`` as Nav2's SimpleSmoother does (poses pulled toward their
    neighbours, held to the original; ends fixed) and write ``smoothed_path``. With
    ``check_for_collisions`` a result crossing a lethal cell of the global costmap FAILs with
    SMOOTHED_PATH_IN_COLLISION; no path FAILs with INVALID_PATH. ``was_completed`` says whether
    it converged within its iterations. (Nav2 ``SmoothPath``; ``smoother_id`` and
    ``max_smoothing_duration`` are accepted, one smoother here.)"""

    INPUT_PORTS = {
        "unsmoothed_path": PortInformation(Path, True, "path to smooth"),
        "max_smoothing_duration": PortInformation(float, False, "Nav2's time limit, s", 3.0),
        "check_for_collisions": PortInformation(bool, False, "fail if the result collides",
                                                False),
        "smoother_id": PortInformation(str, False, "smoother plugin id", ""),
    }
    OUTPUT_PORTS = {
        "smoothed_path": PortInformation(Path, True, "the smoothed path"),
        "smoothing_duration": PortInformation(float, False, "time spent, s (simulated: 0)"),
        "was_completed": PortInformation(bool, False, "converged within the iterations"),
        "error_code_id": PortInformation(int, False, "a SmootherError; 0 on success"),
        "error_msg": PortInformation(str, False, "why smoothing failed"),
    }

    def setup(self, **kwargs: Any) -> None:
        self.costmap = self.component(kwargs, "global_costmap", optional=True)

    def update(self) -> Status:
        path = self.read("unsmoothed_path")
        if path is None or len(path) == 0:
            return self._fail(SmootherError.INVALID_PATH, "no path to smooth")
        smoothed, done = path_ops.smooth(path)
        if self.get_input("check_for_collisions") and self.costmap is not None:
            from navcore.costmap.cost_values import LETHAL_OBSTACLE
            grid = self.costmap.costmap
            for x, y, _ in smoothed.poses:
                cell = grid.world_to_map(float(x), float(y))
                if cell is not None and int(grid.costs[cell[1], cell[0]]) >= LETHAL_OBSTACLE:
                    return self._fail(SmootherError.SMOOTHED_PATH_IN_COLLISION,
                                      f"smoothed path collides at ({x:.2f}, {y:.2f})")
        self.write("smoothed_path", smoothed)
        self.write("smoothing_duration", 0.0)
        self.write("was_completed", done)
        self.write("error_code_id", int(SmootherError.NONE))
        self.write("error_msg", "")
        return SUCCESS

    def _fail(self, code: int, msg: str) -> Status:
        self.write("error_code_id", int(code))
        self.write("error_msg", msg)
        self.say(msg)
        return FAILURE


