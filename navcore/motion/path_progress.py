"""How much of a path is left from the robot: the length from the closest path pose to the end
(Nav2's IsGoalNearby), with numba kernels tested against numpy (tests/test_motion.py)."""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from navcore.types import Path, Pose2D


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
        step = np.hypot(poses[i + 1, 0] - poses[i, 0], poses[i + 1, 1] - poses[i, 1])
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
    a NaN distance wins, as there). Checked every tick, so one pass without temporaries.
    np.hypot, not math.hypot: libm's in both modes (plain Python's math.hypot differs by an ulp
    from the compiled one)."""
    best, best_d = 0, math.inf
    for i in range(poses.shape[0]):
        d = np.hypot(poses[i, 0] - x, poses[i, 1] - y)
        if d != d:
            return d + to_go[i]
        if d < best_d:
            best, best_d = i, d
    if best_d == math.inf:  # every distance infinite: np.argmin takes the first
        best = 0
        best_d = np.hypot(poses[0, 0] - x, poses[0, 1] - y)
    return best_d + to_go[best]
