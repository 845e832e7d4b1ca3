"""Pure pursuit along a trail of poses, forwards or backwards, and the poses a constant
command sweeps (what a collision check looks at)."""

from __future__ import annotations

import math

from navcore.types import Pose2D, Twist

# spacing of the poses a motion is checked at, m
CHECK_STEP = 0.05


def pure_pursuit(pose: Pose2D, trail: list[Pose2D], index: int, target: Pose2D, speed: float,
                 lookahead: float, w_max: float, period: float) -> tuple[Twist, int]:
    """One step along ``trail`` toward ``target``: aim at the first trail pose at least
    ``lookahead`` metres away from ``trail[index]`` on, drive forwards when the aim is ahead
    and backwards when it is behind, on the arc through it, at ``speed`` (no faster than
    reaches ``target`` in one ``period``), turning at most ``w_max``. Returns the command and
    the new trail index."""
    while index < len(trail) - 1 and pose.distance_to(trail[index]) < lookahead:
        index += 1
    aim = trail[index].relative_to(pose)
    v = -speed if aim.x <= 0.0 else speed
    v = math.copysign(min(abs(v), pose.distance_to(target) / period), v)
    l2 = max(aim.x * aim.x + aim.y * aim.y, 1e-6)
    w = max(-w_max, min(w_max, v * 2.0 * aim.y / l2))
    return Twist(v, 0.0, w), index


def swept_poses(pose: Pose2D, v: float, w: float, horizon: float) -> list[Pose2D]:
    """The poses of ``horizon`` seconds of the command (v, w) from ``pose``, every
    ``CHECK_STEP`` metres of travel (at least one)."""
    n = max(1, int(math.ceil(abs(v) * horizon / CHECK_STEP)))
    dt = horizon / n
    poses, p = [], pose
    for _ in range(n):
        p = p.compose(Pose2D(v * dt, 0.0, w * dt))
        poses.append(p)
    return poses
