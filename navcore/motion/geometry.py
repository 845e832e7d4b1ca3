"""Plane geometry of short robot motions: headings, candidate poses around the robot
and the circular arcs a differential drive follows to reach a point."""

from __future__ import annotations

import math

import numpy as np

from navcore.types import Pose2D


def heading_to(a: Pose2D, b: Pose2D) -> float:
    """Direction from a to b, rad."""
    return math.atan2(b.y - a.y, b.x - a.x)


def ring_candidates(center: Pose2D, min_distance: float, max_distance: float, radial_step: float,
                    angular_samples: int) -> list[Pose2D]:
    """Poses on rings around ``center``, each facing away from it."""
    out = []
    radii = np.arange(min_distance, max_distance + 1e-9, max(radial_step, 1e-3))
    for r in radii:
        for k in range(angular_samples):
            a = center.theta + 2.0 * math.pi * k / angular_samples
            out.append(Pose2D(center.x + r * math.cos(a), center.y + r * math.sin(a),
                              math.atan2(math.sin(a), math.cos(a))))
    return out


def arc_poses(pose: Pose2D, x: float, y: float, step: float,
              max_turn: float = 0.5 * math.pi, end_only: bool = False) -> list[Pose2D] | None:
    """Poses every ``step`` metres along the circular arc a differential drive follows from
    ``pose`` to the point (x, y), forwards if the point is ahead, backwards if behind; the last
    one is at the point with the heading the arc ends with (``end_only``: just that one). None
    when the arc would turn by more than ``max_turn`` or the point is (nearly) abeam or at the
    robot."""
    rel = Pose2D(x, y, 0.0).relative_to(pose)
    d2 = rel.x * rel.x + rel.y * rel.y
    turn = 2.0 * math.atan2(abs(rel.y), abs(rel.x))
    if d2 < 1e-6 or turn > max_turn:
        return None
    k = 2.0 * rel.y / d2                                    # curvature: w = v * k either way
    length = turn / abs(k) if abs(k) > 1e-9 else abs(rel.x)
    direction = 1.0 if rel.x > 0.0 else -1.0
    n = max(1, int(math.ceil(length / step)))
    out = []
    for j in range(n if end_only else 1, n + 1):
        s = direction * length * j / n                      # signed distance along the arc
        a = k * s
        lx = math.sin(a) / k if abs(k) > 1e-9 else s
        ly = (1.0 - math.cos(a)) / k if abs(k) > 1e-9 else 0.0
        out.append(pose.compose(Pose2D(lx, ly, a)))
    return out
