"""Operations on paths that Nav2's behaviour-tree nodes perform (truncating, windowing around
the robot, joining, smoothing), as plain functions over ``Path`` (poses: (N, 3) float64 x, y,
theta in m, m, rad)."""

from __future__ import annotations

import math

import numpy as np

from navcore.types import Path, Pose2D, angle_diff


def truncate_end(path: Path, distance: float) -> Path:
    """Drop the poses within ``distance`` m (straight line) of the last pose, keeping at least
    two, and point the new last pose at the old goal (Nav2 ``TruncatePath``; a zero-length
    last step gets heading 0)."""
    poses = path.poses
    if len(poses) == 0:
        return Path(poses.copy(), path.frame_id, path.stamp)
    gx, gy = poses[-1, 0], poses[-1, 1]
    n = len(poses)
    while n > 2 and math.hypot(poses[n - 1, 0] - gx, poses[n - 1, 1] - gy) < distance:
        n -= 1
    out = poses[:n].copy()
    dx, dy = gx - out[-1, 0], gy - out[-1, 1]
    out[-1, 2] = math.atan2(dy, dx) if (dx or dy) else 0.0
    return Path(out, path.frame_id, path.stamp)


def _first_beyond(xy: np.ndarray, start: int, step: int, distance: float) -> int | None:
    """Index of the first pose walking from ``start`` by ``step`` (+1/-1) at which the length
    integrated along the path exceeds ``distance``; None when none does (Nav2's
    ``first_after_integrated_distance`` returning the end)."""
    i, acc = start, 0.0
    while 0 <= i + step < len(xy):
        acc += math.hypot(xy[i + step, 0] - xy[i, 0], xy[i + step, 1] - xy[i, 1])
        if acc > distance:
            return i + step
        i += step
    return None


def closest_pose_index(path: Path, pose: Pose2D, begin: int = 0,
                       search_dist: float = math.inf, angular_weight: float = 0.0) -> int:
    """Index of the path pose nearest ``pose`` (distance sqrt(dx^2+dy^2+(w*dtheta)^2)) among
    the poses from ``begin`` before the first one more than ``search_dist`` m further along."""
    end = len(path.poses)
    if math.isfinite(search_dist):
        beyond = _first_beyond(path.poses[:, :2], begin, +1, search_dist)
        end = end if beyond is None else beyond
    seg = path.poses[begin:end]
    da = angular_weight * np.abs(np.array([angle_diff(pose.theta, t) for t in seg[:, 2]]))
    d = np.sqrt((seg[:, 0] - pose.x) ** 2 + (seg[:, 1] - pose.y) ** 2 + da ** 2)
    return begin + int(np.argmin(d))


def window_around(path: Path, index: int, forward: float, backward: float) -> Path:
    """The poses of ``path`` within ``backward`` m before pose ``index`` and ``forward`` m
    after it, measured along the path (Nav2 ``TruncatePathLocal``; a negative ``forward``
    means to the end). The first pose beyond either distance is left out, as in Nav2."""
    xy = path.poses[:, :2]
    if forward < 0.0:
        forward = math.inf
    hi = _first_beyond(xy, index, +1, forward)
    lo = _first_beyond(xy, index, -1, backward)
    start = 0 if lo is None else lo + 1
    end = len(xy) if hi is None else hi
    return Path(path.poses[start:end].copy(), path.frame_id, path.stamp)


def concatenate(first: Path | None, second: Path | None) -> Path | None:
    """``first``'s poses then ``second``'s (Nav2 ``ConcatenatePaths``); None if both are empty.
    The frame is the first non-empty input's."""
    parts = [p for p in (first, second) if p is not None and len(p) > 0]
    if not parts:
        return None
    return Path(np.vstack([p.poses for p in parts]), parts[0].frame_id, parts[0].stamp)


def smooth(path: Path, w_data: float = 0.2, w_smooth: float = 0.3, tolerance: float = 1e-10,
           max_iterations: int = 1000) -> tuple[Path, bool]:
    """Nav2's SimpleSmoother: move each inner pose toward its neighbours' mean (``w_smooth``)
    while held to the original (``w_data``), until the total change of an iteration falls below
    ``tolerance``; the ends stay. Headings are recomputed along the result, the last one kept.
    Returns the path and whether it converged within ``max_iterations``."""
    poses = path.poses
    if len(poses) < 3:
        return Path(poses.copy(), path.frame_id, path.stamp), True
    orig = poses[:, :2]
    cur = orig.copy()
    converged = False
    for _ in range(max_iterations):
        prev = cur.copy()
        for i in range(1, len(cur) - 1):  # Gauss-Seidel, as Nav2: uses the updated neighbour
            cur[i] += w_data * (orig[i] - cur[i]) + w_smooth * (cur[i - 1] + cur[i + 1]
                                                                - 2.0 * cur[i])
        if float(np.sum(np.abs(cur - prev))) < tolerance:
            converged = True
            break
    out = np.empty_like(poses)
    out[:, :2] = cur
    out[:-1, 2] = np.arctan2(np.diff(cur[:, 1]), np.diff(cur[:, 0]))
    out[-1, 2] = poses[-1, 2]
    return Path(out, path.frame_id, path.stamp), converged


class TrackingFeedback:
    """How well the robot follows a path (nav2_msgs/TrackingFeedback, Nav2 main):
    ``position_tracking_error`` m, signed (+ = robot left of the path);
    ``heading_tracking_error`` rad (path heading - robot heading, + = robot turned right of it);
    ``current_path_index`` (closest pose); ``distance_to_goal`` m (straight line);
    ``remaining_path_length`` m (along the path from the closest pose); ``speed`` m/s."""

    __slots__ = ("position_tracking_error", "heading_tracking_error", "current_path_index",
                 "robot_pose", "distance_to_goal", "speed", "remaining_path_length")

    def __init__(self, position_tracking_error: float, heading_tracking_error: float,
                 current_path_index: int, robot_pose: Pose2D, distance_to_goal: float,
                 speed: float, remaining_path_length: float) -> None:
        self.position_tracking_error = position_tracking_error
        self.heading_tracking_error = heading_tracking_error
        self.current_path_index = current_path_index
        self.robot_pose = robot_pose
        self.distance_to_goal = distance_to_goal
        self.speed = speed
        self.remaining_path_length = remaining_path_length

    def __repr__(self) -> str:
        return ("TrackingFeedback(" + ", ".join(f"{k}={getattr(self, k)!r}"
                                                for k in self.__slots__) + ")")


def tracking_feedback(path: Path, pose: Pose2D, speed: float, begin: int = 0) -> TrackingFeedback:
    """Tracking errors of ``pose`` against the segment of ``path`` after its closest pose
    (searched from ``begin``)."""
    poses = path.poses
    i = closest_pose_index(path, pose, begin)
    j = min(i + 1, len(poses) - 1)
    a = poses[i if j > i else max(i - 1, 0)]
    b = poses[j]
    dx, dy = b[0] - a[0], b[1] - a[1]
    seg = math.hypot(dx, dy)
    if seg > 0.0:
        cross = (dx * (pose.y - a[1]) - dy * (pose.x - a[0])) / seg
        path_heading = math.atan2(dy, dx)
    else:
        cross = math.hypot(pose.x - poses[i, 0], pose.y - poses[i, 1])
        path_heading = float(poses[i, 2])
    steps = np.hypot(np.diff(poses[i:, 0]), np.diff(poses[i:, 1]))
    return TrackingFeedback(float(cross), angle_diff(path_heading, pose.theta), int(i), pose,
                            math.hypot(poses[-1, 0] - pose.x, poses[-1, 1] - pose.y),
                            float(speed), float(np.sum(steps)))


def path_length(path: Path | None) -> float:
    return 0.0 if path is None else path.length()
