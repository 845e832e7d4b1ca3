"""What blocks the route on the map, and when the sensors last saw it.

A plan much longer than the route on the static map alone goes round something the sensors
put in the costmap. Whether that is worth clearing depends on how old it is: cells a beam ended
in a moment ago are an obstacle standing there now; cells nobody has seen for a while may be
gone (a door opened, a cart moved) and only the costmap remembers them. The cells are the
sensed lethal cells (obstacle and voxel layers) near the map-only route; their age comes from
the observed-space memory (``navcore.costmap.observed_space``), which keeps the last time a beam
ended in each cell whatever the costmaps clear. A cell outside its window, or never seen
occupied (a phantom), counts as never seen.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from navcore.costmap.cost_values import LETHAL_OBSTACLE
from navcore.types import Path


def blocking_cells(layered: Any, route: Path, radius: float) -> np.ndarray:
    """World centres (N, 2) of the sensed lethal cells within ``radius`` m (a square, per
    route pose every cell along it) of the ``route``: what stands in the map-only way."""
    found = []
    for layer in layered.obstacle_layers():
        g = layer.grid
        res = g.resolution
        poses = np.asarray(route.poses, dtype=float)
        if len(poses) == 0:
            continue
        # one route pose a cell (the path's spacing may be finer)
        steps = np.hypot(*np.diff(poses[:, :2], axis=0).T) if len(poses) > 1 else np.zeros(0)
        s = np.concatenate([[0.0], np.cumsum(steps)])
        keep = np.unique(np.searchsorted(s, np.arange(0.0, s[-1] + 1e-9, res)))
        keep = keep[keep < len(poses)]
        k = int(math.ceil(radius / res))
        mask = np.zeros(g.costs.shape, bool)
        cx = np.floor((poses[keep, 0] - g.origin_x) / res).astype(np.int64)
        cy = np.floor((poses[keep, 1] - g.origin_y) / res).astype(np.int64)
        for x, y in zip(cx, cy):
            x0, x1 = max(x - k, 0), min(x + k + 1, g.size_x)
            y0, y1 = max(y - k, 0), min(y + k + 1, g.size_y)
            if x0 < x1 and y0 < y1:
                mask[y0:y1, x0:x1] = True
        ys, xs = np.nonzero(mask & (g.costs == LETHAL_OBSTACLE))
        found.append(np.column_stack([g.origin_x + (xs + 0.5) * res,
                                      g.origin_y + (ys + 0.5) * res]))
    if not found:
        return np.zeros((0, 2))
    return np.unique(np.concatenate(found), axis=0)


def last_seen_occupied(observed: Any, xy: np.ndarray) -> float:
    """The newest time a beam ended in one of the cells at ``xy`` (N, 2), or in a cell next to
    one (the memory's grid need not be the costmap's), according to the observed-space memory
    ``observed``; -inf when none was seen (or none is in its window)."""
    if observed is None or len(xy) == 0:
        return -math.inf
    res = observed.resolution
    mx = np.floor((xy[:, 0] - observed.origin_x) / res).astype(np.int64)
    my = np.floor((xy[:, 1] - observed.origin_y) / res).astype(np.int64)
    newest = -math.inf
    for dx in (-1, 0, 1):
        for dy in (-1, 0, 1):
            x, y = mx + dx, my + dy
            inside = (x >= 0) & (y >= 0) & (x < observed.size_x) & (y < observed.size_y)
            if inside.any():
                newest = max(newest, float(np.max(observed.occupied[y[inside], x[inside]])))
    return newest
