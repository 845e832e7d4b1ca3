"""global_planner: navfn's successor with Dijkstra or A*, quadratic or plain updates, gradient or
grid paths, and orientation modes (ROS ``global_planner/GlobalPlanner``).

The cost of a cell is ``min(cost * cost_factor + neutral_cost, lethal_cost - 1)`` for costs below
``lethal_cost - 1`` (and unknown when ``allow_unknown``), else impassable. With the default
``old_navfn_behavior`` false, start and goal are fractional cells (``(w - origin)/res - 0.5``), the
wave is seeded over the 2x2 block around the start, the 5x5 around the goal is given potential
(``clearEndpoint``) and world points are ``origin + (cell + 0.5) * res``.

Differences from the C++, on purpose: A* is navfn's ``calcNavFnAstar`` wavefront over the same
potential, a cell's band picked by potential + heuristic (the C++ AStarExpansion assigns a cell
once and never improves it, so its paths are not least-cost). With the plain update the heuristic
is Manhattan x ``neutral_cost`` (consistent: the goal's potential is the least path cost); with
the quadratic one, straight-line distance x 0.99 x ``neutral_cost``, which that update (rising by
as little as 0.704 x cost per cell) does not keep consistent: on the 1000^2 and 2000^2 office
benchmarks the goal's potential is 0.2 % and 0.1 % above Dijkstra's (with 20 x neutral_cost wide
bands, see ASTAR_QUADRATIC_BAND). Dijkstra runs
until the goal's potential is final, in bands ``BAND_NEUTRALS`` x ``neutral_cost`` wide (the C++
uses 2 x), no queue cap, buffers reused, the shared costmap is never
written (``outline_map`` and the robot-cell clearing act on the planner's view only), the path
ends with one goal pose (the C++ repeats the goal's position), and
``default_tolerance`` is honoured (the C++ declares it and ignores it). A robot whose cell it may
not enter (inscribed or lethal cost) gets no plan but ``START_OCCUPIED`` (Nav2's error code), where
the C++ clears that cell and plans from it; with ``old_navfn_behavior`` it does as navfn does and
plans from it.
"""

from __future__ import annotations

import functools

import numpy as np

from navcore.costmap.costmap2d import Costmap2D
from navcore.costmap.cost_values import NO_INFORMATION
from navcore.params import Param, Parameters
from navcore.planners.common import diagnose, finite_pose, search_tolerance
from navcore.planners.orientation import apply_orientation
from navcore.planners.result import PlanReason, PlanResult
from navcore.planners.traceback import STOP_NEAR_POINT, gradient_path, grid_path
from navcore.planners.wavefront import (BAND_NEUTRALS, HEURISTIC_EUCLIDEAN,
                                        HEURISTIC_MANHATTAN, HEURISTIC_NONE, POT_HIGH, Workspace,
                                        descent_margin, kernel_tables, plan_field,
                                        run_wavefront)
from navcore.types import Path, Pose2D

GLOBAL_PLANNER_PARAMS = (
    Param("allow_unknown", True, bool, "plan through unknown cells"),
    Param("default_tolerance", 0.0, float, "m: when the goal is unreachable, plan to the reachable "
          "point closest to it within this square half-side", min=0.0),
    Param("use_dijkstra", True, bool, "Dijkstra wavefront; false: A*"),
    Param("use_quadratic", True, bool, "navfn's quadratic (planar-wave) potential; false: "
          "min(4 neighbours) + cost"),
    Param("use_grid_path", False, bool, "path by 8-neighbour steepest descent; false: gradient"),
    Param("old_navfn_behavior", False, bool, "integer start/goal cells, corner world points, "
          "single-cell seed, no goal clearing (navfn's conventions)"),
    Param("lethal_cost", 253, int, "cost value treated as impassable (and above)", min=1, max=255),
    Param("neutral_cost", 50, int, "cost of a free cell", min=1, max=255),
    Param("cost_factor", 3.0, float, "multiplies the costmap value before adding neutral_cost",
          min=0.01, max=5.0),
    Param("orientation_mode", 1, int, "0 None, 1 Forward, 2 Interpolate, 3 ForwardThenInterpolate, "
          "4 Backward, 5 Leftward, 6 Rightward", min=0, max=6),
    Param("orientation_window_size", 1, int, "poses either side used for Forward-type headings",
          min=1),
    Param("reuse_search", False, bool, "with use_dijkstra: root the potential at the goal so "
          "that a replan toward the same goal repairs the last field where costs changed "
          "instead of searching afresh (navbt's; the repair gives exactly a fresh goal-rooted "
          "plan's path; ROS roots it at the robot: paths differ slightly from the default's)"),
    Param("outline_map", True, bool, "treat the map's outer border as lethal (the wavefront "
          "never enters the border either way: its 4-cell stencil needs all neighbours)"),
    Param("publish_potential", True, bool, "return the potential grid with each plan"),
    Param("visualize_potential", False, bool, "same as publish_potential (navfn's name)"),
    Param("publish_scale", 100, int, "accepted for ROS files (potential display scale)", min=1,
          max=100),
    Param("planner_window_x", 0.0, float, "m: declared by ROS, unused there and here"),
    Param("planner_window_y", 0.0, float, "m: declared by ROS, unused there and here"),
)


# A* with the quadratic update: straight-line distance x this x neutral_cost (in free space the
# quadratic potential grows by 0.9957 x cost per cell of straight-line distance)
ASTAR_QUADRATIC_SCALE = 0.99
# ... and bands 20 x neutral_cost wide (BAND_NEUTRALS elsewhere, navfn's 2 x): that heuristic is
# not consistent for the quadratic update, so narrow bands close cells early and then correct
# them. Measured on the office benchmark (1000^2 / 2000^2): updates per cell 0.74 / 0.96 -> 0.58 /
# 0.74, goal potential 1.9 % / 1.8 % -> 0.2 % / 0.1 % above Dijkstra's (then 2 x wide).
ASTAR_QUADRATIC_BAND = 20


def global_planner_cost_table(lethal_cost: int, neutral_cost: int, cost_factor: float,
                              allow_unknown: bool) -> np.ndarray:
    """``DijkstraExpansion::getCost`` for every costmap value, as a 256-entry float32 table."""
    v = np.arange(256, dtype=np.float64)
    out = np.full(256, float(lethal_cost), np.float32)
    ok = v < lethal_cost - 1
    if allow_unknown:
        ok[NO_INFORMATION] = True
    out[ok] = np.minimum(v[ok] * cost_factor + neutral_cost, lethal_cost - 1).astype(np.float32)
    return out


def _endpoint_potential(pot: np.ndarray, n: int, nx: int, cost: float, quadratic: bool) -> float:
    l, r, u, d = (float(pot[n - 1]), float(pot[n + 1]), float(pot[n - nx]), float(pot[n + nx]))
    tc, ta = min(l, r), min(u, d)
    if not quadratic:
        return min(tc, ta) + cost
    dc = tc - ta
    if dc < 0:
        dc, ta = -dc, tc
    if dc >= cost:
        return ta + cost
    q = dc / cost
    return ta + cost * (-0.2301 * q * q + 0.5307 * q + 0.7040)


@functools.lru_cache(maxsize=8)
def _gp_tables(lethal: int, neutral: int, cost_factor: float, allow_unknown: bool) -> tuple:
    """``global_planner_cost_table`` and its ``kernel_tables``, built once per setting (they took
    ~0.07 ms of every plan); shared, never written."""
    lut = global_planner_cost_table(lethal, neutral, cost_factor, allow_unknown)
    return lut, kernel_tables(lut, lethal, True)


class GlobalPlanner:
    """ROS global_planner; ``make_plan(start, goal)`` gives a path or
    the reason there is none (an exception is a bug)."""

    def __init__(self, costmap: Costmap2D, params: dict | None = None) -> None:
        self.costmap = costmap
        self.params = Parameters(GLOBAL_PLANNER_PARAMS, params, where="GlobalPlanner")
        self._ws = Workspace()
        self.last_updates = 0
        self.last_repaired = False  # whether the last plan repaired the previous field

    def make_plan(self, start: Pose2D, goal: Pose2D) -> PlanResult:
        """A path from ``start`` to ``goal`` (map frame), or the reason there is none."""
        return self._make_plan(start, goal)

    def _to_map(self, w: Pose2D) -> tuple[float, float] | None:
        cm = self.costmap
        c = cm.world_to_map(w.x, w.y)
        if c is None:
            return None
        if self.params.old_navfn_behavior:
            return float(c[0]), float(c[1])
        # snap values within 1e-9 of a whole cell: a cell centre must not land in the cell below
        # through rounding (4.425 / 0.05 - 0.5 = 87.99999999999999)
        mx = (w.x - cm.origin_x) / cm.resolution - 0.5
        my = (w.y - cm.origin_y) / cm.resolution - 0.5
        rx, ry = round(mx), round(my)
        return (float(rx) if abs(mx - rx) < 1e-9 else mx,
                float(ry) if abs(my - ry) < 1e-9 else my)

    def _make_plan(self, start: Pose2D, goal: Pose2D) -> PlanResult:
        if not (finite_pose(start) and finite_pose(goal)):
            return PlanResult.failure(PlanReason.INVALID_POSE)
        cm, p = self.costmap, self.params
        s = self._to_map(start)
        if s is None:
            return PlanResult.failure(PlanReason.START_OUTSIDE_MAP)
        g = self._to_map(goal)
        if g is None:
            return PlanResult.failure(PlanReason.GOAL_OUTSIDE_MAP)
        gc = cm.world_to_map(goal.x, goal.y)
        nx, ny = cm.size_x, cm.size_y
        lethal, neutral = p.lethal_cost, p.neutral_cost
        lut, tables = _gp_tables(lethal, neutral, p.cost_factor, bool(p.allow_unknown))
        ws = self._ws
        ws.ensure(nx, ny)
        if cm.costs.dtype != np.uint8:
            raise TypeError(f"costmap costs must be uint8, got {cm.costs.dtype}")
        sc = cm.world_to_map(start.x, start.y)
        if not p.old_navfn_behavior and lut[cm.costs[sc[1], sc[0]]] >= lethal:
            # the robot's cell is one it may not enter (inscribed or lethal): report it, as
            # Nav2's planners do, instead of clearing the cell and planning from it (navfn)
            return PlanResult.failure(PlanReason.START_OCCUPIED)
        costs = np.ascontiguousarray(cm.costs).reshape(-1)
        sx, sy = s
        band = BAND_NEUTRALS * neutral
        if p.reuse_search and p.use_dijkstra and gc is not None \
                and 0 < gc[0] < nx - 1 and 0 < gc[1] < ny - 1 \
                and lut[costs[gc[1] * nx + gc[0]]] < lethal:
            r = self._plan_from_goal(costs, tables, lut, s, g, start, goal)
            if r is not None:
                return r
            # the robot cannot be reached from the goal: the robot-rooted search says why
        seeds_a, pots_a, pushes_a = self._seeds(sx, sy)
        target = int(g[1]) * nx + int(g[0])
        if p.use_dijkstra:
            hkind, hscale = HEURISTIC_NONE, 0.0
        elif p.use_quadratic:
            # not exact for the quadratic update (see wavefront): a little above Dijkstra
            hkind, hscale = HEURISTIC_EUCLIDEAN, ASTAR_QUADRATIC_SCALE * neutral
            band = ASTAR_QUADRATIC_BAND * neutral
        else:
            # exact: every step costs at least neutral_cost, so this is consistent
            hkind, hscale = HEURISTIC_MANHATTAN, float(neutral)
        reached, self.last_updates, _ = run_wavefront(
            ws, costs, tables, nx, ny, seeds_a, pots_a, pushes_a, target, float(lethal),
            float(band), 2 * nx * ny,
            p.use_quadratic, hkind, hscale)
        publish = p.publish_potential or p.visualize_potential
        potential = ws.pot.reshape(ny, nx) if publish else None
        goal_pose = goal
        if not reached:
            best = search_tolerance(cm, ws.pot, goal, p.default_tolerance) \
                if p.default_tolerance > 0.0 else None
            if best is None:
                passable = lut[cm.costs] < lethal
                return PlanResult.failure(diagnose(passable, gc, self.last_updates), potential)
            goal_pose = Pose2D(best[0], best[1], goal.theta)
            g = self._to_map(goal_pose)
            gc = cm.world_to_map(goal_pose.x, goal_pose.y)
        if not p.old_navfn_behavior:
            self._clear_endpoint(costs, ws.pot, gc, nx, ny)
        if p.use_grid_path:
            ok, xy = grid_path(ws.pot, nx, ny, g[0], g[1], sx, sy, 4 * nx * ny)
        else:
            ok, xy = gradient_path(ws.pot, nx, ny, g[0], g[1], STOP_NEAR_POINT, sx, sy,
                                   4 * nx * ny, float(lethal))
        if not ok or len(xy) == 0:
            return PlanResult.failure(PlanReason.NO_PATH, potential)
        return self._to_result(xy[::-1], sx, sy, start, goal_pose, potential)

    def _seeds(self, x: float, y: float) -> tuple:
        """Seed cells, their potentials and the cells the wave starts from, for a wave from the
        map point (x, y) (fractional cells): the 2x2 block around it, or its cell alone with
        ``old_navfn_behavior``."""
        nx = self.costmap.size_x
        k = int(y) * nx + int(x)
        if self.params.old_navfn_behavior:
            seeds, seed_pots = [k], [0.0]
            pushes = [k + 1, k - 1, k - nx, k + nx]
        else:
            dx = np.floor((x - int(x)) * 100 + 0.5) / 100
            dy = np.floor((y - int(y)) * 100 + 0.5) / 100
            two_n = 2.0 * self.params.neutral_cost
            seeds = [k, k + 1, k + nx, k + nx + 1]
            seed_pots = [two_n * dx * dy, two_n * (1 - dx) * dy, two_n * dx * (1 - dy),
                         two_n * (1 - dx) * (1 - dy)]
            pushes = [k + 2, k - 1, k + nx - 1, k + nx + 2, k - nx, k - nx + 1, k + 2 * nx,
                      k + 2 * nx + 1]
        return (np.array(seeds, np.int64), np.array(seed_pots, np.float32),
                np.array(pushes, np.int64))

    def _plan_from_goal(self, costs: np.ndarray, tables: tuple, lut: np.ndarray,
                        s: tuple[float, float], g: tuple[float, float], start: Pose2D,
                        goal: Pose2D) -> PlanResult | None:
        """``reuse_search`` (Dijkstra only): the field seeded at the goal, final up to the robot
        (repaired from the last one when only a few costs changed), the path descending from
        the robot; ``clearEndpoint`` acts around the robot and is undone afterwards, so the
        field stays reusable."""
        cm, p, ws = self.costmap, self.params, self._ws
        nx, ny = cm.size_x, cm.size_y
        (sx, sy), (gx, gy) = s, g
        lethal = p.lethal_cost
        k = int(sy) * nx + int(sx)
        _, self.last_updates, _, self.last_repaired = plan_field(
            ws, costs, tables, nx, ny, *self._seeds(gx, gy), k, float(lethal),
            float(BAND_NEUTRALS * p.neutral_cost), 2 * nx * ny, p.use_quadratic,
            descent_margin(lut, cm.costs, (int(sx), int(sy)), lethal))
        pot = ws.pot
        if pot[k] >= POT_HIGH:
            return None
        block = np.array([(int(sy) + j) * nx + int(sx) + i for j in range(-2, 3)
                          for i in range(-2, 3) if 0 <= int(sx) + i < nx and 0 <= int(sy) + j < ny])
        saved = pot[block].copy()
        if not p.old_navfn_behavior:
            self._clear_endpoint(costs, pot, (int(sx), int(sy)), nx, ny)
        if p.use_grid_path:
            ok, xy = grid_path(pot, nx, ny, sx, sy, gx, gy, 4 * nx * ny)
        else:
            ok, xy = gradient_path(pot, nx, ny, sx, sy, STOP_NEAR_POINT, gx, gy, 4 * nx * ny,
                                   float(lethal))
        pot[block] = saved
        if not ok or len(xy) == 0:
            return None
        publish = p.publish_potential or p.visualize_potential
        return self._to_result(xy, sx, sy, start, goal, pot.reshape(ny, nx) if publish else None)

    def _to_result(self, pts: np.ndarray, sx: float, sy: float, start: Pose2D, goal_pose: Pose2D,
                   potential: np.ndarray | None) -> PlanResult:
        """World poses from the cell points of a path robot -> goal, ending with the goal."""
        cm, p = self.costmap, self.params
        off = 0.0 if p.old_navfn_behavior else 0.5
        if not p.old_navfn_behavior:
            # the path's last point is exactly the goal, which is appended below; a start in the
            # goal's own cell leaves nothing else, so the start itself leads
            pts = pts[:-1] if len(pts) > 1 else np.array([[sx, sy]])
        poses = np.zeros((len(pts) + 1, 3))
        poses[:-1, 0] = cm.origin_x + (pts[:, 0] + off) * cm.resolution
        poses[:-1, 1] = cm.origin_y + (pts[:, 1] + off) * cm.resolution
        poses[-1] = (goal_pose.x, goal_pose.y, goal_pose.theta)
        apply_orientation(poses, start, p.orientation_mode, p.orientation_window_size)
        return PlanResult(True, Path(poses), PlanReason.NONE, potential)

    def _clear_endpoint(self, costs: np.ndarray, pot: np.ndarray, gc: tuple[int, int], nx: int,
                        ny: int) -> None:
        """Give unreached cells in the 5x5 around the goal a potential (``clearEndpoint``)."""
        gx, gy = gc
        neutral = self.params.neutral_cost
        for j in range(-2, 3):
            for i in range(-2, 3):
                x, y = gx + i, gy + j
                if not (1 <= x < nx - 1 and 1 <= y < ny - 1):
                    continue
                n = y * nx + x
                if pot[n] < POT_HIGH:
                    continue
                # the C++ hands cost + neutral to an unsigned char parameter: it wraps at 256
                c = float((int(costs[n]) + neutral) & 0xFF)
                if c <= 0.0:
                    continue
                pot[n] = np.float32(_endpoint_potential(pot, n, nx, c, self.params.use_quadratic))
