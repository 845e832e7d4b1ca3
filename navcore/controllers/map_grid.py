"""base_local_planner's MapGrid: cell distances to the global path and to the local goal.

Every control cycle the plan part that lies in the local costmap is densified to the costmap
resolution and seeds a 4-neighbour breadth-first wavefront (one cell = distance 1). Lethal,
inscribed and unknown cells stop the wave and read ``obstacle`` (= the number of cells); cells the
wave never reaches read ``unreachable`` (= cells + 1). Also here: how the global plan is cut to the
local costmap (transformGlobalPlan) and pruned behind the robot (prunePlan).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from navcore.costmap.cost_values import (INSCRIBED_INFLATED_OBSTACLE, LETHAL_OBSTACLE,
                                         NO_INFORMATION)


@njit(cache=True, nogil=True)
def densify_plan(poses: np.ndarray, resolution: float) -> np.ndarray:
    """adjustPlanResolution: insert evenly spaced points so no gap exceeds ``resolution``.

    Inserted points copy the heading of the segment's start (ROS does not interpolate it).
    """
    n = poses.shape[0]
    if n < 2:
        return poses.copy()
    r2 = resolution * resolution
    steps = np.ones(n - 1, dtype=np.int64)
    total = 1
    for i in range(1, n):
        dx = poses[i, 0] - poses[i - 1, 0]
        dy = poses[i, 1] - poses[i - 1, 1]
        d2 = dx * dx + dy * dy
        if d2 > r2:
            steps[i - 1] = int(math.ceil(math.sqrt(d2) / resolution))
        total += steps[i - 1]
    out = np.empty((total, 3))
    # rows copied element by element: a row assignment pulls in numba's shape-error message
    # formatting (about 2 s of compiling on the first run)
    for c in range(3):
        out[0, c] = poses[0, c]
    k = 1
    for i in range(1, n):
        m = steps[i - 1]
        dx = (poses[i, 0] - poses[i - 1, 0]) / m
        dy = (poses[i, 1] - poses[i - 1, 1]) / m
        for j in range(1, m):
            out[k, 0] = poses[i - 1, 0] + j * dx
            out[k, 1] = poses[i - 1, 1] + j * dy
            out[k, 2] = poses[i - 1, 2]
            k += 1
        for c in range(3):
            out[k, c] = poses[i, c]
        k += 1
    return out


def local_plan(poses: np.ndarray, x: float, y: float, size_m: float) -> np.ndarray:
    """transformGlobalPlan: the first run of plan poses within half the costmap's larger side of
    the robot (skip the poses before it, stop at the first one beyond)."""
    poses = np.asarray(poses, dtype=np.float64).reshape(-1, 3)
    first, end = _first_run_within(poses, x, y, (size_m / 2.0) ** 2)
    return poses[first:end]


@njit(cache=True, nogil=True)
def _first_run_within(poses: np.ndarray, x: float, y: float, r2: float) -> tuple[int, int]:
    """[first, end) of the first run of poses within squared distance ``r2`` of (x, y);
    (0, 0) when none is. A kernel: the numpy version cost tens of microseconds per cycle."""
    n = poses.shape[0]
    first = -1
    for i in range(n):
        dx = poses[i, 0] - x
        dy = poses[i, 1] - y
        inside = dx * dx + dy * dy <= r2
        if first < 0:
            if inside:
                first = i
        elif not inside:
            return first, i
    if first < 0:
        return 0, 0
    return first, n


def prune_plan(poses: np.ndarray, x: float, y: float) -> np.ndarray:
    """prunePlan: drop poses from the front until the first one within 1 m of the robot."""
    poses = np.asarray(poses, dtype=np.float64).reshape(-1, 3)
    near = (poses[:, 0] - x) ** 2 + (poses[:, 1] - y) ** 2 < 1.0
    if not near.any():
        return poses[:0]
    return poses[int(np.argmax(near)):]


@njit(cache=True, nogil=True)
def plan_cells(costs: np.ndarray, origin_x: float, origin_y: float, resolution: float,
               plan: np.ndarray) -> np.ndarray:
    """Cells (mx, my) of the densified plan's first run on the map and not unknown, (K, 2) int64.

    The path grid seeds all of them; the local goal is the last one.
    """
    size_y, size_x = costs.shape
    out = np.empty((plan.shape[0], 2), dtype=np.int64)
    k = 0
    started = False
    for i in range(plan.shape[0]):
        wx = plan[i, 0]
        wy = plan[i, 1]
        ok = wx >= origin_x and wy >= origin_y
        if ok:
            mx = int((wx - origin_x) / resolution)
            my = int((wy - origin_y) / resolution)
            ok = mx < size_x and my < size_y and costs[my, mx] != NO_INFORMATION
        if ok:
            out[k, 0] = mx
            out[k, 1] = my
            k += 1
            started = True
        elif started:
            break
    return out[:k]


@njit(cache=True, nogil=True)
def distance_grid(costs: np.ndarray, seeds: np.ndarray, passable: np.ndarray) -> np.ndarray:
    """Breadth-first cell distance from ``seeds`` ((K, 2) mx, my), int32 indexed [my, mx].

    Blocked cells (lethal, inscribed, unknown) that the wave touches get ``size``; untouched cells
    ``size + 1``. ``passable`` ([my, mx] bool, may be 0x0) marks cells never blocked (the
    trajectory rollout planner's robot footprint at the start). Breadth-first order makes the
    first label of a cell its distance, as the ROS queue does.
    """
    size_y, size_x = costs.shape
    n = size_x * size_y
    flat = costs.reshape(n)  # reshape, not ravel: same view, far less to compile
    use_pass = passable.shape[0] == size_y and passable.shape[1] == size_x
    pas = passable.reshape(passable.size)
    dist = np.full(n, n + 1, dtype=np.int32)
    queue = np.empty(n, dtype=np.int32)
    qx = np.empty(n, dtype=np.int32)  # each queued cell's column: no division to find it
    tail = 0
    for i in range(seeds.shape[0]):
        j = seeds[i, 1] * size_x + seeds[i, 0]
        if dist[j] != 0:
            dist[j] = 0
            queue[tail] = j
            qx[tail] = seeds[i, 0]
            tail += 1
    head = 0
    while head < tail:
        j = queue[head]
        cx = qx[head]
        head += 1
        nd = dist[j] + 1
        # the four neighbours, written out: a helper call per neighbour costs more than the work
        for side in range(4):
            if side == 0:
                if cx == 0:
                    continue
                k = j - 1
            elif side == 1:
                if cx == size_x - 1:
                    continue
                k = j + 1
            elif side == 2:
                if j < size_x:
                    continue
                k = j - size_x
            else:
                if j >= n - size_x:
                    continue
                k = j + size_x
            if dist[k] != n + 1:
                continue
            c = flat[k]
            if (c == LETHAL_OBSTACLE or c == INSCRIBED_INFLATED_OBSTACLE or c == NO_INFORMATION) \
                    and not (use_pass and pas[k]):
                dist[k] = n
                continue
            dist[k] = nd
            queue[tail] = k
            qx[tail] = cx - 1 if side == 0 else (cx + 1 if side == 1 else cx)
            tail += 1
    return dist.reshape(size_y, size_x)


def path_and_goal_grids(costs: np.ndarray, origin_x: float, origin_y: float, resolution: float,
                        plan: np.ndarray, passable: np.ndarray | None = None
                        ) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
    """(path grid, local-goal grid, plan cells) for a local plan, or None when no plan cell is
    on the map (ROS logs "None of the points of the global plan were in the local costmap")."""
    dense = densify_plan(plan, resolution)
    cells = plan_cells(costs, origin_x, origin_y, resolution, dense)
    if len(cells) == 0:
        return None
    pas = np.zeros((0, 0), dtype=np.bool_) if passable is None else passable
    path = distance_grid(costs, cells, pas)
    goal = distance_grid(costs, cells[-1:], pas)
    return path, goal, cells


def goal_grid(costs: np.ndarray, origin_x: float, origin_y: float, resolution: float,
              plan: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
    """Local-goal grid and its seed cell alone (for DWA's forward-shifted goal plan)."""
    cells = plan_cells(costs, origin_x, origin_y, resolution, densify_plan(plan, resolution))
    if len(cells) == 0:
        return None
    return distance_grid(costs, cells[-1:], np.zeros((0, 0), dtype=np.bool_)), cells[-1]


def cell_of(x: float, y: float, origin_x: float, origin_y: float, resolution: float,
            size_x: int, size_y: int) -> tuple[int, int] | None:
    """worldToMap (truncation toward the origin corner; None off the grid)."""
    if x < origin_x or y < origin_y or not (math.isfinite(x) and math.isfinite(y)):
        return None
    mx, my = int((x - origin_x) / resolution), int((y - origin_y) / resolution)
    if mx >= size_x or my >= size_y:
        return None
    return mx, my
