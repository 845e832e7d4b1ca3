"""navfn: the NavfnROS global planner (Dijkstra wavefront + gradient descent path).

Same sequence as ``NavfnROS::makePlan``: the wave is seeded at the robot and stops when the goal's
potential is final; the cost transform is navfn's (``COST_NEUTRAL`` 50 + ``COST_FACTOR`` 0.8 x cost,
inscribed and lethal impassable, unknown 253 when ``allow_unknown``); the goal tolerance square is
searched for the reachable point closest to the goal; the path descends the interpolated gradient
from there and comes out robot -> goal in world coordinates ``origin + cell * resolution`` (navfn's
corner convention), ending with the goal pose. Differences from the C++: no 10000-cell queue cap,
the stop waits for the goal's potential to be final (see ``wavefront``), threshold bands are
``BAND_NEUTRALS`` (10) x ``COST_NEUTRAL`` wide instead of 2 x (fewer updates, slightly different
potentials: see there), buffers are reused, and the shared costmap is never written (the C++
clears the robot cell in it).
"""

from __future__ import annotations

import functools

import numpy as np

from navcore.costmap.costmap2d import Costmap2D
from navcore.params import Param, Parameters
from navcore.planners.common import diagnose, finite_pose, search_tolerance
from navcore.planners.result import PlanReason, PlanResult
from navcore.planners.traceback import STOP_NEAR_NEUTRAL, gradient_path
from navcore.planners.wavefront import (BAND_NEUTRALS, POT_HIGH, Workspace, descent_margin,
                                        kernel_tables, plan_field, run_wavefront)
from navcore.types import Path, Pose2D

COST_NEUTRAL = 50
COST_FACTOR = 0.8
COST_OBS = 254
COST_OBS_ROS = 253
COST_UNKNOWN_ROS = 255

NAVFN_PARAMS = (
    Param("allow_unknown", True, bool,
          "plan through unknown cells (cost 253, the dearest passable)"),
    Param("default_tolerance", 0.0, float, "m: accept the reachable point closest to the goal "
          "within this square half-side when the goal itself is not reachable", min=0.0),
    Param("visualize_potential", False, bool, "return the potential grid with each plan"),
    Param("reuse_search", False, bool, "root the potential at the goal so that a replan toward "
          "the same goal repairs the last field where costs changed instead of searching afresh "
          "(navbt's; the repair gives exactly a fresh goal-rooted plan's path; ROS roots it at the "
          "robot: paths differ slightly from the default's)"),
    Param("planner_window_x", 0.0, float, "m: declared by NavfnROS, unused there and here"),
    Param("planner_window_y", 0.0, float, "m: declared by NavfnROS, unused there and here"),
    Param("planner_costmap_publish_frequency", 0.0, float, "Hz: accepted for ROS files, unused"),
)


def navfn_cost_table(allow_unknown: bool) -> np.ndarray:
    """navfn's ``setCostmap`` transform of every ROS cost value, as a 256-entry lookup table."""
    v = np.arange(256)
    out = np.full(256, COST_OBS, np.float32)
    free = v < COST_OBS_ROS
    out[free] = np.minimum((COST_NEUTRAL + COST_FACTOR * v[free]).astype(np.int64), COST_OBS - 1)
    if allow_unknown:
        out[COST_UNKNOWN_ROS] = COST_OBS - 1
    return out


@functools.lru_cache(maxsize=4)
def _navfn_tables(allow_unknown: bool) -> tuple:
    """``navfn_cost_table`` and its ``kernel_tables``, built once per setting (they took ~0.07 ms
    of every plan); shared, never written."""
    lut = navfn_cost_table(allow_unknown)
    return lut, kernel_tables(lut, COST_OBS, False)


class NavFn:
    """Global planner with NavfnROS semantics; ``make_plan(start, goal)`` gives a path or
    the reason there is none (an exception is a bug)."""

    def __init__(self, costmap: Costmap2D, params: dict | None = None) -> None:
        self.costmap = costmap
        self.params = Parameters(NAVFN_PARAMS, params, where="NavfnROS")
        self._ws = Workspace()
        self.last_updates = 0  # cell updates of the last propagation (for benchmarks)
        self.last_repaired = False  # whether the last plan repaired the previous field

    def make_plan(self, start: Pose2D, goal: Pose2D) -> PlanResult:
        """A path from ``start`` to ``goal`` (map frame), or the reason there is none."""
        return self._make_plan(start, goal)

    def _make_plan(self, start: Pose2D, goal: Pose2D) -> PlanResult:
        if not (finite_pose(start) and finite_pose(goal)):
            return PlanResult.failure(PlanReason.INVALID_POSE)
        cm = self.costmap
        p = self.params
        sc = cm.world_to_map(start.x, start.y)
        if sc is None:
            return PlanResult.failure(PlanReason.START_OUTSIDE_MAP)
        gc = cm.world_to_map(goal.x, goal.y)
        tol = p.default_tolerance
        if gc is None and tol <= 0.0:
            return PlanResult.failure(PlanReason.GOAL_OUTSIDE_MAP)
        nx, ny = cm.size_x, cm.size_y
        ws = self._ws
        ws.ensure(nx, ny)
        lut, tables = _navfn_tables(bool(p.allow_unknown))
        if cm.costs.dtype != np.uint8:
            raise TypeError(f"costmap costs must be uint8, got {cm.costs.dtype}")
        costs = np.ascontiguousarray(cm.costs).reshape(-1)
        k = sc[1] * nx + sc[0]
        target = gc[1] * nx + gc[0] if gc is not None else 0  # off-map goal: ROS aims at cell 0
        if p.reuse_search and gc is not None and 0 < gc[0] < nx - 1 and 0 < gc[1] < ny - 1 \
                and lut[costs[target]] < COST_OBS:
            r = self._plan_from_goal(costs, tables, lut, sc, gc, goal)
            if r is not None:
                return r
            # the robot cannot be reached from the goal: the robot-rooted search says why
        _, self.last_updates, _ = run_wavefront(
            ws, costs, tables, nx, ny, np.array([k], np.int64),
            np.array([0.0], np.float32), np.array([k + 1, k - 1, k - nx, k + nx], np.int64),
            target, float(COST_OBS), float(BAND_NEUTRALS * COST_NEUTRAL), 2 * nx * ny, True)
        pot = ws.pot
        potential = pot.reshape(ny, nx) if p.visualize_potential else None
        best = search_tolerance(cm, pot, goal, tol)
        if best is None:
            passable = lut[cm.costs] < COST_OBS
            return PlanResult.failure(diagnose(passable, gc, self.last_updates), potential)
        bc = cm.world_to_map(*best)
        ok, xy = gradient_path(pot, nx, ny, float(bc[0]), float(bc[1]), STOP_NEAR_NEUTRAL,
                               float(sc[0]), float(sc[1]), max(4 * nx, nx * ny // 2),
                               float(COST_OBS))
        if not ok or len(xy) == 0:
            return PlanResult.failure(PlanReason.NO_PATH, potential)
        poses = np.zeros((len(xy) + 1, 3))
        poses[:-1, 0] = cm.origin_x + xy[::-1, 0] * cm.resolution
        poses[:-1, 1] = cm.origin_y + xy[::-1, 1] * cm.resolution
        poses[-1] = (best[0], best[1], goal.theta)
        return PlanResult(True, Path(poses), PlanReason.NONE, potential)

    def _plan_from_goal(self, costs: np.ndarray, tables: tuple, lut: np.ndarray,
                        sc: tuple[int, int], gc: tuple[int, int], goal: Pose2D
                        ) -> PlanResult | None:
        """``reuse_search``: the field seeded at the goal, final up to the robot (repaired from
        the last one when only a few costs changed), the path descending from the robot."""
        cm, ws = self.costmap, self._ws
        nx, ny = cm.size_x, cm.size_y
        g, k = gc[1] * nx + gc[0], sc[1] * nx + sc[0]
        _, self.last_updates, _, self.last_repaired = plan_field(
            ws, costs, tables, nx, ny, np.array([g], np.int64), np.array([0.0], np.float32),
            np.array([g + 1, g - 1, g - nx, g + nx], np.int64), k, float(COST_OBS),
            float(BAND_NEUTRALS * COST_NEUTRAL), 2 * nx * ny, True,
            descent_margin(lut, cm.costs, sc, COST_OBS))
        pot = ws.pot
        if pot[k] >= POT_HIGH:
            return None
        ok, xy = gradient_path(pot, nx, ny, float(sc[0]), float(sc[1]), STOP_NEAR_NEUTRAL,
                               float(gc[0]), float(gc[1]), max(4 * nx, nx * ny // 2),
                               float(COST_OBS))
        if not ok or len(xy) == 0:
            return None
        potential = pot.reshape(ny, nx) if self.params.visualize_potential else None
        poses = np.zeros((len(xy) + 1, 3))
        poses[:-1, 0] = cm.origin_x + xy[:, 0] * cm.resolution
        poses[:-1, 1] = cm.origin_y + xy[:, 1] * cm.resolution
        poses[-1] = (goal.x, goal.y, goal.theta)
        return PlanResult(True, Path(poses), PlanReason.NONE, potential)

    def potential_at(self, x: float, y: float) -> float:
        """The last plan's potential at a world point (navfn ``getPointPotential``); inf off-map."""
        c = self.costmap.world_to_map(x, y)
        if c is None or self._ws.shape != (self.costmap.size_x, self.costmap.size_y):
            return float("inf")
        v = float(self._ws.pot[c[1] * self.costmap.size_x + c[0]])
        return v if v < POT_HIGH else float("inf")
