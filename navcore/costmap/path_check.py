"""Is a path still passable on a costmap? (Nav2's IsPathValid: the cost of the cell under each
path pose.)"""

from __future__ import annotations

import numpy as np

from navcore.costmap.cost_values import NO_INFORMATION
from navcore.costmap.costmap2d import Costmap2D


def first_blocked(costmap: Costmap2D, poses: np.ndarray, max_cost: int,
                  unknown_blocks: bool = False) -> tuple[int, int] | None:
    """(index, cost) of the first pose of ``poses`` (N, 3) whose cell costs more than
    ``max_cost``; None if there is none. Poses off the map are skipped; an unknown cell blocks
    only with ``unknown_blocks``."""
    for i, (x, y, _) in enumerate(poses):
        cell = costmap.world_to_map(float(x), float(y))
        if cell is None:
            continue
        cost = int(costmap.costs[cell[1], cell[0]])
        if cost == NO_INFORMATION and not unknown_blocks:
            continue
        if cost > max_cost:
            return i, cost
    return None
