"""Cells a costmap clear erased, and when: an obstacle the sensors mark again soon after a clear
is confirmed, and later clears keep it.

Without it a plan-clear-replan loop never ends when a sensed obstacle really blocks the way: the
planner fails, a clear erases the obstacle, the next plan goes through it, the robot drives up,
sees it again, the planner fails... and the mission ends on whatever times out first instead of
the planner's NO_VALID_PATH. With it, the second clear within ``window`` seconds of the first
keeps every cell the first one erased and the sensors have marked again since; those stay
until the sensors see through them (raytracing clears them as any other obstacle cell).

Cells are kept by world lattice index (cell index plus the grid origin in cells), so a rolling
costmap that moved between two clears still matches them.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from navcore.costmap.cost_values import LETHAL_OBSTACLE


def _lattice_offset(grid: Any) -> tuple[int, int]:
    return (int(round(grid.origin_x / grid.resolution)),
            int(round(grid.origin_y / grid.resolution)))


def sensed_lethal_keys(layered: Any) -> np.ndarray:
    """(N, 2) int64 world lattice keys (x, y) of the lethal cells of ``layered``'s obstacle and
    voxel layers (what the sensors marked; the static map is not in them)."""
    keys = []
    for layer in layered.obstacle_layers():
        g = layer.grid
        ys, xs = np.nonzero(g.costs == LETHAL_OBSTACLE)
        ox, oy = _lattice_offset(g)
        keys.append(np.column_stack([xs.astype(np.int64) + ox, ys.astype(np.int64) + oy]))
    if not keys:
        return np.zeros((0, 2), np.int64)
    return np.unique(np.concatenate(keys), axis=0)


def _in(keys: np.ndarray, among: np.ndarray) -> np.ndarray:
    """Boolean mask of the rows of ``keys`` that are rows of ``among``."""
    if len(keys) == 0 or len(among) == 0:
        return np.zeros(len(keys), bool)
    k = keys[:, 0] * (1 << 32) + keys[:, 1]
    a = among[:, 0] * (1 << 32) + among[:, 1]
    return np.isin(k, a)


class ClearMemory:
    """What the clears of one costmap erased. Call ``clear(layered, now, do_clear)`` in place of
    a bare clear: it confirms, clears, and puts the confirmed cells back."""

    def __init__(self, window: float = 10.0) -> None:
        if not window >= 0.0:
            raise ValueError(f"ClearMemory: window must be >= 0 s, got {window!r}")
        self.window = float(window)
        self.erased = np.zeros((0, 2), np.int64)    # keys the last clear erased
        self.erased_at = -np.inf
        self.confirmed = np.zeros((0, 2), np.int64)

    def confirm(self, layered: Any, now: float) -> np.ndarray:
        """Keys erased by the last clear (at most ``window`` s ago) that the sensors have marked
        again; they join ``confirmed``. Returns the newly confirmed keys."""
        lethal = sensed_lethal_keys(layered)
        if now - self.erased_at > self.window:
            new = np.zeros((0, 2), np.int64)
        else:
            new = self.erased[_in(self.erased, lethal)]
        # confirmed cells the sensors have since seen through (raytraced free) are forgotten
        self.confirmed = self.confirmed[_in(self.confirmed, lethal)]
        if len(new):
            self.confirmed = np.unique(np.concatenate([self.confirmed, new]), axis=0)
        return new

    def clear(self, layered: Any, now: float, do_clear: Any) -> int:
        """Confirm, remember what is lethal now, run ``do_clear()`` (the costmap's own clear) and
        mark the confirmed cells lethal again in the obstacle layers. Returns how many
        confirmed cells were kept."""
        self.confirm(layered, now)
        self.erased = sensed_lethal_keys(layered)
        self.erased_at = now
        do_clear()
        return self.restore(layered)

    def restore(self, layered: Any) -> int:
        """Mark ``confirmed`` lethal in the first obstacle layer (cells on its grid) and redraw
        the master. Returns how many were marked."""
        layers = layered.obstacle_layers()
        if not layers or len(self.confirmed) == 0:
            return 0
        g = layers[0].grid
        ox, oy = _lattice_offset(g)
        xs = self.confirmed[:, 0] - ox
        ys = self.confirmed[:, 1] - oy
        ok = (xs >= 0) & (xs < g.size_x) & (ys >= 0) & (ys < g.size_y)
        g.costs[ys[ok], xs[ok]] = LETHAL_OBSTACLE
        layers[0].add_extra_bounds(g.origin_x, g.origin_y, g.origin_x + g.size_x * g.resolution,
                                   g.origin_y + g.size_y * g.resolution)
        pose = getattr(layered, "_last_pose", None)
        if pose is not None:
            layered.update_map(pose)
        return int(np.count_nonzero(ok))


def memory_of(layered: Any, window: float) -> ClearMemory:
    """The ClearMemory kept on ``layered`` (made on first use; ``window`` follows the caller)."""
    mem = getattr(layered, "clear_memory", None)
    if mem is None:
        mem = ClearMemory(window)
        layered.clear_memory = mem
    mem.window = float(window)
    return mem
