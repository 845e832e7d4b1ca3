"""base_local_planner's TrajectoryPlannerROS: trajectory rollout (or DWA with ``dwa: true``).

Samples a vx x vtheta grid ramped with the acceleration limits over ``sim_time``, then strafes
(holonomic), in-place rotations toward the best heading, sideways escapes and finally a slow
backward escape, in the order and with the latches of trajectory_planner.cpp. Cost of a
trajectory = path_distance_bias * path cells + goal_distance_bias * goal cells +
occdist_scale * worst footprint cost (all multiplied by the resolution with ``meter_scoring``);
-1 marks an illegal footprint or off-map point, -2 a point cut off from the path or goal.

Effective defaults are the BaseLocalPlanner.cfg ones (sim_time 1.7, vx_samples 20, dwa false,
holonomic_robot true), with the node-only prune_plan true and yaw_goal_tolerance 0.05.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np
from numba import njit

from navcore.costmap.cost_values import LETHAL_OBSTACLE
from navcore.costmap.costmap2d import Costmap2D
from navcore.costmap.footprint import footprint_cost
from navcore.params import Param, ParameterError, Parameters
from navcore.types import Pose2D, Twist

from navcore.controllers import goal_checks as gc
from navcore.controllers.base import LocalPlannerBase
from navcore.controllers.map_grid import densify_plan, distance_grid, plan_cells
from navcore.controllers.result import ControlResult, ControlStatus, describe_rejections
from navcore.controllers.rollout import RAMPED_FROM_CURRENT, simulate


class RolloutWeights(NamedTuple):
    """The rollout critics' scales of one cycle, by name (ROS's pdist_scale, gdist_scale,
    occdist_scale); ``array()`` is the float64 array the kernels take, in this order (the
    ``RW_*`` indices below)."""

    path: float
    goal: float
    occdist: float

    def array(self) -> np.ndarray:
        return np.array(self, dtype=np.float64)


# positions in RolloutWeights.array(): compile-time constants in the kernels, defined beside
# them because numba's cache does not see a change to another module's globals
RW_PATH, RW_GOAL, RW_OCCDIST = range(3)


@dataclass(frozen=True)
class RolloutCycle:
    """What one cycle's scoring reads: the costmap window, the critics' weights
    (``RolloutWeights.array()``), the distance grids from the local plan and from its end, and
    that end."""

    costs: np.ndarray
    ox: float
    oy: float
    res: float
    weights: np.ndarray
    path: np.ndarray
    goal: np.ndarray
    final_goal: tuple[float, float]


TR_PARAMS = (
    Param("acc_lim_x", 2.5, float, "x acceleration limit (m/s^2)", min=0.0),
    Param("acc_lim_y", 2.5, float, "y acceleration limit (m/s^2)", min=0.0),
    Param("acc_lim_theta", 3.2, float, "yaw acceleration limit (rad/s^2)", min=0.0),
    Param("max_vel_x", 0.55, float, "max forward velocity (m/s)", min=0.0),
    Param("min_vel_x", 0.0, float, "min forward velocity (m/s)"),
    Param("max_vel_theta", 1.0, float, "max yaw rate (rad/s)"),
    Param("min_vel_theta", -1.0, float, "min yaw rate (rad/s)"),
    Param("min_in_place_vel_theta", 0.4, float, "min absolute yaw rate turning in place (rad/s)",
          min=0.0),
    Param("sim_time", 1.7, float, "forward simulation horizon (s)", min=1e-6),
    Param("sim_granularity", 0.025, float, "step between trajectory points (m)", min=1e-6),
    Param("angular_sim_granularity", 0.025, float, "angular step between points (rad)",
          min=1e-6),
    Param("path_distance_bias", 0.6, float, "weight of staying near the global path", min=0.0),
    Param("goal_distance_bias", 0.8, float, "weight of reaching the local goal", min=0.0),
    Param("occdist_scale", 0.01, float, "weight of obstacle cost", min=0.0),
    Param("oscillation_reset_dist", 0.05, float, "travel that releases the rotate/strafe "
          "latches (m)", min=0.0),
    Param("escape_reset_dist", 0.10, float, "travel that ends an escape (m)", min=0.0),
    Param("escape_reset_theta", math.pi / 2, float, "turn that ends an escape (rad)", min=0.0),
    Param("vx_samples", 20, int, "x velocity samples", min=1),
    Param("vtheta_samples", 20, int, "yaw rate samples", min=1),
    Param("heading_lookahead", 0.325, float, "how far ahead in-place rotations look (m)"),
    Param("holonomic_robot", True, bool, "also try strafing samples"),
    Param("escape_vel", -0.1, float, "backward speed of the escape (m/s)", max=0.0),
    Param("dwa", False, bool, "sample only what one control period can reach (DWA window)"),
    Param("heading_scoring", False, bool, "score by heading instead of path distance; "
          "not supported here", choices=(False,)),
    Param("heading_scoring_timestep", 0.1, float, "with heading_scoring (s)", min=0.0),
    Param("simple_attractor", False, bool, "score by straight-line distance to the goal; not "
          "supported here", choices=(False,)),
    Param("y_vels", "-0.3,-0.1,0.1,-0.3", str, "strafe velocities tried when stuck, "
          "comma separated (m/s)"),
    Param("prune_plan", True, bool, "drop plan poses behind the robot (more than 1 m back)"),
    Param("xy_goal_tolerance", 0.10, float, "goal position tolerance (m)", min=0.0),
    Param("yaw_goal_tolerance", 0.05, float, "goal yaw tolerance (rad)", min=0.0),
    Param("latch_xy_goal_tolerance", False, bool, "once inside xy_goal_tolerance, only rotate "
          "in place"),
    Param("meter_scoring", False, bool, "biases per metre instead of per cell"),
    Param("trans_stopped_vel", 0.1, float, "below this the robot counts as stopped (m/s)",
          min=0.0),
    Param("rot_stopped_vel", 0.1, float, "below this the robot counts as stopped (rad/s)",
          min=0.0),
    Param("stop_time_buffer", 0.2, float, "time to stop before a collision (s); unused by the "
          "scoring, as in ROS", min=0.0),
    Param("controller_frequency", 20.0, float, "control rate; sim_period = 1/frequency (Hz)",
          min=1e-3),
)

IGNORED = ("restore_defaults", "global_frame_id", "publish_cost_grid_pc")


def parse_y_vels(text: Any) -> list[float]:
    """ROS's comma separated ``y_vels`` (a list is accepted too)."""
    if isinstance(text, (list, tuple)):
        items = list(text)
    else:
        items = [t for t in str(text).replace(" ", "").split(",") if t]
    try:
        return [float(v) for v in items]
    except ValueError:
        raise ParameterError(f"TrajectoryPlannerROS: y_vels must be numbers separated by commas, "
                             f"got {text!r}") from None


@njit(cache=True, nogil=True)
def rollout_cost(pts: np.ndarray, k: int, n: int, costs: np.ndarray, origin_x: float,
                 origin_y: float, resolution: float, footprint: np.ndarray,
                 path_grid: np.ndarray, goal_grid: np.ndarray, weights: np.ndarray,
                 base: float, budget: float) -> float:
    """trajectory_planner.cpp's generateTrajectory cost of trajectory ``k``, point by point:
    -1 off the map or an illegal footprint, -2 cut off from path or goal, else the weighted sum
    (path and goal distance at the last point, worst footprint cost). ``base`` is the known
    path-and-goal part (0 if unknown): once ``base`` plus the obstacle part so far exceeds
    ``budget`` the partial (lower-bound) cost is returned.
    """
    size_y, size_x = costs.shape
    impossible = size_x * size_y
    inv = 1.0 / resolution
    occ = 0.0
    pd = 0.0
    gd = 0.0
    for i in range(n):
        px = pts[k, i, 0]
        py = pts[k, i, 1]
        if px < origin_x or py < origin_y:
            return -1.0
        mx = int((px - origin_x) * inv)
        my = int((py - origin_y) * inv)
        if mx >= size_x or my >= size_y:
            return -1.0
        f = footprint_cost(costs, origin_x, origin_y, resolution, footprint, px, py, pts[k, i, 2])
        if f < 0 or f >= LETHAL_OBSTACLE:
            return -1.0
        c = costs[my, mx]
        if f > occ:
            occ = f
        if c > occ:
            occ = c
        pd = path_grid[my, mx]
        gd = goal_grid[my, mx]
        if pd >= impossible or gd >= impossible:
            return -2.0
        if base + weights[RW_OCCDIST] * occ > budget:
            return base + weights[RW_OCCDIST] * occ
    return weights[RW_PATH] * pd + weights[RW_GOAL] * gd + weights[RW_OCCDIST] * occ


@njit(cache=True, nogil=True)
def grid_bound(pts: np.ndarray, k: int, n: int, costs: np.ndarray, origin_x: float,
               origin_y: float, resolution: float, path_grid: np.ndarray, goal_grid: np.ndarray,
               weights: np.ndarray) -> tuple[float, int]:
    """A lower bound of ``rollout_cost`` from the cells under the centre alone (no footprint),
    or its -1 / -2 verdict when the centre already decides it; and the worst centre cost."""
    size_y, size_x = costs.shape
    impossible = size_x * size_y
    inv = 1.0 / resolution
    cmax = 0
    pd = 0.0
    gd = 0.0
    for i in range(n):
        px = pts[k, i, 0]
        py = pts[k, i, 1]
        if px < origin_x or py < origin_y:
            return -1.0, cmax
        mx = int((px - origin_x) * inv)
        my = int((py - origin_y) * inv)
        if mx >= size_x or my >= size_y:
            return -1.0, cmax
        c = costs[my, mx]
        if c >= LETHAL_OBSTACLE:
            return -1.0, cmax
        if c > cmax:
            cmax = c
        pd = path_grid[my, mx]
        gd = goal_grid[my, mx]
        if pd >= impossible or gd >= impossible:
            return -2.0, cmax
    return weights[RW_PATH] * pd + weights[RW_GOAL] * gd + weights[RW_OCCDIST] * cmax, cmax


@njit(cache=True, nogil=True)
def lower_bounds(pts: np.ndarray, steps: np.ndarray, costs: np.ndarray, origin_x: float,
                 origin_y: float, resolution: float, path_grid: np.ndarray,
                 goal_grid: np.ndarray, weights: np.ndarray
                 ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``grid_bound`` of every trajectory: (verdict or bound, bound with inf for the rejected,
    the path-and-goal part alone)."""
    k_n = pts.shape[0]
    scores = np.empty(k_n)
    bound = np.full(k_n, np.inf)
    base = np.zeros(k_n)
    for k in range(k_n):
        b, cmax = grid_bound(pts, k, steps[k], costs, origin_x, origin_y, resolution, path_grid,
                             goal_grid, weights)
        scores[k] = b
        if b >= 0:
            bound[k] = b
            base[k] = b - weights[RW_OCCDIST] * cmax
    return scores, bound, base


@njit(cache=True, nogil=True)
def best_rollout(pts: np.ndarray, steps: np.ndarray, costs: np.ndarray, origin_x: float,
                 origin_y: float, resolution: float, footprint: np.ndarray,
                 path_grid: np.ndarray, goal_grid: np.ndarray, weights: np.ndarray,
                 exhaustive: bool) -> tuple[np.ndarray, int]:
    """Costs of every trajectory and the first one of least cost (-1 if none is legal): the
    vx x vtheta loop's choice, found by branch and bound on the centre-cell lower bound.
    Pruned trajectories keep their lower bound as score."""
    scores, bound, base = lower_bounds(pts, steps, costs, origin_x, origin_y, resolution,
                                       path_grid, goal_grid, weights)
    k_n = pts.shape[0]
    order = np.argsort(bound, kind="mergesort")
    best = -1
    best_cost = np.inf
    for j in range(k_n):
        k = order[j]
        if bound[k] == np.inf:
            break
        slack = 1e-9 * (1.0 + abs(best_cost)) if best >= 0 else 0.0
        if not exhaustive and best >= 0 and bound[k] > best_cost + slack:
            continue
        budget = np.inf if (exhaustive or best < 0) else best_cost + slack
        c = rollout_cost(pts, k, steps[k], costs, origin_x, origin_y, resolution, footprint,
                         path_grid, goal_grid, weights, base[k], budget)
        scores[k] = c
        if c < 0 or c > budget:
            continue
        if best < 0 or c < best_cost or (c == best_cost and k < best):
            best = k
            best_cost = c
    return scores, best


def footprint_cells(costmap: Costmap2D, footprint: np.ndarray, pose: Pose2D) -> np.ndarray:
    """[my, mx] mask of the cells whose centres lie inside the footprint at ``pose`` (even-odd
    rule): the start footprint that the rollout planner's wavefront may pass through."""
    return _cells_inside(costmap.costs.shape[0], costmap.costs.shape[1], costmap.origin_x,
                         costmap.origin_y, costmap.resolution,
                         np.asarray(footprint, dtype=np.float64), pose.x, pose.y,
                         math.cos(pose.theta), math.sin(pose.theta))


@njit(cache=True, nogil=True)
def _cells_inside(size_y: int, size_x: int, ox: float, oy: float, res: float,
                  footprint: np.ndarray, x: float, y: float, c: float, s: float) -> np.ndarray:
    """``footprint_cells`` for the pose (x, y) with heading cosine ``c`` and sine ``s``."""
    n = footprint.shape[0]
    wx = np.empty(n)
    wy = np.empty(n)
    for k in range(n):
        wx[k] = x + c * footprint[k, 0] - s * footprint[k, 1]
        wy[k] = y + s * footprint[k, 0] + c * footprint[k, 1]
    mask = np.zeros((size_y, size_x), dtype=np.bool_)
    x0 = max(0, int(math.floor((wx.min() - ox) / res)))
    x1 = min(size_x - 1, int(math.floor((wx.max() - ox) / res)))
    y0 = max(0, int(math.floor((wy.min() - oy) / res)))
    y1 = min(size_y - 1, int(math.floor((wy.max() - oy) / res)))
    for my in range(y0, y1 + 1):
        gy = oy + (my + 0.5) * res
        for mx in range(x0, x1 + 1):
            gx = ox + (mx + 0.5) * res
            inside = False
            ax, ay = wx[n - 1], wy[n - 1]
            for k in range(n):
                bx, by = wx[k], wy[k]
                # a crossing edge never has by == ay: no division by zero
                if (ay <= gy) != (by <= gy) and gx < ax + (gy - ay) * (bx - ax) / (by - ay):
                    inside = not inside
                ax, ay = bx, by
            mask[my, mx] = inside
    return mask


class TrajectoryPlanner(LocalPlannerBase):
    """The trajectory rollout local planner (``base_local_planner/TrajectoryPlannerROS``).

    Same constructor and interface as ``DWAPlanner``; ``params`` is a TrajectoryPlannerROS
    namespace and stays live.
    """

    NAME = "TrajectoryPlannerROS"

    def __init__(self, costmap: Costmap2D, footprint: np.ndarray,
                 params: dict[str, Any] | None = None) -> None:
        super().__init__(costmap, footprint)
        self.params = Parameters(TR_PARAMS, params, where=self.NAME, ignore=IGNORED)
        parse_y_vels(self.params.y_vels)
        # a bad y_vels is refused where it is set (SetParameters reports it), not found later
        self.params.before_change(lambda new: parse_y_vels(new["y_vels"]) if "y_vels" in new
                                  else None)
        self.exhaustive = False
        self.reset()

    # --- state --------------------------------------------------------------------------------
    def reset(self) -> None:
        """Forget the goal latch, the rotate/strafe latches and any escape in progress."""
        self._xy_latch = False
        self._reached = False
        self._rotating_to_goal = False
        self._clear_latches()
        self._escaping = False
        self._escape = (0.0, 0.0, 0.0)
        self._prev = (0.0, 0.0)

    def _clear_latches(self) -> None:
        self.rotating_left = self.rotating_right = False
        self.strafe_left = self.strafe_right = False
        self.stuck_left = self.stuck_right = False
        self.stuck_left_strafe = self.stuck_right_strafe = False

    def _on_new_plan(self) -> None:
        # TrajectoryPlannerROS::setPlan forgets only the goal latch and the reached flag
        self._xy_latch = False
        self._reached = False

    def is_goal_reached(self) -> bool:
        """True once a cycle found the robot within both goal tolerances (ROS's reached_goal_)."""
        return self._reached

    # --- one cycle ----------------------------------------------------------------------------
    def _weights(self) -> RolloutWeights:
        """The critics' scales of this cycle: path_distance_bias, goal_distance_bias and
        occdist_scale, all three multiplied by the costmap resolution with meter_scoring (as
        TrajectoryPlannerROS does)."""
        p = self._p()
        scale = self.costmap.resolution if p.meter_scoring else 1.0
        return RolloutWeights(path=p.path_distance_bias * scale,
                              goal=p.goal_distance_bias * scale,
                              occdist=p.occdist_scale * scale)

    def _compute(self, pose: Pose2D, velocity: Twist) -> ControlResult:
        p = self._p()
        local = self._local_plan(pose, p.prune_plan)
        if len(local) == 0:
            return ControlResult(Twist.zero(), ControlStatus.NO_VALID_TRAJECTORY,
                                 reason=f"{self.NAME}: no pose of the plan lies within the local "
                                        "costmap around the robot")
        costs = self._costs()
        cm = self.costmap
        cells = plan_cells(costs, cm.origin_x, cm.origin_y, cm.resolution,
                           densify_plan(local, cm.resolution))
        inside = footprint_cells(cm, self.footprint, pose)
        ctx = RolloutCycle(costs=costs, ox=cm.origin_x, oy=cm.origin_y, res=cm.resolution,
                           weights=self._weights().array(),
                           path=distance_grid(costs, cells, inside),
                           goal=distance_grid(costs, cells[-1:], inside),
                           final_goal=(float(local[-1, 0]), float(local[-1, 1])))
        gx, gy, gth = (float(v) for v in local[-1])
        if self._xy_latch or math.hypot(gx - pose.x, gy - pose.y) <= p.xy_goal_tolerance:
            if p.latch_xy_goal_tolerance:
                self._xy_latch = True
            goal = Pose2D(gx, gy, gth)
            return self._at_goal(pose, velocity, goal, ctx)
        return self._follow(pose, velocity, ctx)

    def _samples(self, pose: Pose2D, velocity: Twist, ctx: RolloutCycle
                 ) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
        """createTrajectories' samples in its order: (samples (K, 3), group per sample, the
        unlimited in-place yaw rates, dvtheta). Groups: 0 vx x vtheta, 1 forward strafe,
        2 in-place rotation, 3 sideways escape, 4 backward escape."""
        p = self._p()
        vx, vth = velocity.vx, velocity.wz
        max_x = p.max_vel_x
        fx, fy = ctx.final_goal
        max_x = min(max_x, math.hypot(fx - pose.x, fy - pose.y) / p.sim_time)
        span = 1.0 / p.controller_frequency if p.dwa else p.sim_time
        hi_x = max(min(max_x, vx + p.acc_lim_x * span), p.min_vel_x)
        lo_x = max(p.min_vel_x, vx - p.acc_lim_x * span)
        hi_t = min(p.max_vel_theta, vth + p.acc_lim_theta * span)
        lo_t = max(p.min_vel_theta, vth - p.acc_lim_theta * span)
        dvx = (hi_x - lo_x) / (p.vx_samples - 1) if p.vx_samples > 1 else 0.0
        dvt = (hi_t - lo_t) / (p.vtheta_samples - 1) if p.vtheta_samples > 1 else 0.0
        parts: list[np.ndarray] = []
        groups: list[np.ndarray] = []

        def add(vx_: np.ndarray, vy_: np.ndarray, vth_: np.ndarray, g: int) -> None:
            parts.append(np.column_stack([vx_, vy_, vth_]))
            groups.append(np.full(len(vx_), g))

        nv, nt = p.vx_samples, p.vtheta_samples
        if not self._escaping:
            # per vx: the straight sample, then vtheta_samples - 1 rates from the bottom (ROS
            # never samples the top rate here)
            xs = np.repeat(lo_x + np.arange(nv) * dvx, nt)
            ts = np.tile(np.concatenate([[0.0], lo_t + np.arange(nt - 1) * dvt]), nv)
            add(xs, np.zeros_like(xs), ts, 0)
            if p.holonomic_robot:
                add(np.array([0.1, 0.1]), np.array([0.1, -0.1]), np.zeros(2), 1)
        raw_theta = lo_t + np.arange(nt) * dvt
        lim = np.where(raw_theta > 0, np.maximum(raw_theta, p.min_in_place_vel_theta),
                       np.minimum(raw_theta, -p.min_in_place_vel_theta))
        add(np.zeros(nt), np.zeros(nt), lim, 2)
        if p.holonomic_robot:
            vys = np.array(parse_y_vels(p.y_vels), dtype=np.float64)
            add(np.zeros(len(vys)), vys, np.zeros(len(vys)), 3)
        add(np.array([p.escape_vel]), np.zeros(1), np.zeros(1), 4)
        return np.concatenate(parts), np.concatenate(groups), raw_theta, dvt

    def _rollout(self, pose: Pose2D, velocity: Twist, samples: np.ndarray
                 ) -> tuple[np.ndarray, np.ndarray]:
        p = self._p()
        vmag = np.hypot(samples[:, 0], samples[:, 1])
        steps = (np.maximum(vmag * p.sim_time / p.sim_granularity,
                            np.abs(samples[:, 2]) / p.angular_sim_granularity) + 0.5)
        steps = np.maximum(steps.astype(np.int64), 1)  # ROS scores at least the start pose
        vel = np.array([velocity.vx, velocity.vy, velocity.wz])
        acc = np.array([p.acc_lim_x, p.acc_lim_y, p.acc_lim_theta])
        pts, _, _ = simulate(samples, steps, pose.x, pose.y, pose.theta, vel, acc, p.sim_time,
                             RAMPED_FROM_CURRENT, 0.0)
        return pts, steps

    def _cost(self, pts: np.ndarray, steps: np.ndarray, k: int, ctx: RolloutCycle,
              base: float = 0.0, budget: float = math.inf) -> float:
        """Cost of trajectory k; above ``budget`` it may stop early with a lower bound."""
        return float(rollout_cost(pts, k, int(steps[k]), ctx.costs, ctx.ox, ctx.oy,
                                  ctx.res, self.footprint, ctx.path, ctx.goal,
                                  ctx.weights, base, budget))

    def _ahead_goal_dists(self, pts: np.ndarray, steps: np.ndarray, ks: np.ndarray,
                          ctx: RolloutCycle) -> np.ndarray:
        """Goal-grid values ``heading_lookahead`` ahead of the ends of trajectories ``ks``
        (inf where that point is off the map)."""
        end = pts[ks, steps[ks] - 1]
        la = self._p().heading_lookahead
        x = end[:, 0] + la * np.cos(end[:, 2])
        y = end[:, 1] + la * np.sin(end[:, 2])
        cm = self.costmap
        out = np.full(len(ks), np.inf)
        ok = (x >= cm.origin_x) & (y >= cm.origin_y)
        mx = np.where(ok, (x - cm.origin_x) / cm.resolution, 0).astype(np.int64)
        my = np.where(ok, (y - cm.origin_y) / cm.resolution, 0).astype(np.int64)
        ok &= (mx < cm.size_x) & (my < cm.size_y)
        out[ok] = ctx.goal[my[ok], mx[ok]]
        return out

    def find_best(self, pose: Pose2D, velocity: Twist, ctx: RolloutCycle
                  ) -> tuple[int, float, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """findBestPath: (chosen index or -1, its cost, samples, points, steps, scores), with
        the latch and escape bookkeeping of createTrajectories."""
        p = self._p()
        samples, group, raw_theta, dvt = self._samples(pose, velocity, ctx)
        pts, steps = self._rollout(pose, velocity, samples)
        scores = np.full(len(samples), np.nan)
        best, best_cost = -1, -1.0
        main = np.flatnonzero(group <= 1)
        if len(main):
            sc, b = best_rollout(pts[main], steps[main], ctx.costs, ctx.ox, ctx.oy,
                                 ctx.res, self.footprint, ctx.path, ctx.goal,
                                 ctx.weights, self.exhaustive)
            scores[main] = sc
            if b >= 0:
                best, best_cost = int(main[b]), float(sc[b])
        heading_dist = math.inf
        rest = np.flatnonzero(group >= 2)
        lb, bound, base = lower_bounds(pts[rest], steps[rest], ctx.costs, ctx.ox,
                                       ctx.oy, ctx.res, ctx.path, ctx.goal,
                                       ctx.weights)
        scores[rest] = lb
        lower = dict(zip(rest.tolist(), zip(bound.tolist(), base.tolist())))
        # in-place rotations: prefer turning toward where the goal is closer
        rot = np.flatnonzero(group == 2)
        aheads = self._ahead_goal_dists(pts, steps, rot, ctx)
        for j, k in enumerate(rot):
            t = raw_theta[j]
            if not (t > dvt or t < -dvt):
                continue
            ahead = float(aheads[j])
            if ahead >= heading_dist:
                continue
            if not ((t < 0 and not self.stuck_left) or (t > 0 and not self.stuck_right)):
                continue
            bnd, bse = lower[int(k)]
            strict = best >= 0 and samples[best, 1] == 0.0  # only a cheaper rotation may win
            if bnd == math.inf or (strict and bnd > best_cost):
                continue
            c = self._cost(pts, steps, k, ctx, bse, best_cost if strict else math.inf)
            scores[k] = c
            if c >= 0 and (best < 0 or c <= best_cost or samples[best, 1] != 0.0):
                best, best_cost, heading_dist = int(k), c, ahead
        if best >= 0:
            return self._finish(pose, best, best_cost, samples, pts, steps, scores)
        # stuck: sideways escapes (holonomic only)
        side = np.flatnonzero(group == 3)
        aheads = self._ahead_goal_dists(pts, steps, side, ctx)
        for j, k in enumerate(side):
            vy = samples[k, 1]
            c = self._cost(pts, steps, k, ctx)
            scores[k] = c
            if c < 0 or not (best < 0 or c <= best_cost):
                continue
            ahead = float(aheads[j])
            if ahead >= heading_dist:
                continue
            if (vy > 0 and not self.stuck_left_strafe) or (vy < 0 and not self.stuck_right_strafe):
                best, best_cost, heading_dist = int(k), c, ahead
        if best >= 0:
            return self._finish(pose, best, best_cost, samples, pts, steps, scores)
        # last resort: back off slowly, even through what the map calls blocked
        k = int(np.flatnonzero(group == 4)[0])
        c = self._cost(pts, steps, k, ctx)
        scores[k] = c
        x, y = self._prev
        if math.hypot(pose.x - x, pose.y - y) > p.oscillation_reset_dist:
            self._clear_latches()
        if not self._escaping and c > -2.0:
            self._escape = (pose.x, pose.y, pose.theta)
            self._escaping = True
        self._end_escape_if_far(pose)
        return k, (1.0 if c == -1.0 else c), samples, pts, steps, scores

    def _end_escape_if_far(self, pose: Pose2D) -> None:
        ex, ey, eth = self._escape
        p = self._p()
        if (math.hypot(pose.x - ex, pose.y - ey) > p.escape_reset_dist
                or abs(math.remainder(pose.theta - eth, 2 * math.pi)) > p.escape_reset_theta):
            self._escaping = False

    def _finish(self, pose: Pose2D, best: int, cost: float, samples: np.ndarray,
                pts: np.ndarray, steps: np.ndarray, scores: np.ndarray
                ) -> tuple[int, float, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Latch in-place rotation and strafe directions; release them after moving on."""
        vx, vy, vth = samples[best]
        if not vx > 0:
            if vth < 0:
                self.stuck_right = self.stuck_right or self.rotating_right
                self.rotating_right = True
            elif vth > 0:
                self.stuck_left = self.stuck_left or self.rotating_left
                self.rotating_left = True
            elif vy > 0:
                self.stuck_right_strafe = self.stuck_right_strafe or self.strafe_right
                self.strafe_right = True
            elif vy < 0:
                self.stuck_left_strafe = self.stuck_left_strafe or self.strafe_left
                self.strafe_left = True
            self._prev = (pose.x, pose.y)
        x, y = self._prev
        if math.hypot(pose.x - x, pose.y - y) > self._p().oscillation_reset_dist:
            self._clear_latches()
        self._end_escape_if_far(pose)
        return best, cost, samples, pts, steps, scores

    def _follow(self, pose: Pose2D, velocity: Twist, ctx: RolloutCycle) -> ControlResult:
        best, cost, samples, pts, steps, scores = self.find_best(pose, velocity, ctx)
        if cost < 0:
            return ControlResult(Twist.zero(), ControlStatus.NO_VALID_TRAJECTORY,
                                 None, pts, scores, samples,
                                 reason=f"{self.NAME}: every trajectory was illegal ("
                                        f"{describe_rejections(scores)})")
        vx, vy, vth = (float(v) for v in samples[best])
        what = "escaping backward" if self._escaping else f"cost {cost:.4f}"
        return ControlResult(Twist(vx, vy, vth), ControlStatus.FOLLOWING,
                             pts[best, :steps[best]].copy(), pts,
                             scores, samples, reason=f"{self.NAME}: {what}")

    def _legal(self, pose: Pose2D, velocity: Twist, cmd: Twist, ctx: RolloutCycle) -> bool:
        """checkTrajectory: the ramped trajectory toward ``cmd`` has a non-negative cost."""
        pts, steps = self._rollout(pose, velocity, np.array([[cmd.vx, cmd.vy, cmd.wz]]))
        return self._cost(pts, steps, 0, ctx) >= 0

    def _at_goal(self, pose: Pose2D, velocity: Twist, goal: Pose2D,
                 ctx: RolloutCycle) -> ControlResult:
        p = self._p()
        if gc.yaw_reached(pose, goal, p.yaw_goal_tolerance):
            self._rotating_to_goal = False
            self._xy_latch = False
            self._reached = True
            return ControlResult(Twist.zero(), ControlStatus.GOAL_REACHED,
                                 reason=f"{self.NAME}: goal reached")
        self.find_best(pose, velocity, ctx)  # ROS runs it here for its side effects on latches
        period = 1.0 / p.controller_frequency
        if not self._rotating_to_goal and not gc.stopped(velocity, p.rot_stopped_vel,
                                                         p.trans_stopped_vel):
            cmd = gc.stop_with_acc_limits(velocity, (p.acc_lim_x, p.acc_lim_y, p.acc_lim_theta),
                                          period)
            what = "braking at the goal position"
        else:
            self._rotating_to_goal = True
            left = math.remainder(goal.theta - pose.theta, 2 * math.pi) > 0
            wz = gc.rotate_to_goal_velocity(pose.theta, goal.theta, velocity.wz, p.acc_lim_theta,
                                            period, p.min_in_place_vel_theta,
                                            p.max_vel_theta if left else -p.min_vel_theta)
            cmd = Twist(0.0, 0.0, wz)
            what = "rotating to the goal yaw"
        if not self._legal(pose, velocity, cmd, ctx):
            return ControlResult(Twist.zero(), ControlStatus.NO_VALID_TRAJECTORY,
                                 reason=f"{self.NAME}: {what} would collide")
        return ControlResult(cmd, ControlStatus.ROTATING_TO_GOAL, reason=f"{self.NAME}: {what}")
