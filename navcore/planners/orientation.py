"""global_planner's orientation filter: which heading each pose of a plan gets."""

from __future__ import annotations

import math

import numpy as np

from navcore.types import Pose2D, angle_diff, normalize_angle

NONE, FORWARD, INTERPOLATE, FORWARD_THEN_INTERPOLATE, BACKWARD, LEFTWARD, RIGHTWARD = range(7)
MODE_NAMES = ("None", "Forward", "Interpolate", "ForwardThenInterpolate", "Backward", "Leftward",
              "Rightward")


def _along_path(poses: np.ndarray, window: int) -> np.ndarray:
    """Heading of the chord from pose i-window to pose i+window (clamped), for every pose."""
    n = len(poses)
    i = np.arange(n)
    i0 = np.maximum(0, i - window)
    i1 = np.minimum(n - 1, i + window)
    return np.arctan2(poses[i1, 1] - poses[i0, 1], poses[i1, 0] - poses[i0, 0])


def _interpolate(poses: np.ndarray, i0: int, i1: int) -> None:
    """Spread the turn from pose i0's heading to pose i1's evenly over the poses between.

    (The C++ multiplies the increment by the absolute index, which is only right for i0 = 0.)
    """
    if i1 <= i0:
        return
    a0, a1 = float(poses[i0, 2]), float(poses[i1, 2])
    step = angle_diff(a1, a0) / (i1 - i0)
    for k in range(i0, i1 + 1):
        poses[k, 2] = normalize_angle(a0 + step * (k - i0))


def apply_orientation(poses: np.ndarray, start: Pose2D, mode: int, window: int) -> None:
    """Set ``poses[:, 2]`` in place by ``orientation_mode`` (0-6). The last pose (the goal) keeps
    its heading in every mode except Interpolate, which ends on it."""
    n = len(poses)
    if n == 0 or mode == NONE:
        return
    if mode in (FORWARD, BACKWARD, LEFTWARD, RIGHTWARD, FORWARD_THEN_INTERPOLATE):
        heading = _along_path(poses, window)[: n - 1]
        offset = {FORWARD: 0.0, FORWARD_THEN_INTERPOLATE: 0.0, BACKWARD: math.pi,
                  LEFTWARD: -math.pi / 2, RIGHTWARD: math.pi / 2}[mode]
        if offset:
            heading = np.array([normalize_angle(h + offset) for h in heading])
        poses[: n - 1, 2] = heading
    if mode == INTERPOLATE:
        poses[0, 2] = start.theta
        _interpolate(poses, 0, n - 1)
    elif mode == FORWARD_THEN_INTERPOLATE and n >= 3:
        # keep forward headings up to where the path stops turning, then turn smoothly to the goal
        i = n - 3
        last = float(poses[i, 2])
        while i > 0 and abs(angle_diff(float(poses[i - 1, 2]), last)) <= 0.35:
            i -= 1
        poses[0, 2] = start.theta
        _interpolate(poses, i, n - 1)
