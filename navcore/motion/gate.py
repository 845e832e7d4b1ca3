"""The gate on a path: the narrow passage ahead of the robot (a gap in a wall, a doorway) that a
robot swinging between two ways could not get into, and the pose to line up for.

A local planner scores its samples for progress along the path and clearance at once; in front
of a gap only a few centimetres wider than the body, each sample that enters it scores badly,
the robot slides along the wall, the next plan takes the other gap, and so on. Lining up in
front of the gap and driving straight through (``navcore.motion.line_up``, as for a tight goal)
is what gets it through. The gate is measured with ``goal_room`` at poses along the path,
facing along it.
"""

from __future__ import annotations

import math

import numpy as np

from navcore.costmap.costmap2d import Costmap2D
from navcore.motion.line_up import body_extent, goal_room, side_distances
from navcore.motion.path_progress import length_to_go
from navcore.types import Path, Pose2D


def path_heading(poses: np.ndarray, i: int, span: float) -> float:
    """The direction of the path at pose ``i``: from ``span`` m before it to ``span`` m after
    (fewer at the ends)."""
    xy = poses[:, :2]
    steps = np.hypot(*np.diff(xy, axis=0).T)
    s = np.concatenate([[0.0], np.cumsum(steps)])
    a = int(np.searchsorted(s, s[i] - span, side="left"))
    b = int(np.searchsorted(s, s[i] + span, side="right")) - 1
    a, b = min(a, i), max(b, i)
    if b == a:
        return float(poses[i, 2])
    return math.atan2(xy[b, 1] - xy[a, 1], xy[b, 0] - xy[a, 0])


def gate_on_path(costmap: Costmap2D, path: Path, pose: Pose2D, footprint: np.ndarray,
                 lookahead: float, narrow_margin: float, step: float | None = None,
                 max_depth: float = 1.5) -> Pose2D | None:
    """The pose to drive straight to through the narrowest place of ``path`` between a body
    length and ``lookahead`` m (path length) ahead of the path pose nearest ``pose`` (the
    place the robot stands in is not the one to line up for), when its room per
    side beyond the footprint is below ``narrow_margin``: on the straight line through that
    place along the path's direction there, the farthest pose (stepping ``step`` m, a cell by
    default, up to ``max_depth`` m) still in the narrow part. None when nothing ahead is that
    narrow or the path is too short."""
    poses = np.asarray(path.poses, dtype=float)
    if len(poses) < 2:
        return None
    step = costmap.resolution if step is None else step
    near = int(np.argmin(np.hypot(poses[:, 0] - pose.x, poses[:, 1] - pose.y)))
    to_go = length_to_go(poses)
    rear, front, _ = body_extent(footprint)
    ahead = np.nonzero((to_go <= to_go[near] - (front - rear))
                       & (to_go >= to_go[near] - lookahead))[0]
    best, best_margin = None, narrow_margin
    last_s = -math.inf
    for i in ahead:
        s = to_go[near] - to_go[i]
        if s - last_s < step - 1e-9:         # one station a step
            continue
        last_s = s
        p = Pose2D(float(poses[i, 0]), float(poses[i, 1]), path_heading(poses, int(i), 0.2))
        margin = goal_room(costmap, p, footprint).margin
        if margin < best_margin:
            best, best_margin = p, margin
    if best is None:
        return None
    # centred across the narrowest place: a path of cell centres may run a cell off the middle
    stations = np.arange(rear, front + 1e-9, costmap.resolution)
    left, right = side_distances(costmap, best, stations)
    k = int(np.argmin(left + right))
    best = best.compose(Pose2D(0.0, 0.5 * float(left[k] - right[k]), 0.0))
    last = best
    for d in np.arange(step, max_depth + 1e-9, step):
        p = best.compose(Pose2D(float(d), 0.0, 0.0))
        if goal_room(costmap, p, footprint).margin >= narrow_margin:
            break
        last = p
    return last
