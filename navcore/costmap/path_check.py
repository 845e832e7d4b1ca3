"""Is a path still passable on a costmap? (Nav2's IsPathValid: the cost of the cell under each
path pose.)"""

from __future__ import annotations

import numpy as np

from navcore.costmap.cost_values import NO_INFORMATION
from navcore.costmap.costmap2d import Costmap2D


def blocked_poses(costmap: Costmap2D, poses: np.ndarray, max_cost: int,
                  unknown_blocks: bool = False, max_length: float = -1.0,
                  first_only: bool = True) -> list[tuple[int, int]]:
    """(index, cost) of the poses of ``poses`` (N, 3) whose cell costs more than ``max_cost``
    (or is unknown, with ``unknown_blocks``), in path order: only the first with ``first_only``,
    and only within ``max_length`` m along the path when it is positive. Poses off the map are
    skipped."""
    out: list[tuple[int, int]] = []
    travelled, prev = 0.0, None
    for i, (x, y, _) in enumerate(poses):
        if max_length > 0.0:
            if prev is not None:
                travelled += float(np.hypot(x - prev[0], y - prev[1]))
            prev = (x, y)
            if travelled > max_length:
                break
        cell = costmap.world_to_map(float(x), float(y))
        if cell is None:
            continue
        cost = int(costmap.costs[cell[1], cell[0]])
        unknown = cost == NO_INFORMATION
        if (unknown and unknown_blocks) or (not unknown and cost > max_cost):
            out.append((i, cost))
            if first_only:
                break
    return out


def first_blocked(costmap: Costmap2D, poses: np.ndarray, max_cost: int,
                  unknown_blocks: bool = False) -> tuple[int, int] | None:
    """(index, cost) of the first blocked pose of ``poses`` (see ``blocked_poses``), or None."""
    hits = blocked_poses(costmap, poses, max_cost, unknown_blocks)
    return hits[0] if hits else None
