"""dwa_local_planner's DWAPlannerROS: sample velocities, roll them out, score them with the
critic chain, latch oscillation flags, stop and rotate to the goal yaw at the end.

Parameter names and effective defaults are DWAPlannerROS's (DWAPlanner.cfg with the shared
LocalPlannerLimits). Departures from ROS, both toward safety: the footprint is grown above
``scaling_speed`` as documented (ROS computes the factor but never applies it), and the
obstacle critic keeps rejecting lethal trajectories even when ``occdist_scale`` is 0.
"""

from __future__ import annotations

import math
from typing import Any, NamedTuple

import numpy as np

from navcore.costmap.costmap2d import Costmap2D
from navcore.costmap.footprint import bound_reach, square_max
from navcore.params import Param, Parameters
from navcore.types import Pose2D, Twist

from navcore.controllers import goal_checks as gc
from navcore.controllers.base import LocalPlannerBase
from navcore.controllers.critics import DwaWeights, score_dwa
from navcore.controllers.map_grid import densify_plan, distance_grid, plan_cells
from navcore.controllers.oscillation import OscillationFlags
from navcore.controllers.result import ControlResult, ControlStatus, describe_rejections
from navcore.controllers.rollout import (CONSTANT, RAMPED, filter_and_steps, sample_grid,
                                         simulate)

class DwaCycle(NamedTuple):
    """What one cycle's scoring reads (updatePlanAndLocalCosts): the costmap window, the
    distance grids from the path, the local goal and the point ahead of it, the critics'
    weights (``DwaWeights.array()``) and the footprint cost bound. Immutable, like
    ``DwaWeights``; a named tuple because one is made every cycle and a frozen dataclass
    costs several times more to build (docs/performance.md, "Wave 2 benchmark check")."""

    costs: np.ndarray
    ox: float
    oy: float
    res: float
    path: np.ndarray
    goal: np.ndarray
    front: np.ndarray
    weights: np.ndarray
    local_goal: tuple[float, float]
    bound: np.ndarray
    reach: int


LIMITS_PARAMS = (
    Param("max_vel_trans", 0.55, float, "max translational speed |(vx, vy)| (m/s)", min=0.0),
    Param("min_vel_trans", 0.1, float, "min translational speed unless rotating fast enough (m/s)",
          min=0.0),
    Param("max_vel_x", 0.55, float, "max forward velocity (m/s)"),
    Param("min_vel_x", 0.0, float, "min x velocity; negative lets the robot back off (m/s)"),
    Param("max_vel_y", 0.1, float, "max strafe velocity; 0 for differential drive (m/s)"),
    Param("min_vel_y", -0.1, float, "min strafe velocity; 0 for differential drive (m/s)"),
    Param("max_vel_theta", 1.0, float, "max absolute yaw rate (rad/s)", min=0.0),
    Param("min_vel_theta", 0.4, float, "min absolute yaw rate when not translating; its absolute "
          "value is used (rad/s)"),
    Param("acc_lim_x", 2.5, float, "x acceleration limit (m/s^2)", min=0.0),
    Param("acc_lim_y", 2.5, float, "y acceleration limit (m/s^2)", min=0.0),
    Param("acc_lim_theta", 3.2, float, "yaw acceleration limit (rad/s^2)", min=0.0),
    Param("acc_lim_trans", 0.1, float, "translational acceleration limit; unused by DWA's "
          "sampling, as in ROS (m/s^2)", min=0.0),
    Param("prune_plan", False, bool, "drop plan poses behind the robot (more than 1 m back)"),
    Param("xy_goal_tolerance", 0.1, float, "goal position tolerance (m)", min=0.0),
    Param("yaw_goal_tolerance", 0.1, float, "goal yaw tolerance (rad)", min=0.0),
    Param("trans_stopped_vel", 0.1, float, "below this translational speed the robot counts as "
          "stopped (m/s)", min=0.0),
    Param("theta_stopped_vel", 0.1, float, "below this yaw rate the robot counts as stopped "
          "(rad/s)", min=0.0),
    Param("latch_xy_goal_tolerance", False, bool, "once inside xy_goal_tolerance, only rotate in "
          "place even if pushed out again"),
)

DWA_PARAMS = LIMITS_PARAMS + (
    Param("sim_time", 1.7, float, "forward simulation horizon (s)", min=0.0),
    Param("sim_granularity", 0.025, float, "step between trajectory points (m)", min=1e-6),
    Param("angular_sim_granularity", 0.1, float, "angular step between trajectory points (rad)",
          min=1e-6),
    # DWAPlanner.cfg's 32 / 24 (applied on the first reconfigure call), not TrajectoryPlanner's
    # 0.6 / 0.8: times the resolution, a cell of progress must be able to outweigh the obstacle
    # term (occdist_scale x up to 252), else rotating in place beside an obstacle always wins
    Param("path_distance_bias", 32.0, float, "weight of staying near the global path", min=0.0),
    Param("goal_distance_bias", 24.0, float, "weight of reaching the local goal", min=0.0),
    Param("occdist_scale", 0.01, float, "weight of obstacle cost", min=0.0),
    Param("twirling_scale", 0.0, float, "weight of abs(yaw rate)", min=0.0),
    Param("stop_time_buffer", 0.2, float, "time to stop before a collision (s); unused by the DWA "
          "critics, as in ROS", min=0.0),
    Param("oscillation_reset_dist", 0.05, float, "travel that releases oscillation flags (m)",
          min=0.0),
    Param("oscillation_reset_angle", 0.2, float, "turn that releases oscillation flags (rad)",
          min=0.0),
    Param("forward_point_distance", 0.325, float, "distance of the scored point ahead of the "
          "robot centre (m)"),
    Param("scaling_speed", 0.25, float, "speed above which the footprint grows (m/s)", min=0.0),
    Param("max_scaling_factor", 0.2, float, "footprint growth at max_vel_trans", min=0.0),
    Param("vx_samples", 3, int, "x velocity samples", min=1),
    Param("vy_samples", 10, int, "y velocity samples", min=1),
    Param("vth_samples", 20, int, "yaw rate samples", min=1),
    Param("use_dwa", True, bool, "hold each sample over the horizon (DWA) instead of ramping "
          "toward it (trajectory rollout)"),
    Param("controller_frequency", 20.0, float, "control rate; sim_period = 1/frequency (Hz)",
          min=1e-3),
    Param("sum_scores", False, bool, "sum the footprint costs along a trajectory instead of "
          "taking the max"),
    Param("cheat_factor", 1.0, float, "alignment is off within forward_point_distance * "
          "sqrt(cheat_factor) of the goal", min=0.0),
)

# keys a ROS DWAPlannerROS namespace may carry that mean nothing here
IGNORED = ("restore_defaults", "publish_cost_grid_pc", "publish_traj_pc", "global_frame_id")


class DWAPlanner(LocalPlannerBase):
    """The DWA local planner (``dwa_local_planner/DWAPlannerROS``).

    ``costmap`` is the local rolling-window costmap, read afresh every cycle (its origin moves);
    ``footprint`` an (N, 2) polygon in the robot frame (padded, as the costmap has it);
    ``params`` a DWAPlannerROS namespace. ``params`` stays live: change it between cycles.
    """

    NAME = "DWAPlannerROS"

    def __init__(self, costmap: Costmap2D, footprint: np.ndarray,
                 params: dict[str, Any] | None = None) -> None:
        super().__init__(costmap, footprint)
        self.params = Parameters(DWA_PARAMS, params, where=self.NAME, ignore=IGNORED)
        self.oscillation = OscillationFlags()
        self._xy_latch = False
        self._rotating_to_goal = False
        self.exhaustive = False  # score every trajectory in full (for drawing); slower
        # distance grids of the current costmap window, by seed cells (see _distance_grid)
        self._grid_cache: dict[str, Any] = {}
        self._reach: tuple[Any, int] | None = None  # (key, bound_reach) of the last _bound

    def reset(self) -> None:
        """Forget the latched xy tolerance, the rotate-to-goal phase and the oscillation flags."""
        self._xy_latch = False
        self._rotating_to_goal = False
        self.oscillation.reset()

    # --- goal ---------------------------------------------------------------------------------
    def _position_reached(self, pose: Pose2D, goal: Pose2D) -> bool:
        p = self._p()
        if (p.latch_xy_goal_tolerance and self._xy_latch) or gc.xy_reached(pose, goal,
                                                                             p.xy_goal_tolerance):
            self._xy_latch = True
            return True
        return False

    def is_goal_reached(self) -> bool:
        """At the goal position (or latched there), within the yaw tolerance, and stopped, as of
        the last ``compute_velocity`` call."""
        goal, pose, p = self.goal(), self._last_pose, self.params
        if goal is None or pose is None:
            return False
        if not ((p.latch_xy_goal_tolerance and self._xy_latch)
                or gc.xy_reached(pose, goal, p.xy_goal_tolerance)):
            return False
        return (gc.yaw_reached(pose, goal, p.yaw_goal_tolerance)
                and gc.stopped(self._last_vel, p.theta_stopped_vel, p.trans_stopped_vel))

    # --- one cycle ----------------------------------------------------------------------------
    def _compute(self, pose: Pose2D, velocity: Twist) -> ControlResult:
        p = self._p()
        local = self._local_plan(pose, p.prune_plan)
        if len(local) == 0:
            return ControlResult(Twist.zero(), ControlStatus.NO_VALID_TRAJECTORY,
                                 reason=f"{self.NAME}: no pose of the plan lies within the local "
                                        "costmap around the robot")
        ctx = self._prepare(pose, local)
        goal = self.goal()
        assert goal is not None
        if self._position_reached(pose, goal):
            return self._stop_and_rotate(pose, velocity, goal, ctx)
        self._rotating_to_goal = False
        return self._follow(pose, velocity, local, ctx)

    def _prepare(self, pose: Pose2D, local: np.ndarray) -> DwaCycle:
        """Grids and critic weights of this cycle (updatePlanAndLocalCosts)."""
        p, cm = self._p(), self.costmap
        costs = self._costs()
        ox, oy, res = cm.origin_x, cm.origin_y, cm.resolution
        self._sync_grid_cache(costs, ox, oy, res)
        cells = plan_cells(costs, ox, oy, res, densify_plan(local, res))
        path_grid = self._distance_grid(costs, cells)
        goal_grid = self._distance_grid(costs, cells[-1:])
        # the nose is drawn to a point forward_point_distance past the local goal, on the line
        # from the robot, so that it does not have to turn around at the very end
        gx, gy = local[-1, 0], local[-1, 1]
        ang = math.atan2(gy - pose.y, gx - pose.x)
        front = local.copy()
        front[-1, 0] += p.forward_point_distance * math.cos(ang)
        front[-1, 1] += p.forward_point_distance * math.sin(ang)
        fcells = plan_cells(costs, ox, oy, res, densify_plan(front, res))
        if len(fcells) and len(cells) and np.array_equal(fcells[-1], cells[-1]):
            front_grid = goal_grid
        else:
            front_grid = self._distance_grid(costs, fcells[-1:])
        bound, reach = self._bound(costs, res)
        pdist, gdist = p.path_distance_bias * res, p.goal_distance_bias * res
        fpd = p.forward_point_distance
        near_goal = (gx - pose.x) ** 2 + (gy - pose.y) ** 2 <= fpd * fpd * p.cheat_factor
        weights = DwaWeights(occdist=p.occdist_scale, goal_front=gdist,
                             alignment=0.0 if near_goal else pdist, path=pdist, goal=gdist,
                             twirling=p.twirling_scale, forward_point_distance=fpd,
                             scaling_speed=p.scaling_speed, max_vel_trans=p.max_vel_trans,
                             max_scaling_factor=p.max_scaling_factor,
                             sum_scores=1.0 if p.sum_scores else 0.0)
        return DwaCycle(costs, ox, oy, res, path_grid, goal_grid, front_grid, weights.array(),
                        (gx, gy), bound, reach)

    def _sync_grid_cache(self, costs: np.ndarray, ox: float, oy: float, res: float) -> None:
        """Keep the cached distance grids only while the costmap window (origin, resolution and
        every cost) is the one they were built on: a 6 m window compares in microseconds, a
        grid takes a tenth of a millisecond to build."""
        c = self._grid_cache
        if c.get("window") != (ox, oy, res) or not np.array_equal(c.get("costs"), costs):
            self._grid_cache = {"window": (ox, oy, res), "costs": costs.copy(), "grids": {}}

    def _distance_grid(self, costs: np.ndarray, seeds: np.ndarray) -> np.ndarray:
        """``distance_grid`` from ``seeds`` over the current window, built once per distinct
        seed set while the window stays the same (read-only: callers never write to it)."""
        grids = self._grid_cache["grids"]
        key = seeds.tobytes()
        grid = grids.get(key)
        if grid is None:
            if len(grids) >= 8:  # a handful of seed sets per window; never grow unbounded
                grids.clear()
            grid = distance_grid(costs, seeds, np.zeros((0, 0), dtype=np.bool_))
            grids[key] = grid
        return grid

    def _bound(self, costs: np.ndarray, res: float) -> tuple[np.ndarray, int]:
        """The footprint cost bound of the current window (``square_max``), for the footprint
        at its largest (grown to max_scaling_factor at speed, with a little slack for samples
        at the max_vel_trans tolerance), built once per window like the distance grids."""
        key = (res, self._p().max_scaling_factor, self.footprint.tobytes())
        cached = self._grid_cache.get("bound")
        if cached is None or cached[0] != key:
            if self._reach is None or self._reach[0] != key:  # not with every new window
                self._reach = (key, bound_reach(self.footprint, res, 1.01 * (1.0 + key[1])))
            reach = self._reach[1]
            cached = (key, square_max(costs, reach), reach)
            self._grid_cache["bound"] = cached
        return cached[1], cached[2]

    def _acc(self) -> np.ndarray:
        p = self._p()
        return np.array([p.acc_lim_x, p.acc_lim_y, p.acc_lim_theta])

    def _score(self, pose: Pose2D, velocity: Twist, samples: np.ndarray, ctx: DwaCycle,
               exhaustive: bool) -> tuple[np.ndarray, ...]:
        """Roll out and score ``samples``: (points, steps, commands, scores, state, best)."""
        p = self._p()
        samples, steps = filter_and_steps(samples, p.sim_time, p.sim_granularity,
                                          p.angular_sim_granularity, p.min_vel_trans,
                                          abs(p.min_vel_theta), p.max_vel_trans)
        vel = np.array([velocity.vx, velocity.vy, velocity.wz])
        pts, cmds, nose = simulate(samples, steps, pose.x, pose.y, pose.theta, vel, self._acc(),
                                   p.sim_time, CONSTANT if p.use_dwa else RAMPED,
                                   p.forward_point_distance)
        scores, state, best = score_dwa(pts, nose, steps, cmds, ctx.costs, ctx.ox, ctx.oy,
                                        ctx.res, self.footprint, ctx.path, ctx.goal, ctx.front,
                                        ctx.weights, self.oscillation.only, exhaustive,
                                        ctx.bound, ctx.reach)
        return pts, steps, cmds, scores, state, best

    def sample_window(self, velocity: Twist, pose: Pose2D | None = None,
                      local_goal: tuple[float, float] | None = None) -> np.ndarray:
        """The (K, 3) velocity samples of this cycle, before the min/max checks."""
        p = self._p()
        v = (velocity.vx, velocity.vy, velocity.wz)
        acc = (p.acc_lim_x, p.acc_lim_y, p.acc_lim_theta)
        max_x, max_y = p.max_vel_x, p.max_vel_y
        if p.use_dwa:
            reach = [a / p.controller_frequency for a in acc]  # one control period
        else:
            reach = [a * p.sim_time for a in acc]
            if pose is not None and local_goal is not None and p.sim_time > 0:
                # never overshoot the goal within the horizon
                d = math.hypot(local_goal[0] - pose.x, local_goal[1] - pose.y) / p.sim_time
                max_x = max(min(max_x, d), p.min_vel_x)
                max_y = max(min(max_y, d), p.min_vel_y)
        # plain floats: the same IEEE sums and comparisons as arrays, without building them
        hi = [min(m, vi + r) for m, vi, r in zip((max_x, max_y, p.max_vel_theta), v, reach)]
        lo = [max(m, vi - r) for m, vi, r in zip((p.min_vel_x, p.min_vel_y, -p.max_vel_theta), v,
                                                 reach)]
        return sample_grid(np.array(lo), np.array(hi),
                           np.array([p.vx_samples, p.vy_samples, p.vth_samples]))

    def _follow(self, pose: Pose2D, velocity: Twist, local: np.ndarray,
                ctx: DwaCycle) -> ControlResult:
        p = self._p()
        samples = self.sample_window(velocity, pose, ctx.local_goal)
        pts, steps, cmds, scores, state, best = self._score(pose, velocity, samples, ctx,
                                                             self.exhaustive)
        if best < 0:
            return ControlResult(Twist.zero(), ControlStatus.NO_VALID_TRAJECTORY,
                                 None, pts, scores, cmds,
                                 reason=f"{self.NAME}: every trajectory was discarded ("
                                        f"{describe_rejections(scores)})")
        vx, vy, vth = (float(v) for v in cmds[best])
        self.oscillation.update(pose.x, pose.y, pose.theta, vx, vy, vth, p.min_vel_trans,
                                p.oscillation_reset_dist, p.oscillation_reset_angle)
        return ControlResult(Twist(vx, vy, vth), ControlStatus.FOLLOWING,
                             pts[best, :steps[best]].copy(), pts,
                             scores, cmds, reason=f"{self.NAME}: cost {scores[best]:.4f}")

    def _legal(self, pose: Pose2D, velocity: Twist, cmd: Twist, ctx: DwaCycle) -> bool:
        """checkTrajectory: would the whole critic chain accept holding ``cmd``? A command too
        slow to simulate counts as legal (ROS scores its empty trajectory as 0)."""
        sample = np.array([[cmd.vx, cmd.vy, cmd.wz]])
        p = self._p()
        kept, _ = filter_and_steps(sample, p.sim_time, p.sim_granularity,
                                   p.angular_sim_granularity, p.min_vel_trans,
                                   abs(p.min_vel_theta), p.max_vel_trans)
        if len(kept) == 0:
            return True
        *_, scores, _state, best = self._score(pose, velocity, sample, ctx, True)
        return best == 0 and scores[0] >= 0

    def _stop_and_rotate(self, pose: Pose2D, velocity: Twist, goal: Pose2D,
                         ctx: DwaCycle) -> ControlResult:
        """LatchedStopRotateController: at the goal position, brake, then turn to the goal yaw."""
        p = self._p()
        if gc.yaw_reached(pose, goal, p.yaw_goal_tolerance):
            self._rotating_to_goal = False
            if gc.stopped(velocity, p.theta_stopped_vel, p.trans_stopped_vel):
                return ControlResult(Twist.zero(), ControlStatus.GOAL_REACHED,
                                     reason=f"{self.NAME}: goal reached")
            return ControlResult(Twist.zero(), ControlStatus.ROTATING_TO_GOAL,
                                 reason=f"{self.NAME}: at the goal pose, waiting to stop")
        acc = (p.acc_lim_x, p.acc_lim_y, p.acc_lim_theta)
        period = 1.0 / p.controller_frequency
        if not self._rotating_to_goal and not gc.stopped(velocity, p.theta_stopped_vel,
                                                         p.trans_stopped_vel):
            cmd = gc.stop_with_acc_limits(velocity, acc, period)
            what = "braking at the goal position"
        else:
            self._rotating_to_goal = True
            wz = gc.rotate_to_goal_velocity(pose.theta, goal.theta, velocity.wz, acc[2], period,
                                            abs(p.min_vel_theta), p.max_vel_theta)
            cmd = Twist(0.0, 0.0, wz)
            what = "rotating to the goal yaw"
        if not self._legal(pose, velocity, cmd, ctx):
            return ControlResult(Twist.zero(), ControlStatus.NO_VALID_TRAJECTORY,
                                 reason=f"{self.NAME}: {what} would collide")
        return ControlResult(cmd, ControlStatus.ROTATING_TO_GOAL, reason=f"{self.NAME}: {what}")
