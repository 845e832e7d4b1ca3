"""Rotate to the path's heading before following it (the semantics of Nav2's
RotationShimController, without its code).

A robot facing away from a new path turns on the spot until the path ahead lies within
``angular_dist_threshold`` of its heading, and only then hands over to the local planner. A
planner allowed to reverse (``min_vel_x`` < 0) would otherwise follow such a path backwards, into
the laser's blind sector, for as long as the path lasts. As in Nav2 the check is made on each new
path (a replan re-arms it) and, once handed over, the local planner keeps the robot until the
next path.

The angle is the direction, in the robot's frame, of the first path pose at least
``forward_sampling_distance`` metres from the robot (past the pose nearest to it). A path that
ends nearer than that is the local planner's to finish (turning to the goal is its job). The turn runs at ``rotate_to_heading_angular_vel`` rad/s, reached and
left within ``max_angular_accel`` rad/s^2, and is footprint-checked over ``simulate_ahead_time``
seconds of turning.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from navcore.motion.collision import first_collision
from navcore.types import Pose2D, Twist


@dataclass(frozen=True)
class ShimParams:
    """Nav2 RotationShimController parameter names and defaults."""

    angular_dist_threshold: float = 0.785
    forward_sampling_distance: float = 0.5
    rotate_to_heading_angular_vel: float = 1.8
    max_angular_accel: float = 3.2
    simulate_ahead_time: float = 1.0


def heading_error(pose: Pose2D, poses: np.ndarray, forward_sampling_distance: float
                  ) -> float | None:
    """The angle (rad, in (-pi, pi]) from the robot's heading to the sampled path pose (see the
    module docstring), None when no path pose past the nearest one is that far; ``poses`` is
    (N, 3), N >= 1."""
    d = np.hypot(poses[:, 0] - pose.x, poses[:, 1] - pose.y)
    start = int(np.argmin(d))
    far = np.nonzero(d[start:] >= forward_sampling_distance)[0]
    if len(far) == 0:
        return None
    k = start + int(far[0])
    target = Pose2D(float(poses[k, 0]), float(poses[k, 1]), 0.0).relative_to(pose)
    return math.atan2(target.y, target.x)


def turn_command(error: float, current_w: float, period: float, p: ShimParams) -> float:
    """The turn rate toward ``error``: the full rate, within the acceleration from the current
    one, and no faster than stops at the heading (sqrt(2 a |error|))."""
    sign = 1.0 if error > 0.0 else -1.0
    acc = p.max_angular_accel
    w = min(p.rotate_to_heading_angular_vel, math.sqrt(2.0 * acc * abs(error)))
    return min(max(sign * w, current_w - acc * period), current_w + acc * period)


class RotationShim:
    """The per-path state: whether the robot still has to turn before the planner drives."""

    def __init__(self) -> None:
        self.armed = False

    def new_path(self) -> None:
        """A new path: check the heading again."""
        self.armed = True

    def command(self, pose: Pose2D, poses: np.ndarray, current_w: float, period: float,
                p: ShimParams, collision: Any = None
                ) -> tuple[Twist | None, tuple[Pose2D, int] | None]:
        """(The turn command, None) while the path's heading is off by more than the
        threshold; (None, None) once it is not (the planner's turn, until the next path); (None,
        the blocking pose and cost) when the footprint would collide on the costmap handle
        ``collision`` (navcore.motion.collision) within ``simulate_ahead_time`` s of turning."""
        if not self.armed or len(poses) == 0:
            return None, None
        cmd, hit = turn_toward_path(pose, poses, current_w, period, p, collision)
        if cmd is None and hit is None:
            self.armed = False
        return cmd, hit


def turn_toward_path(pose: Pose2D, poses: np.ndarray, current_w: float, period: float,
                     p: ShimParams, collision: Any = None
                     ) -> tuple[Twist | None, tuple[Pose2D, int] | None]:
    """One tick of the turn toward the path: (the command, None) while the path ahead is more
    than ``angular_dist_threshold`` off the heading; (None, None) when it is not (or the path
    ends nearer than the sampling distance); (None, the blocking pose and cost) when the turn's
    footprint collides on ``collision`` within ``simulate_ahead_time`` s."""
    error = heading_error(pose, poses, p.forward_sampling_distance)
    if error is None or abs(error) <= p.angular_dist_threshold:
        return None, None
    w = turn_command(error, current_w, period, p)
    if collision is not None:
        ahead = min(abs(error), p.rotate_to_heading_angular_vel * p.simulate_ahead_time)
        n = max(1, int(math.ceil(ahead / 0.05)))
        sign = 1.0 if error > 0.0 else -1.0
        hit = first_collision(collision, [Pose2D(pose.x, pose.y,
                                                 pose.theta + sign * ahead * k / n)
                                          for k in range(1, n + 1)], pose)
        if hit is not None:
            return None, hit
    return Twist(0.0, 0.0, w), None
