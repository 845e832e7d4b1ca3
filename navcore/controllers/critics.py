"""DWA's critic chain (dwa_local_planner's ScoredSamplingPlanner) in one numba kernel.

Cost of a trajectory = sum over critics of scale x cost, critics with scale 0 skipped, any negative
critic cost rejecting it. The critics, as dwa_planner.cpp chains them:

======================= ============================= =========================================
oscillation             1                             -5 if the sample breaks a direction latch
obstacle                ``occdist_scale``             max footprint cost over the points
goal_front              ``goal_distance_bias * res``  local-goal grid (goal pushed ahead) at the
                                                      last point shifted ``forward_point_distance``
alignment               ``path_distance_bias * res``  path grid at the shifted last point
                                                      (0 near the goal)
path                    ``path_distance_bias * res``  path grid at the last point
goal                    ``goal_distance_bias * res``  local-goal grid at the last point
twirling                ``twirling_scale``            abs(vth)
======================= ============================= =========================================

Rejection codes (the ROS ones): -2 a point has no way to the path or goal, -3 a point sits on an
obstacle in a grid, -4 a point (or its shifted twin) is off the map, -5 oscillation, -6 the
footprint touches a lethal or unknown cell, -7 the footprint leaves the map.

Departures from ROS, toward safety: a centre cell that is lethal or unknown rejects the
trajectory (-6) like a footprint cell does, and the obstacle critic rejects lethal trajectories
even when ``occdist_scale`` is 0.

Speed: the grid critics cost a lookup per point, the footprint a raster per point. The kernel
judges trajectories best-first on bounds that only grow toward the true cost (the grid critics
at the last point; all points plus the worst centre cell; the footprints) and stops once no
trajectory left can beat the best (branch and bound). The choice is the one ROS makes (lowest
total, ties to the earliest sample); the score of a pruned trajectory is the bound reached when
it was dropped, as ROS's own early exit reports. A footprint is rasterised only where the
costmap's max over the footprint's reach (``square_max``) says it could raise the cost. The
critics are inlined into the one kernel: a call taking arrays costs more than their work.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from navcore.costmap.cost_values import LETHAL_OBSTACLE
from navcore.costmap.footprint import footprint_cost, reach_of


class DwaWeights(NamedTuple):
    """The DWA critics' scales of one cycle, by name; ``array()`` is the float64 array the
    kernels take, in this order (the ``W_*`` indices below)."""

    occdist: float
    goal_front: float
    alignment: float
    path: float
    goal: float
    twirling: float
    forward_point_distance: float
    scaling_speed: float
    max_vel_trans: float
    max_scaling_factor: float
    sum_scores: float  # 1.0: sum the critics' scores (ROS sum_scores), 0.0: as ROS default

    def array(self) -> np.ndarray:
        return np.array(self, dtype=np.float64)


# positions in DwaWeights.array() (module constants: compile-time constants in the kernels)
(W_OCCDIST, W_GOAL_FRONT, W_ALIGNMENT, W_PATH, W_GOAL, W_TWIRLING, W_FORWARD_POINT_DISTANCE,
 W_SCALING_SPEED, W_MAX_VEL_TRANS, W_MAX_SCALING_FACTOR, W_SUM_SCORES) = range(11)

SCORED, PRUNED, REJECTED = 0, 1, 2


@njit(cache=True, nogil=True)
def grid_critic(pts: np.ndarray, k: int, n: int, grid: np.ndarray, origin_x: float,
                origin_y: float, resolution: float, xshift: float, stop_on_failure: bool) -> float:
    """MapGridCostFunction with aggregation Last: grid value at the last point, negative codes
    for points off the map (-4) and, with ``stop_on_failure``, on obstacles (-3) or cut off (-2).

    One critic at a time, as ROS chains them: the reference that ``grid_critics`` (all four in
    one pass, what the planner runs) is tested against.
    """
    size_y, size_x = grid.shape
    obstacle = size_x * size_y
    value = 0.0
    for i in range(n):
        px = pts[k, i, 0]
        py = pts[k, i, 1]
        if xshift != 0.0:
            th = pts[k, i, 2]
            px += xshift * math.cos(th)
            py += xshift * math.sin(th)
        if px < origin_x or py < origin_y:
            return -4.0
        mx = int((px - origin_x) / resolution)
        my = int((py - origin_y) / resolution)
        if mx >= size_x or my >= size_y:
            return -4.0
        d = grid[my, mx]
        if stop_on_failure:
            if d == obstacle:
                return -3.0
            if d == obstacle + 1:
                return -2.0
        value = d
    return value


@njit(cache=True, nogil=True, inline="always")
def oscillation_critic(vx: float, vy: float, vth: float, flags: np.ndarray) -> float:
    """-5 when a latched "only this direction" flag forbids the sample, else 0.

    ``flags``: forward_pos_only, forward_neg_only, strafe_pos_only, strafe_neg_only,
    rot_pos_only, rot_neg_only.
    """
    if ((flags[0] and vx < 0.0) or (flags[1] and vx > 0.0) or (flags[2] and vy < 0.0)
            or (flags[3] and vy > 0.0) or (flags[4] and vth < 0.0) or (flags[5] and vth > 0.0)):
        return -5.0
    return 0.0


@njit(cache=True, nogil=True, inline="always")
def footprint_scale(vx: float, vy: float, scaling_speed: float, max_vel_trans: float,
                    max_scaling_factor: float) -> float:
    """ObstacleCostFunction::getScalingFactor: grow the footprint above ``scaling_speed``."""
    vmag = math.hypot(vx, vy)
    if vmag > scaling_speed and max_vel_trans > scaling_speed:
        return 1.0 + max_scaling_factor * (vmag - scaling_speed) / (max_vel_trans - scaling_speed)
    return 1.0


@njit(cache=True, nogil=True, inline="always")
def grid_critics(pts: np.ndarray, nose: np.ndarray, k: int, n: int, origin_x: float,
                 origin_y: float, resolution: float, path_grid: np.ndarray,
                 goal_grid: np.ndarray, front_grid: np.ndarray, weights: np.ndarray,
                 costs: np.ndarray, start: int = 0) -> tuple[float, int]:
    """The four map-grid critics of trajectory ``k`` in one pass over its points: the weighted
    sum, or the first critic's negative code in chain order (goal_front, alignment, path, goal);
    and the worst centre-cell cost seen, a lower bound of the obstacle critic for free.

    With ``start = n - 1`` only the last point is judged: the sum is then already exact for a
    valid trajectory (aggregation Last), which makes it a cheap first bound.

    Same results as ``grid_critic`` called once per critic (aggregation Last; goal_front and
    alignment at the nose points without stop_on_failure; path and goal with it).
    """
    front_s = weights[W_GOAL_FRONT]
    align_s = weights[W_ALIGNMENT]
    path_s = weights[W_PATH]
    goal_s = weights[W_GOAL]
    size_y, size_x = path_grid.shape
    obstacle = size_x * size_y
    inv = 1.0 / resolution
    use_nose = front_s != 0.0 or align_s != 0.0
    need_path = path_s != 0.0
    need_goal = goal_s != 0.0
    # a code per critic; the chain reports the first critic (in order) that failed
    c_nose = 0.0
    c_path = 0.0
    c_goal = 0.0
    v_front = 0.0
    v_align = 0.0
    v_path = 0.0
    v_goal = 0.0
    cmax = 0
    track = costs.shape[0] == size_y and costs.shape[1] == size_x  # an empty costs: no centres
    for i in range(start, n):
        if use_nose and c_nose == 0.0:
            px = nose[k, i, 0]
            py = nose[k, i, 1]
            mx = int((px - origin_x) * inv)
            my = int((py - origin_y) * inv)
            if px < origin_x or py < origin_y or mx >= size_x or my >= size_y:
                c_nose = -4.0  # both nose critics go off the map together
            else:
                v_front = front_grid[my, mx]
                v_align = path_grid[my, mx]
        if (need_path and c_path == 0.0) or (need_goal and c_goal == 0.0):
            px = pts[k, i, 0]
            py = pts[k, i, 1]
            mx = int((px - origin_x) * inv)
            my = int((py - origin_y) * inv)
            if px < origin_x or py < origin_y or mx >= size_x or my >= size_y:
                if c_path == 0.0:
                    c_path = -4.0
                if c_goal == 0.0:
                    c_goal = -4.0
            else:
                if track:
                    cc = costs[my, mx]
                    if cc > cmax:
                        cmax = cc
                if c_path == 0.0:
                    dp = path_grid[my, mx]
                    if dp == obstacle:
                        c_path = -3.0
                    elif dp == obstacle + 1:
                        c_path = -2.0
                    else:
                        v_path = dp
                if c_goal == 0.0:
                    dg = goal_grid[my, mx]
                    if dg == obstacle:
                        c_goal = -3.0
                    elif dg == obstacle + 1:
                        c_goal = -2.0
                    else:
                        v_goal = dg
    c_front = c_nose
    c_align = c_nose
    if front_s != 0.0 and c_front < 0:
        return c_front, cmax
    if align_s != 0.0 and c_align < 0:
        return c_align, cmax
    if path_s != 0.0 and c_path < 0:
        return c_path, cmax
    if goal_s != 0.0 and c_goal < 0:
        return c_goal, cmax
    return front_s * v_front + align_s * v_align + path_s * v_path + goal_s * v_goal, cmax


COARSE = 4  # the first footprint pass checks every 4th point


@njit(cache=True, nogil=True, inline="always")
def _fold(cost: float, c: float, sum_scores: bool) -> float:
    """The obstacle critic's running cost with one more point's: summed or the max."""
    return cost + c if sum_scores else max(cost, c)


@njit(cache=True, nogil=True, inline="always")
def obstacle_critic(pts: np.ndarray, k: int, n: int, costs: np.ndarray, origin_x: float,
                    origin_y: float, resolution: float, footprint: np.ndarray, sum_scores: bool,
                    base: float, scale: float, budget: float, phase: int, cost: float,
                    bound: np.ndarray, reach: int) -> float:
    """Worst (or summed) footprint cost over the points; -6 / -7 on lethal or off-map.

    The centre cell counts too (ROS takes the max of the footprint and the centre cell). Phase 0
    visits every COARSE-th point from the far end (where a lethal cell usually is), phase 1 the
    others; ``cost`` carries phase 0's result into phase 1, and the two phases together give the
    full critic (max and sum ignore order). Stops early, returning the partial cost, once
    ``base + scale * cost`` exceeds ``budget``.

    ``bound`` (``square_max`` of the costs at ``reach`` cells, which must hold the footprint;
    reach < 0: none) skips the rasterising where it cannot change the result: the footprint
    then lies on the map, below lethal, and no higher than the centre cell (sum) or than the
    cost so far (max).
    """
    size_y, size_x = costs.shape
    for i in range(n - 1, -1, -1):
        if ((n - 1 - i) % COARSE == 0) != (phase == 0):
            continue
        px = pts[k, i, 0]
        py = pts[k, i, 1]
        if reach >= 0 and px >= origin_x and py >= origin_y:
            mx = int((px - origin_x) / resolution)
            my = int((py - origin_y) / resolution)
            if (reach <= mx < size_x - reach and reach <= my < size_y - reach
                    and bound[my, mx] < LETHAL_OBSTACLE):
                c = costs[my, mx]
                if bound[my, mx] <= (c if sum_scores else max(c, cost)):
                    cost = _fold(cost, c, sum_scores)
                    if base + scale * cost > budget:
                        return cost
                    continue
        f = footprint_cost(costs, origin_x, origin_y, resolution, footprint, px, py,
                           pts[k, i, 2])
        if f < 0:
            return -7.0
        if f >= LETHAL_OBSTACLE:
            return -6.0
        if px < origin_x or py < origin_y:
            return -7.0
        mx = int((px - origin_x) / resolution)
        my = int((py - origin_y) / resolution)
        if mx >= size_x or my >= size_y:
            return -7.0
        cost = _fold(cost, max(f, costs[my, mx]), sum_scores)
        if base + scale * cost > budget:
            return cost
    return cost


@njit(cache=True, nogil=True, inline="always")
def _heap_push(keys: np.ndarray, ids: np.ndarray, size: int, key: float, k: int) -> int:
    """Push (key, k) on the binary min-heap held in ``keys``/``ids``; ties order by k. New size."""
    i = size
    while i > 0:
        parent = (i - 1) // 2
        if keys[parent] < key or (keys[parent] == key and ids[parent] < k):
            break
        keys[i] = keys[parent]
        ids[i] = ids[parent]
        i = parent
    keys[i] = key
    ids[i] = k
    return size + 1


@njit(cache=True, nogil=True, inline="always")
def _heap_pop(keys: np.ndarray, ids: np.ndarray, size: int) -> int:
    """Remove the smallest entry (read it from keys[0], ids[0] first). New size."""
    size -= 1
    key = keys[size]
    k = ids[size]
    i = 0
    while True:
        child = 2 * i + 1
        if child >= size:
            break
        if child + 1 < size and (keys[child + 1] < keys[child] or (
                keys[child + 1] == keys[child] and ids[child + 1] < ids[child])):
            child += 1
        if key < keys[child] or (key == keys[child] and k < ids[child]):
            break
        keys[i] = keys[child]
        ids[i] = ids[child]
        i = child
    keys[i] = key
    ids[i] = k
    return size


@njit(cache=True, nogil=True)
def score_dwa(pts: np.ndarray, nose: np.ndarray, steps: np.ndarray, vels: np.ndarray,
              costs: np.ndarray, origin_x: float, origin_y: float, resolution: float,
              footprint: np.ndarray, path_grid: np.ndarray, goal_grid: np.ndarray,
              front_grid: np.ndarray, weights: np.ndarray, flags: np.ndarray, exhaustive: bool,
              bound: np.ndarray, reach: int) -> tuple[np.ndarray, np.ndarray, int]:
    """Score every trajectory; return (scores, state per trajectory, best index or -1).

    ``nose``: the points ``forward_point_distance`` ahead (from ``simulate``).
    ``weights``: ``DwaWeights.array()``.
    ``state``: SCORED, PRUNED (score is a lower bound) or REJECTED (score is the code).
    With ``exhaustive`` every trajectory is scored in full (for drawing and for tests).
    ``bound``, ``reach``: see ``obstacle_critic`` (a 0 x 0 ``bound``: rasterise every footprint);
    the same results either way.

    Bounds that never exceed the true cost let most trajectories stop early: the grid critics at
    the last point (one lookup each), then over all points plus the worst centre cell, then the
    footprints, checked far end first and every 4th point before the rest so that a lethal cell or
    a blown budget shows up soon.
    """
    occ_s = weights[W_OCCDIST]
    twirl_s = weights[W_TWIRLING]
    sum_scores = weights[W_SUM_SCORES] != 0.0
    k_n = pts.shape[0]
    scores = np.zeros(k_n)
    state = np.zeros(k_n, dtype=np.int8)
    cheap = np.full(k_n, np.inf)
    no_costs = costs[:0, :0]
    use_bound = bound.shape[0] == costs.shape[0] and bound.shape[1] == costs.shape[1]
    base_of = np.zeros(k_n)  # the cost of everything but the footprint
    # stage 0: oscillation and the last point
    for k in range(k_n):
        vth = vels[k, 2]
        c = oscillation_critic(vels[k, 0], vels[k, 1], vth, flags)
        if c >= 0:
            c = grid_critics(pts, nose, k, steps[k], origin_x, origin_y, resolution, path_grid,
                             goal_grid, front_grid, weights, no_costs, steps[k] - 1)[0]
        if c < 0:
            scores[k] = c
            state[k] = REJECTED
            continue
        cheap[k] = c + twirl_s * abs(vth)
        scores[k] = cheap[k]
    order = np.argsort(cheap, kind="mergesort")
    best = -1
    best_cost = np.inf
    # best first: a trajectory is refined (grid critics over all points, then its footprints)
    # only while its bound is the lowest of all bounds known (heap) or knowable (the next cheap
    # bound, which every later trajectory reaches). Bounds never exceed the final cost, even in
    # floating point: each level adds to the same base.
    heap_keys = np.empty(k_n)
    heap_ids = np.empty(k_n, dtype=np.int64)
    heap_n = 0
    level_of = np.zeros(k_n, dtype=np.int8)  # 1 once a trajectory's grid pass is done
    partial = np.zeros(k_n)
    j = 0
    while True:
        next_cheap = np.inf
        if j < k_n and state[order[j]] != REJECTED:
            next_cheap = cheap[order[j]]
        if heap_n > 0 and heap_keys[0] <= next_cheap:
            b2 = heap_keys[0]
            k = heap_ids[0]
            level = level_of[k]
            heap_n = _heap_pop(heap_keys, heap_ids, heap_n)
        elif next_cheap < np.inf:
            k = order[j]
            j += 1
            b2, level = cheap[k], 0
        else:
            break
        # a tie goes to the earlier sample, as in ROS's strict comparison in sample order
        if not exhaustive and best >= 0 and (b2 > best_cost or (b2 == best_cost and k > best)):
            scores[k] = b2
            state[k] = PRUNED
            if level == 0:  # every later cheap bound is at least as high
                for jj in range(j, k_n):
                    if state[order[jj]] != REJECTED:
                        state[order[jj]] = PRUNED
                j = k_n
            continue
        budget = np.inf if (exhaustive or best < 0) else best_cost
        if level == 0:  # the grid critics over every point, and the centre cells
            c, cmax = grid_critics(pts, nose, k, steps[k], origin_x, origin_y, resolution,
                                   path_grid, goal_grid, front_grid, weights, costs, 0)
            if c >= 0 and cmax >= LETHAL_OBSTACLE:
                c = -6.0  # the centre cell lies inside the footprint
            if c < 0:
                scores[k] = c
                state[k] = REJECTED
                continue
            base_of[k] = c + twirl_s * abs(vels[k, 2])
            partial[k] = cmax
            scores[k] = base_of[k] + occ_s * cmax
            level_of[k] = 1
            heap_n = _heap_push(heap_keys, heap_ids, heap_n, scores[k], k)
            continue
        fp = footprint
        s = footprint_scale(vels[k, 0], vels[k, 1], weights[W_SCALING_SPEED],
                            weights[W_MAX_VEL_TRANS], weights[W_MAX_SCALING_FACTOR])
        if s != 1.0:
            fp = footprint * s
        reach_k = -1
        if use_bound:
            r2 = 0.0
            for v in range(fp.shape[0]):
                r2 = max(r2, fp[v, 0] * fp[v, 0] + fp[v, 1] * fp[v, 1])
            if reach_of(math.sqrt(r2), resolution) <= reach:  # the bound holds this footprint
                reach_k = reach
        base = base_of[k]
        o = obstacle_critic(pts, k, steps[k], costs, origin_x, origin_y, resolution, fp,
                            sum_scores, base, occ_s, budget, 0, 0.0 if sum_scores else partial[k],
                            bound, reach_k)
        if o >= 0 and base + occ_s * o <= budget:
            o = obstacle_critic(pts, k, steps[k], costs, origin_x, origin_y, resolution, fp,
                                sum_scores, base, occ_s, budget, 1, o, bound, reach_k)
        if o < 0:
            scores[k] = o
            state[k] = REJECTED
            continue
        scores[k] = base + occ_s * o
        total = scores[k]
        if total > budget or (total == budget and k > best):
            state[k] = PRUNED
            continue
        if best < 0 or total < best_cost or (total == best_cost and k < best):
            best = k
            best_cost = total
    return scores, state, best
