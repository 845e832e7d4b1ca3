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

Speed: the grid critics cost a lookup per point, the footprint a raster per point. The kernel
scores the grid critics of every trajectory first, then evaluates footprints in order of that
lower bound and stops once no remaining trajectory can beat the best (branch and bound). The
choice is the one ROS makes (lowest total, ties to the earliest sample); the score of a pruned
trajectory is the lower bound reached when it was dropped, as ROS's own early exit reports.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from navcore.costmap.cost_values import LETHAL_OBSTACLE
from navcore.costmap.footprint import footprint_cost

SCORED, PRUNED, REJECTED = 0, 1, 2


@njit(cache=True, nogil=True)
def grid_critic(pts: np.ndarray, k: int, n: int, grid: np.ndarray, origin_x: float,
                origin_y: float, resolution: float, xshift: float, stop_on_failure: bool) -> float:
    """MapGridCostFunction with aggregation Last: grid value at the last point, negative codes
    for points off the map (-4) and, with ``stop_on_failure``, on obstacles (-3) or cut off (-2)."""
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


@njit(cache=True, nogil=True)
def oscillation_critic(vx: float, vy: float, vth: float, flags: np.ndarray) -> float:
    """-5 when a latched "only this direction" flag forbids the sample, else 0.

    ``flags``: forward_pos_only, forward_neg_only, strafe_pos_only, strafe_neg_only,
    rot_pos_only, rot_neg_only.
    """
    if ((flags[0] and vx < 0.0) or (flags[1] and vx > 0.0) or (flags[2] and vy < 0.0)
            or (flags[3] and vy > 0.0) or (flags[4] and vth < 0.0) or (flags[5] and vth > 0.0)):
        return -5.0
    return 0.0


@njit(cache=True, nogil=True)
def footprint_scale(vx: float, vy: float, scaling_speed: float, max_vel_trans: float,
                    max_scaling_factor: float) -> float:
    """ObstacleCostFunction::getScalingFactor: grow the footprint above ``scaling_speed``."""
    vmag = math.hypot(vx, vy)
    if vmag > scaling_speed and max_vel_trans > scaling_speed:
        return 1.0 + max_scaling_factor * (vmag - scaling_speed) / (max_vel_trans - scaling_speed)
    return 1.0


@njit(cache=True, nogil=True)
def obstacle_critic(pts: np.ndarray, k: int, n: int, costs: np.ndarray, origin_x: float,
                    origin_y: float, resolution: float, footprint: np.ndarray, sum_scores: bool,
                    base: float, scale: float, budget: float) -> float:
    """Worst (or summed) footprint cost over the points; -6 / -7 on lethal or off-map.

    Stops early, returning the partial cost, once ``base + scale * cost`` exceeds ``budget``.
    The centre cell counts too (ROS takes the max of the footprint and the centre cell).
    """
    size_y, size_x = costs.shape
    cost = 0.0
    for i in range(n):
        px = pts[k, i, 0]
        py = pts[k, i, 1]
        f = footprint_cost(costs, origin_x, origin_y, resolution, footprint, px, py, pts[k, i, 2])
        if f < 0:
            return -7.0
        if f >= LETHAL_OBSTACLE:
            return -6.0
        mx = int((px - origin_x) / resolution)
        my = int((py - origin_y) / resolution)
        if px < origin_x or py < origin_y or mx >= size_x or my >= size_y:
            return -7.0
        c = costs[my, mx]
        if c > f:
            f = c
        if sum_scores:
            cost += f
        elif f > cost:
            cost = f
        if base + scale * cost > budget:
            return cost
    return cost


@njit(cache=True, nogil=True)
def score_dwa(pts: np.ndarray, steps: np.ndarray, vels: np.ndarray, costs: np.ndarray,
              origin_x: float, origin_y: float, resolution: float, footprint: np.ndarray,
              path_grid: np.ndarray, goal_grid: np.ndarray, front_grid: np.ndarray,
              weights: np.ndarray, flags: np.ndarray, exhaustive: bool
              ) -> tuple[np.ndarray, np.ndarray, int]:
    """Score every trajectory; return (scores, state per trajectory, best index or -1).

    ``weights``: occdist, goal_front, alignment, path, goal, twirling scales, forward shift,
    scaling_speed, max_vel_trans, max_scaling_factor, sum_scores (0/1).
    ``state``: SCORED, PRUNED (score is a lower bound) or REJECTED (score is the code).
    With ``exhaustive`` every trajectory is scored in full (for drawing and for tests).
    """
    occ_s = weights[0]
    front_s = weights[1]
    align_s = weights[2]
    path_s = weights[3]
    goal_s = weights[4]
    twirl_s = weights[5]
    xshift = weights[6]
    sum_scores = weights[10] != 0.0
    k_n = pts.shape[0]
    scores = np.zeros(k_n)
    state = np.zeros(k_n, dtype=np.int8)
    bound = np.full(k_n, np.inf)
    # pass 1: everything but the footprint
    for k in range(k_n):
        n = steps[k]
        vx, vy, vth = vels[k, 0], vels[k, 1], vels[k, 2]
        c = oscillation_critic(vx, vy, vth, flags)
        total = 0.0
        if c >= 0 and front_s != 0.0:
            g = grid_critic(pts, k, n, front_grid, origin_x, origin_y, resolution, xshift, False)
            c = g if g < 0 else c
            total += front_s * g
        if c >= 0 and align_s != 0.0:
            g = grid_critic(pts, k, n, path_grid, origin_x, origin_y, resolution, xshift, False)
            c = g if g < 0 else c
            total += align_s * g
        if c >= 0 and path_s != 0.0:
            g = grid_critic(pts, k, n, path_grid, origin_x, origin_y, resolution, 0.0, True)
            c = g if g < 0 else c
            total += path_s * g
        if c >= 0 and goal_s != 0.0:
            g = grid_critic(pts, k, n, goal_grid, origin_x, origin_y, resolution, 0.0, True)
            c = g if g < 0 else c
            total += goal_s * g
        if c < 0:
            scores[k] = c
            state[k] = REJECTED
            continue
        total += twirl_s * abs(vth)
        bound[k] = total
        scores[k] = total
    # pass 2: footprints, cheapest lower bound first
    order = np.argsort(bound, kind="mergesort")
    best = -1
    best_cost = np.inf
    for j in range(k_n):
        k = order[j]
        if state[k] == REJECTED:
            break  # rejected ones sort last (bound = inf)
        slack = 1e-9 * (1.0 + abs(best_cost)) if best >= 0 else 0.0
        if not exhaustive and best >= 0 and bound[k] > best_cost + slack:
            state[k] = PRUNED
            continue
        fp = footprint
        s = footprint_scale(vels[k, 0], vels[k, 1], weights[7], weights[8], weights[9])
        if s != 1.0:
            fp = footprint * s
        budget = np.inf if (exhaustive or best < 0) else best_cost + slack
        o = obstacle_critic(pts, k, steps[k], costs, origin_x, origin_y, resolution, fp,
                            sum_scores, bound[k], occ_s, budget)
        if o < 0:
            scores[k] = o
            state[k] = REJECTED
            continue
        total = bound[k] + occ_s * o
        scores[k] = total
        if budget < np.inf and total > budget:
            state[k] = PRUNED
            continue
        if best < 0 or total < best_cost or (total == best_cost and k < best):
            best = k
            best_cost = total
    return scores, state, best
