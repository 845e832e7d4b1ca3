"""Global planners: reasons instead of exceptions, exact Dijkstra/A* against a plain graph search,
paths clear of lethal cells, no dropped cells on big open maps, carrot planner, make_planner."""

from __future__ import annotations

import heapq
import math

import numpy as np
import pytest

from navcore.costmap.costmap2d import Costmap2D
from navcore.params import ParameterError
from navcore.planners import (PLANNER_KINDS, CarrotPlanner, GlobalPlanner, NavFn, PlanResult,
                              make_planner)
from navcore.planners.global_planner import global_planner_cost_table
from navcore.planners.navfn import navfn_cost_table
from navcore.types import Pose2D

RES = 0.1


def centre(cm: Costmap2D, mx: int, my: int, theta: float = 0.0) -> Pose2D:
    return Pose2D(*cm.map_to_world(mx, my), theta)


def walled(nx: int, ny: int) -> Costmap2D:
    """Open costmap with a vertical lethal wall x = nx//2 for y < ny-6 (a gap at the top)."""
    cm = Costmap2D(nx, ny, RES)
    cm.costs[: ny - 6, nx // 2] = 254
    return cm


def reference_dijkstra(cell_cost: np.ndarray, passable: np.ndarray, start: tuple[int, int]
                       ) -> np.ndarray:
    """Plain 4-connected node-weighted Dijkstra with heapq: entering a cell costs its cost."""
    ny, nx = cell_cost.shape
    dist = np.full((ny, nx), np.inf)
    sx, sy = start
    dist[sy, sx] = 0.0
    heap = [(0.0, sx, sy)]
    while heap:
        d, x, y = heapq.heappop(heap)
        if d > dist[y, x]:
            continue
        for ax, ay in ((x - 1, y), (x + 1, y), (x, y - 1), (x, y + 1)):
            if 0 < ax < nx - 1 and 0 < ay < ny - 1 and passable[ay, ax]:
                nd = d + cell_cost[ay, ax]
                if nd < dist[ay, ax]:
                    dist[ay, ax] = nd
                    heapq.heappush(heap, (nd, ax, ay))
    return dist


def random_costmap(rng: np.random.Generator, nx: int, ny: int) -> Costmap2D:
    cm = Costmap2D(nx, ny, RES)
    c = rng.integers(0, 253, size=(ny, nx)).astype(np.uint8)
    c[rng.random((ny, nx)) < 0.45] = 0
    c[rng.random((ny, nx)) < 0.18] = 254
    c[rng.random((ny, nx)) < 0.04] = 255
    cm.costs[:] = c
    return cm


# ---------------------------------------------------------------- reasons, never exceptions

@pytest.mark.parametrize("kind", ["navfn/NavfnROS", "global_planner/GlobalPlanner"])
def test_grid_planners_give_reasons_instead_of_raising(kind: str) -> None:
    cm = walled(40, 30)
    p = make_planner(kind, cm)
    ok = p.make_plan(centre(cm, 3, 3), centre(cm, 36, 3))
    assert ok.ok and ok.reason == "" and len(ok.path) > 2
    assert p.make_plan(Pose2D(-1.0, 0.5), centre(cm, 36, 3)).reason == "start_outside_map"
    assert p.make_plan(centre(cm, 3, 3), Pose2D(4.1, 0.5)).reason == "goal_outside_map"
    assert p.make_plan(centre(cm, 3, 3), centre(cm, 20, 10)).reason == "goal_occupied"
    assert p.make_plan(Pose2D(math.nan, 0.2), centre(cm, 36, 3)).reason == "invalid_pose"
    # close the gap: the two halves are no longer connected
    cm.costs[:, 20] = 254
    assert p.make_plan(centre(cm, 3, 3), centre(cm, 36, 3)).reason == "no_path"
    # box the robot in: every neighbour lethal
    cm.costs[:] = 0
    cm.costs[7:14, 7:14] = 254
    cm.costs[10, 10] = 0
    r = p.make_plan(centre(cm, 10, 10), centre(cm, 36, 3))
    assert (r.ok, r.path, r.reason) == (False, None, "start_occupied")
    # the costmap may change size between calls
    cm.resize(60, 50, RES, 0.0, 0.0)
    assert p.make_plan(centre(cm, 3, 3), centre(cm, 55, 45)).ok


def test_planner_bug_raises_instead_of_reporting_no_path() -> None:
    # a bug is not "no path": the tree would answer it with recoveries (see
    # tests/test_executive.py, INTERNAL_ERROR)
    cm = walled(40, 30)
    p = NavFn(cm)
    cm.costs = None  # a broken costmap
    with pytest.raises(AttributeError):
        p.make_plan(centre(cm, 3, 3), centre(cm, 36, 3))


def test_params_are_ros_names_with_effective_defaults() -> None:
    cm = walled(20, 20)
    nf, gp = NavFn(cm), GlobalPlanner(cm)
    assert (nf.params.allow_unknown, nf.params.default_tolerance, nf.params.visualize_potential) \
        == (True, 0.0, False)
    assert (gp.params.use_dijkstra, gp.params.use_quadratic, gp.params.use_grid_path,
            gp.params.old_navfn_behavior) == (True, True, False, False)
    assert (gp.params.lethal_cost, gp.params.neutral_cost, gp.params.cost_factor) == (253, 50, 3.0)
    assert (gp.params.orientation_mode, gp.params.orientation_window_size) == (1, 1)
    with pytest.raises(ParameterError, match="cost_factor"):
        GlobalPlanner(cm, {"cost_factor": 9.0})
    with pytest.raises(ParameterError, match="did you mean 'use_dijkstra'"):
        GlobalPlanner(cm, {"use_dijkstr": True})


def test_make_planner_kinds_and_suggestion() -> None:
    cm = walled(20, 20)
    assert isinstance(make_planner("navfn/NavfnROS", cm), NavFn)
    assert isinstance(make_planner("global_planner/GlobalPlanner", cm, {"cost_factor": 0.55}),
                      GlobalPlanner)
    carrot = make_planner("carrot_planner/CarrotPlanner", cm, footprint_cost=lambda x, y, t: 0)
    assert isinstance(carrot, CarrotPlanner)
    assert len(PLANNER_KINDS) == 3
    with pytest.raises(ValueError, match="did you mean 'navfn/NavfnROS'"):
        make_planner("navfn/NavFnROS", cm)
    with pytest.raises(ValueError, match="footprint_cost"):
        make_planner("carrot_planner/CarrotPlanner", cm)


# ---------------------------------------------------------------- cost transforms

def test_navfn_cost_transform() -> None:
    t = navfn_cost_table(allow_unknown=True)
    assert t[0] == 50 and t[100] == 130 and t[252] == 251  # 50 + 0.8 v, truncated
    assert t[253] == 254 and t[254] == 254  # inscribed and lethal: impassable
    assert t[255] == 253  # unknown: the dearest passable value
    assert navfn_cost_table(allow_unknown=False)[255] == 254


def test_global_planner_cost_transform() -> None:
    t = global_planner_cost_table(253, 50, 3.0, True)
    assert t[0] == 50 and t[10] == 80 and t[67] == 251 and t[68] == 252  # saturates at lethal-1
    assert t[251] == 252 and t[252] == 253 and t[254] == 253 and t[255] == 252
    assert global_planner_cost_table(253, 50, 3.0, False)[255] == 253


# ---------------------------------------------------------------- optimality

@pytest.mark.parametrize("use_dijkstra", [True, False])
def test_dijkstra_and_astar_costs_are_optimal_on_random_grids(use_dijkstra: bool) -> None:
    rng = np.random.default_rng(7 if use_dijkstra else 8)
    checked = 0
    for trial in range(25):
        nx, ny = int(rng.integers(8, 30)), int(rng.integers(8, 30))
        cm = random_costmap(rng, nx, ny)
        params = {"use_dijkstra": use_dijkstra, "use_quadratic": False, "use_grid_path": True,
                  "old_navfn_behavior": True, "cost_factor": float(rng.uniform(0.3, 3.0)),
                  "neutral_cost": int(rng.integers(10, 80))}
        gp = GlobalPlanner(cm, params)
        lut = global_planner_cost_table(253, params["neutral_cost"], params["cost_factor"], True)
        cell_cost = np.floor(lut[cm.costs]).astype(np.float64)  # the C++ hands it over as uchar
        passable = lut[cm.costs] < 253
        for _ in range(6):
            s = (int(rng.integers(1, nx - 1)), int(rng.integers(1, ny - 1)))
            g = (int(rng.integers(1, nx - 1)), int(rng.integers(1, ny - 1)))
            if s == g or not passable[g[1], g[0]]:
                continue
            ref = reference_dijkstra(cell_cost, passable, s)
            r = gp.make_plan(centre(cm, *s), centre(cm, *g))
            pot = r.potential
            if math.isinf(ref[g[1], g[0]]):
                assert not r.ok and r.reason in ("no_path", "start_occupied")
                continue
            assert r.ok, (trial, s, g, r.reason)
            checked += 1
            # the goal's potential is the least path cost, to float32 precision
            assert pot[g[1], g[0]] == pytest.approx(ref[g[1], g[0]], rel=1e-5)
            if use_dijkstra:
                # and so is every cell cheaper than the goal (the field is exact, not first-touch)
                below = ref < ref[g[1], g[0]]
                np.testing.assert_allclose(pot[below], ref[below], rtol=1e-5)
            # the grid path descends strictly from the goal to the start, clear of lethal cells
            cells = np.floor(r.path.poses[:-1, :2] / RES).astype(int)
            vals = pot[cells[:, 1], cells[:, 0]]
            assert (cells[0] == s).all() and (cells[-1] == g).all()
            assert np.all(np.diff(vals) > 0)
            assert np.all(passable[cells[1:, 1], cells[1:, 0]])  # the robot cell may be anything
            steps = np.abs(np.diff(cells, axis=0)).max(axis=1)
            assert np.all(steps == 1)  # 8-connected, no jumps
    assert checked >= 40


def test_quadratic_wavefront_matches_plain_update_in_a_corridor() -> None:
    """Along a 1-cell-wide corridor the quadratic update degenerates to the plain sum."""
    cm = Costmap2D(40, 3, RES)
    cm.costs[:] = 254
    cm.costs[1, 1:39] = 10
    gp = GlobalPlanner(cm, {"old_navfn_behavior": True})
    r = gp.make_plan(centre(cm, 2, 1), centre(cm, 30, 1))
    assert r.ok
    per_cell = 10 * 3.0 + 50
    np.testing.assert_allclose(r.potential[1, 2:31], per_cell * np.arange(29), rtol=1e-6)


# ---------------------------------------------------------------- paths

def _office_like(rng: np.random.Generator, n: int) -> Costmap2D:
    cm = Costmap2D(n, n, 0.05)
    c = np.zeros((n, n), np.uint8)
    for _ in range(n // 6):
        x, y = rng.integers(2, n - 8, size=2)
        w, h = rng.integers(1, 7, size=2)
        c[y:y + h, x:x + w] = 254
    # graded cost around obstacles (a cheap inflation: 3 cells of decreasing cost)
    lethal = c == 254
    out = c.copy()
    for k, v in ((1, 253), (2, 150), (3, 60)):
        grown = lethal.copy()
        for _ in range(k):
            g2 = grown.copy()
            g2[1:] |= grown[:-1]
            g2[:-1] |= grown[1:]
            g2[:, 1:] |= grown[:, :-1]
            g2[:, :-1] |= grown[:, 1:]
            grown = g2
        out = np.where(grown & (out < v), v, out)
    cm.costs[:] = out
    return cm


@pytest.mark.parametrize("kind,params", [
    ("navfn/NavfnROS", {}),
    ("global_planner/GlobalPlanner", {}),
    ("global_planner/GlobalPlanner", {"use_dijkstra": False}),
    ("global_planner/GlobalPlanner", {"use_grid_path": True, "use_dijkstra": False}),
    ("global_planner/GlobalPlanner", {"old_navfn_behavior": True, "use_quadratic": False}),
])
def test_paths_connect_start_to_goal_and_never_touch_lethal_cells(kind: str, params: dict) -> None:
    rng = np.random.default_rng(3)
    cm = _office_like(rng, 120)
    p = make_planner(kind, cm, params)
    corner = 0.0 if kind.startswith("navfn") or params.get("old_navfn_behavior") else 0.5
    found = 0
    for _ in range(12):
        s, g = rng.integers(2, 118, size=(2, 2))
        if cm.costs[s[1], s[0]] != 0 or cm.costs[g[1], g[0]] != 0:
            continue
        start, goal = centre(cm, *s, 0.3), centre(cm, *g, -1.2)
        r = p.make_plan(start, goal)
        if not r.ok:
            assert r.reason == "no_path"
            continue
        found += 1
        xy = r.path.poses[:, :2]
        assert tuple(r.path.poses[-1]) == pytest.approx((goal.x, goal.y, goal.theta))
        assert np.hypot(*(xy[0] - (start.x, start.y))) <= 0.05 * 0.75
        # each pose's own cell (cell i sits at coordinate i + corner) is never lethal
        cells = np.floor((xy - 0.05 * (0.5 - corner)) / 0.05 + 0.5).astype(int)
        assert np.all(cm.costs[cells[:, 1], cells[:, 0]] < 254)
        assert np.all(np.hypot(*np.diff(xy, axis=0).T) <= 0.05 * 1.5)  # no jumps
    assert found >= 5


def test_gradient_path_is_shorter_than_grid_path_and_close_to_straight() -> None:
    cm = Costmap2D(200, 200, 0.05)
    start, goal = centre(cm, 10, 10), centre(cm, 190, 150)
    straight = start.distance_to(goal)
    grad = GlobalPlanner(cm).make_plan(start, goal)
    grid = GlobalPlanner(cm, {"use_grid_path": True}).make_plan(start, goal)
    nav = NavFn(cm).make_plan(start, goal)
    assert grad.ok and grid.ok and nav.ok
    assert grad.path.length() < straight * 1.03
    assert nav.path.length() < straight * 1.03
    assert grid.path.length() > grad.path.length()


def reference_gradient_path(pot: np.ndarray, nx: int, ny: int, fx: float, fy: float,
                            stop_mode: int, tx: float, ty: float, max_steps: int,
                            obs_grad: float) -> tuple:
    """navfn's calcPath written plainly (every gradient computed afresh, no layouts)."""
    ns, high = nx * ny, 1e10

    def grad(n: int) -> tuple:
        if n < nx or n > ns - nx:
            return 0.0, 0.0
        cv, pl, pr, pu, pd = pot[n], pot[n - 1], pot[n + 1], pot[n - nx], pot[n + nx]
        dx = dy = 0.0
        if cv >= high:
            dx = -obs_grad if pl < high else obs_grad if pr < high else 0.0
            dy = -obs_grad if pu < high else obs_grad if pd < high else 0.0
        else:
            # float32 differences summed in double, as the kernel does
            dx = float(pl - cv if pl < high else 0.0) + float(cv - pr if pr < high else 0.0)
            dy = float(pu - cv if pu < high else 0.0) + float(cv - pd if pd < high else 0.0)
        norm = float(np.hypot(dx, dy))  # libm's, as compiled code calls
        return ((float(np.float32(dx / norm)), float(np.float32(dy / norm))) if norm > 0.0
                else (0.0, 0.0))

    def half_away(v: float) -> int:
        return int(math.floor(v + 0.5)) if v >= 0.0 else -int(math.floor(-v + 0.5))

    fx, fy = float(fx), float(fy)
    stc, dx, dy = int(fy) * nx + int(fx), fx - int(fx), fy - int(fy)
    pts: list = []
    for _ in range(max_steps):
        px, py = stc % nx + dx, stc // nx + dy
        if stop_mode == 0:
            near = min(ns - 1, max(0, stc + half_away(dx) + nx * half_away(dy)))
            if pot[near] < 50.0:
                return True, pts + [(tx, ty)]
        elif abs(px - tx) < 0.5 and abs(py - ty) < 0.5:
            return True, pts + [(tx, ty)]
        if stc < nx or stc >= ns - nx:
            break
        pts.append((px, py))
        around = [stc + j * nx + i for j in (-1, 0, 1) for i in (-1, 0, 1)]
        if (len(pts) > 2 and pts[-1] == pts[-3]) or any(pot[c] >= high for c in around):
            minc, minp = stc, float(int(pot[stc]))
            for c in (stc - nx - 1, stc - nx, stc - nx + 1, stc - 1, stc + 1, stc + nx - 1,
                      stc + nx, stc + nx + 1):
                if pot[c] < minp:
                    minc, minp = c, float(int(pot[c]))
            stc, dx, dy = minc, 0.0, 0.0
            if pot[stc] >= high:
                break
            continue
        (x00, y00), (x10, y10) = grad(stc), grad(stc + 1)
        (x01, y01), (x11, y11) = grad(stc + nx), grad(stc + nx + 1)
        gx = (1 - dy) * ((1 - dx) * x00 + dx * x10) + dy * ((1 - dx) * x01 + dx * x11)
        gy = (1 - dy) * ((1 - dx) * y00 + dx * y10) + dy * ((1 - dx) * y01 + dx * y11)
        if gx == 0.0 and gy == 0.0:
            break
        ss = 0.5 / float(np.hypot(gx, gy))
        dx, dy = dx + gx * ss, dy + gy * ss
        stc += int(dx > 1.0) - int(dx < -1.0) + nx * (int(dy > 1.0) - int(dy < -1.0))
        dx += int(dx < -1.0) - int(dx > 1.0)
        dy += int(dy < -1.0) - int(dy > 1.0)
        if stc < 0 or stc >= ns:
            break
    return False, pts


def test_gradient_path_matches_the_plain_reference() -> None:
    """The compiled descent (corner gradients kept while it stays in a cell, one max for the
    unreached-neighbour test) gives exactly the plain transcription's points, both stop modes,
    on the potentials of random maps, read through the wavefront's strided view of its records
    as from a contiguous copy."""
    from navcore.planners.traceback import gradient_path

    rng = np.random.default_rng(8)
    compared = 0
    for _ in range(12):
        nx, ny = int(rng.integers(20, 70)), int(rng.integers(20, 70))
        cm = random_costmap(rng, nx, ny)
        free = np.argwhere(cm.costs[1:-1, 1:-1] == 0) + 1
        planner = NavFn(cm, {"visualize_potential": True})
        for _ in range(3):
            (sy, sx), (gy, gx) = free[rng.integers(len(free), size=2)]
            planner.make_plan(centre(cm, sx, sy), centre(cm, gx, gy))
            pot = planner._ws.pot
            assert pot.strides == (8,)  # the potential half of the 8-byte records
            for stop, tx, ty in ((0, float(sx), float(sy)), (1, sx + 0.3, sy - 0.2)):
                args = (nx, ny, gx + 0.25, gy + 0.1, stop, float(tx), float(ty), 4 * nx * ny,
                        254.0)
                ok, xy = gradient_path(pot, *args)
                ref_ok, ref = reference_gradient_path(np.ascontiguousarray(pot), *args)
                assert ok == ref_ok
                np.testing.assert_array_equal(xy, np.array(ref, float).reshape(-1, 2))
                flat_ok, flat = gradient_path(np.ascontiguousarray(pot), *args)
                assert flat_ok == ok
                np.testing.assert_array_equal(flat, xy)
                compared += ok
    assert compared >= 20


def test_navfn_default_tolerance_plans_to_the_nearest_reachable_point() -> None:
    cm = walled(40, 30)
    goal = centre(cm, 20, 10)  # inside the wall
    assert NavFn(cm).make_plan(centre(cm, 3, 3), goal).reason == "goal_occupied"
    r = NavFn(cm, {"default_tolerance": 0.25}).make_plan(centre(cm, 3, 3), goal)
    assert r.ok
    end = r.path.pose(len(r.path) - 1)
    assert 0.05 < end.distance_to(goal) <= 0.15 and end.theta == goal.theta
    off_map = Pose2D(4.05, 1.0)  # just off the right edge: reachable within tolerance
    assert NavFn(cm).make_plan(centre(cm, 3, 3), off_map).reason == "goal_outside_map"
    assert NavFn(cm, {"default_tolerance": 0.3}).make_plan(centre(cm, 3, 3), off_map).ok


def test_global_planner_default_tolerance() -> None:
    cm = walled(40, 30)
    goal = centre(cm, 20, 10)
    assert GlobalPlanner(cm).make_plan(centre(cm, 3, 3), goal).reason == "goal_occupied"
    r = GlobalPlanner(cm, {"default_tolerance": 0.25}).make_plan(centre(cm, 3, 3), goal)
    assert r.ok and r.path.pose(len(r.path) - 1).distance_to(goal) <= 0.15


def test_orientation_modes() -> None:
    cm = Costmap2D(100, 60, 0.05)
    start, goal = Pose2D(0.5, 0.5, 2.0), Pose2D(4.5, 0.5, -1.0)  # straight along +x

    def plan(mode: int) -> np.ndarray:
        r = GlobalPlanner(cm, {"orientation_mode": mode}).make_plan(start, goal)
        assert r.ok
        return r.path.poses[:, 2]

    fwd = plan(1)
    assert np.allclose(fwd[:-1], 0.0, atol=0.02) and fwd[-1] == pytest.approx(-1.0)
    assert np.allclose(plan(0)[:-1], 0.0) and plan(0)[-1] == pytest.approx(-1.0)
    assert np.allclose(plan(4)[:-1] % (2 * np.pi), np.pi, atol=0.02)  # backward
    assert np.allclose(plan(5)[:-1], -np.pi / 2, atol=0.02)  # leftward: left side leads
    assert np.allclose(plan(6)[:-1], np.pi / 2, atol=0.02)
    interp = plan(2)
    assert interp[0] == pytest.approx(2.0) and interp[-1] == pytest.approx(-1.0)
    steps = np.diff(np.unwrap(interp))
    assert np.allclose(steps, steps[0])  # evenly spread turn, shortest way (-3.0 rad)
    assert np.unwrap(interp)[-1] - interp[0] == pytest.approx(-3.0)
    fti = plan(3)
    assert fti[0] == pytest.approx(2.0) and fti[-1] == pytest.approx(-1.0)


# ---------------------------------------------------------------- no dropped cells

def test_open_map_wavefront_reaches_every_cell() -> None:
    """ROS's 10000-cell queues drop cells on big open maps (168 cells on 4000^2 from the centre);
    a 3300^2 map seeded at its centre has a front longer than 10000 cells."""
    n = 3300
    cm = Costmap2D(n, n, 0.05)
    cm.costs[n // 2 + 700, n // 2 + 700] = 254  # goal in a lethal cell: the wave covers everything
    nf = NavFn(cm, {"visualize_potential": True})
    r = nf.make_plan(centre(cm, n // 2, n // 2), centre(cm, n // 2 + 700, n // 2 + 700))
    assert r.reason == "goal_occupied"
    inner = r.potential[1:-1, 1:-1]
    assert int(np.count_nonzero(inner >= 1e10)) == 1  # only the lethal cell
    # potential grows with distance like a wave front (50 per cell)
    assert r.potential[n // 2, n // 2 + 1000] == pytest.approx(50 * 1000, rel=0.01)


# ---------------------------------------------------------------- carrot planner

def test_carrot_planner_walks_back_to_the_first_free_pose() -> None:
    cm = Costmap2D(100, 100, 0.05)
    cm.costs[40:60, 60:80] = 254  # a block between x 3.0 and 4.0 m

    def footprint_cost(x: float, y: float, theta: float) -> int:
        c = cm.world_to_map(x, y)
        if c is None:
            return -1
        # a 0.1 m "footprint": the max over a 5x5 block
        return int(cm.costs[max(c[1] - 2, 0):c[1] + 3, max(c[0] - 2, 0):c[0] + 3].max())

    cp = CarrotPlanner(cm, footprint_cost)
    assert cp.params.step_size == 0.05 and cp.params.min_dist_from_robot == 0.10
    start = Pose2D(1.0, 2.5, 0.0)
    free = cp.make_plan(start, Pose2D(2.0, 2.5, 1.0))
    assert free.ok and len(free.path) == 2
    assert tuple(free.path.poses[1]) == pytest.approx((2.0, 2.5, 1.0))
    r = cp.make_plan(start, Pose2D(3.5, 2.5, 1.0))
    assert r.ok
    x, y, th = r.path.poses[1]
    assert y == pytest.approx(2.5) and 2.85 <= x < 2.95  # first pose whose 5x5 is clear of x 3.0
    assert footprint_cost(x, y, th) < 254 and footprint_cost(x + 0.05, y, th) == 254
    assert 0.0 < th < 1.0  # heading interpolated from the robot's toward the goal's
    blocked = CarrotPlanner(cm, footprint_cost, {"min_dist_from_robot": 0.1})
    near = Pose2D(2.95, 2.5)
    assert blocked.make_plan(near, Pose2D(3.5, 2.5)).reason == "goal_occupied"
    assert cp.make_plan(start, Pose2D(9.0, 2.5)).reason == "goal_outside_map"
    assert cp.make_plan(Pose2D(-1, 0), Pose2D(2.0, 2.5)).reason == "start_outside_map"
    bad = CarrotPlanner(cm, lambda x, y, t: 1 // 0)
    with pytest.raises(ZeroDivisionError):                 # a bug, not "no path"
        bad.make_plan(start, Pose2D(2.0, 2.5))


def test_plan_result_failure() -> None:
    r = PlanResult.failure("no_path")
    assert (r.ok, r.path, r.reason, r.potential) == (False, None, "no_path", None)


def test_carrot_planner_with_the_costmap_footprint_cost() -> None:
    from navcore.planners import costmap_footprint_cost

    cm = Costmap2D(100, 100, 0.05)
    cm.costs[:, 60:] = 254  # a wall from x = 3.0 m on
    square = np.array([[0.2, 0.2], [0.2, -0.2], [-0.2, -0.2], [-0.2, 0.2]])
    cp = make_planner("carrot_planner/CarrotPlanner", cm,
                      footprint_cost=costmap_footprint_cost(cm, square))
    r = cp.make_plan(Pose2D(1.0, 2.5), Pose2D(3.5, 2.5))
    assert r.ok
    x = r.path.poses[1, 0]
    assert 2.7 < x < 2.81  # the 0.4 m square's front edge stops short of the wall
    cm.costs[:, 40:] = 254  # the costmap changes: the planner reads it at call time
    assert cp.make_plan(Pose2D(1.0, 2.5), Pose2D(3.5, 2.5)).path.poses[1, 0] < 1.8


@pytest.mark.parametrize("kind,params", [
    ("navfn/NavfnROS", {}), ("global_planner/GlobalPlanner", {}),
    ("global_planner/GlobalPlanner", {"use_grid_path": True, "use_dijkstra": False})])
def test_degenerate_plans(kind: str, params: dict) -> None:
    cm = Costmap2D(50, 40, 0.1)
    p = make_planner(kind, cm, params)
    same = p.make_plan(Pose2D(1.0, 1.0), Pose2D(1.0, 1.0, 0.5))
    assert same.ok and tuple(same.path.poses[-1]) == pytest.approx((1.0, 1.0, 0.5))
    near = p.make_plan(Pose2D(1.0, 1.0), Pose2D(1.04, 1.02))  # same cell
    assert near.ok and len(near.path) == 2
    assert near.path.pose(0).distance_to(Pose2D(1.0, 1.0)) < 0.1
    assert tuple(near.path.poses[-1, :2]) == pytest.approx((1.04, 1.02))
    # the outer border is never planned through (navfn's COST_OBS border, outline_map)
    assert p.make_plan(Pose2D(1.0, 1.0), Pose2D(4.99, 3.99)).reason == "goal_occupied"


def test_cell_coordinates_from_the_reciprocal_match_integer_division() -> None:
    """A* recovers (x, y) from a cell index with a multiply by 1/width, not a division: it must
    give exactly divmod's answer up to the largest index of wide maps."""
    from navcore.planners.wavefront import _cell_xy

    rng = np.random.default_rng(5)
    for nx in (3, 7, 8, 999, 1000, 1165, 4000, 65_537, 1 << 20):
        ny = nx
        xs = np.concatenate([rng.integers(0, nx, 400), [0, nx - 1]])
        ys = np.concatenate([rng.integers(0, ny, 400), [ny - 1, 0]])
        for x, y in zip(xs.tolist(), ys.tolist()):
            assert _cell_xy(y * nx + x, nx, 1.0 / nx) == (x, y)


# ---------------------------------------------------------------- the kernel against a reference

def reference_wavefront(cost_lut: np.ndarray, block: float, truncate: bool, costs: np.ndarray,
                        seed: int, target: int, threshold: float, band: float, quadratic: bool,
                        hkind: int = 0, hscale: float = 0.0) -> tuple:
    """navfn's priority-block propagation written plainly (per-cell queue flags 0 idle, 1 in
    current/next, 2 in overflow; float32 arithmetic in the kernel's order), with the wavefront
    module's documented differences. Returns ``(reached, updates, potential)``."""
    f32 = np.float32
    ny, nx = costs.shape
    flat = costs.reshape(-1)
    lut = np.where(cost_lut < block, cost_lut, np.inf).astype(np.float32)
    hf_lut = (np.floor(cost_lut) if truncate else cost_lut).astype(np.float32)
    pot = np.full(nx * ny, f32(1e10), np.float32)
    border = np.zeros((ny, nx), bool)
    border[0, :] = border[-1, :] = border[:, 0] = border[:, -1] = True
    flag = np.where(border.reshape(-1), 4, 0)
    tx, ty = target % nx, target // nx

    def key(n: int, p: np.float32) -> float:
        if hkind == 0:
            return float(p)
        dx, dy = abs(n % nx - tx), abs(n // nx - ty)
        h = hscale * (dx + dy) if hkind == 1 else hscale * math.sqrt(dx * dx + dy * dy)
        return float(p) + h

    pot[seed] = f32(0.0)
    cur = []
    for m in (seed + 1, seed - 1, seed - nx, seed + nx):
        if flag[m] == 0 and lut[flat[m]] < np.inf:
            cur.append(m)
            flag[m] = 1
    t = f32(threshold + (key(seed, f32(0.0)) if hkind else 0.0))
    nxt, over, updates, from_over = [], [], 0, False
    while cur:
        if from_over:
            for n in cur:
                flag[n] = 0
        for n in cur:
            if not from_over:
                flag[n] = 0
            updates += 1
            hf = hf_lut[flat[n]]
            nb = (n - 1, n + 1, n - nx, n + nx)
            l, r, u, d = (pot[m] for m in nb)
            tc, ta0 = min(l, r), min(u, d)
            ta = min(ta0, tc)
            if quadratic:
                dc = abs(tc - ta0)
                q = dc * f32(1.0 / float(hf))
                p = ta + hf if dc >= hf else \
                    ta + hf * (f32(-0.2301) * q * q + f32(0.5307) * q + f32(0.7040))
            else:
                p = ta + hf
            if not p < pot[n]:
                continue
            pot[n] = p
            below = key(n, p) < float(t)
            for m in nb:
                if not pot[m] > p + f32(0.707106781) * lut[flat[m]]:
                    continue
                if below and flag[m] in (0, 2):
                    nxt.append(m)
                    flag[m] = 1
                elif not below and flag[m] == 0:
                    over.append(m)
                    flag[m] = 2
        cur, nxt, from_over = nxt, [], False
        if not cur:
            if pot[target] < t:
                return True, updates, pot
            t = f32(t + f32(band))
            cur, over, from_over = over, [], True
    return bool(pot[target] < 1e10), updates, pot


def kernel_agrees_with_reference(quadratic: bool, hkind: int, trials: int = 12,
                                 variant: tuple | None = None) -> None:
    """The compiled kernel (``variant`` (prefetch, compress), default the planners' own) against
    ``reference_wavefront`` on random costmaps (see the test)."""
    from navcore.planners import wavefront
    from navcore.planners.wavefront import Workspace, kernel_tables, run_wavefront

    if variant is not None:
        key = (quadratic, hkind != 0, *variant)
        if key not in wavefront._PROPAGATE:
            wavefront._PROPAGATE[key] = wavefront._make_propagate(*key)
        saved, wavefront.KERNEL_VARIANT = wavefront.KERNEL_VARIANT, variant
        try:
            kernel_agrees_with_reference(quadratic, hkind, trials)
        finally:
            wavefront.KERNEL_VARIANT = saved
        return

    rng = np.random.default_rng(21)
    for trial in range(trials):
        nx, ny = int(rng.integers(6, 30)), int(rng.integers(6, 30))
        costs = random_costmap(rng, nx, ny).costs
        lut = global_planner_cost_table(253, int(rng.integers(5, 80)),
                                        float(rng.uniform(0.3, 3.0)), True) \
            if trial % 2 else navfn_cost_table(True)
        block, truncate = (253.0, True) if trial % 2 else (254.0, False)
        free = np.argwhere(lut[costs[1:-1, 1:-1]] < block) + 1
        if len(free) < 2:
            continue
        (sy, sx), (gy, gx) = free[rng.choice(len(free), 2, replace=False)]
        seed, target = int(sy * nx + sx), int(gy * nx + gx)
        band = float(rng.choice([20.0, 100.0, 500.0]))
        hscale = 0.0 if hkind == 0 else float(lut.min()) * (0.99 if hkind == 2 else 1.0)
        ref = reference_wavefront(lut, block, truncate, costs, seed, target, block, band,
                                  quadratic, hkind, hscale)
        ws = Workspace()
        ws.ensure(nx, ny)
        reached, updates, _ = run_wavefront(
            ws, costs.reshape(-1), kernel_tables(lut, block, truncate), nx, ny,
            np.array([seed], np.int64), np.array([0.0], np.float32),
            np.array([seed + 1, seed - 1, seed - nx, seed + nx], np.int64), target, block,
            band, 2 * nx * ny, quadratic, hkind, hscale)
        assert (reached, updates) == ref[:2], trial
        np.testing.assert_array_equal(ws.pot, ref[2])


@pytest.mark.parametrize("quadratic,hkind", [(True, 0), (False, 0), (False, 1), (True, 2)])
def test_wavefront_kernel_matches_the_plain_reference(quadratic: bool, hkind: int) -> None:
    """The plain kernel (queue flags and push costs folded into one float32 gate, kept with
    the potential in one 8-byte record per cell, branch-free pushes, one variant per
    update/search kind) visits cells exactly as the plain propagation above: same updates,
    bit-identical potentials, on random costmaps and band widths."""
    kernel_agrees_with_reference(quadratic, hkind, variant=(False, False))


@pytest.mark.parametrize("quadratic,hkind", [(True, 0), (False, 0), (False, 1), (True, 2)])
def test_fast_wavefront_kernel_matches_the_plain_reference(quadratic: bool, hkind: int) -> None:
    """The fast variant (prefetch hints and the four pushes as one vector step with a
    compress, LLVM IR in navcore/prefetch.py and navcore/planners/push4.py) gives the
    same updates and potentials on every host: LLVM expands the compress where the CPU lacks it."""
    kernel_agrees_with_reference(quadratic, hkind, variant=(True, True))


def test_wavefront_kernel_without_avx512_matches_the_plain_reference(tmp_path) -> None:
    """Compiled for a Haswell (no AVX-512; a fresh numba cache) the planners run the prefetching
    kernel with the integer-select pushes (no vector push): check that build against the
    reference too."""
    import os
    import subprocess
    import sys
    from pathlib import Path

    script = (
        "import sys\n"
        f"sys.path.insert(0, {str(Path(__file__).parent)!r})\n"
        "from navcore.planners.wavefront import KERNEL_VARIANT\n"
        "assert KERNEL_VARIANT == (True, False), KERNEL_VARIANT\n"
        "import test_planners as t\n"
        "t.kernel_agrees_with_reference(True, 0, trials=6)\n"
        "t.kernel_agrees_with_reference(False, 1, trials=6)\n"
        "print('agrees')\n")
    features = ("+64bit,+avx,+avx2,+bmi,+bmi2,+cmov,+cx16,+f16c,+fma,+lzcnt,+movbe,+popcnt,+sse,"
                "+sse2,+sse3,+sse4.1,+sse4.2,+ssse3,+xsave")
    env = dict(os.environ, NUMBA_CPU_NAME="haswell", NUMBA_CPU_FEATURES=features,
               NUMBA_CACHE_DIR=str(tmp_path))
    out = subprocess.run([sys.executable, "-c", script], env=env, capture_output=True, text=True,
                         timeout=900)
    assert out.returncode == 0 and "agrees" in out.stdout, out.stderr[-3000:]


def test_wavefront_leaves_the_gate_idle_and_reused_buffers_give_fresh_results() -> None:
    """A run ends with every gate idle (cells still queued get their push cost back), exactly
    as a fresh reset leaves it, also when cut short by ``max_cycles``; the next plan of that size
    then rewrites only the gates of cells whose cost changed. Plans on a reused workspace (costs
    changed here and there, on the border too, and a new cost table) must give the updates and
    potentials of a fresh workspace."""
    from navcore.planners.wavefront import (POT_HIGH, Workspace, kernel_tables, reset_records,
                                            run_wavefront)

    rng = np.random.default_rng(8)
    for trial in range(16):
        nx, ny = int(rng.integers(6, 40)), int(rng.integers(6, 40))
        costs = random_costmap(rng, nx, ny).costs.reshape(-1).copy()
        kept = Workspace()
        kept.ensure(nx, ny)
        for plan in range(5):
            if plan:  # the map changes a little between plans, border included
                k = rng.integers(nx * ny, size=int(rng.integers(0, 6)))
                costs[k] = rng.choice([0, 60, 128, 252, 253, 254, 255], size=len(k))
                costs[rng.integers(nx)] = rng.choice([0, 254])
            gp = plan % 3 == 2
            lut = global_planner_cost_table(253, 50, 3.0, bool(plan % 2)) if gp \
                else navfn_cost_table(bool(plan % 2))
            tables = kernel_tables(lut, 253.0 if gp else 254.0, gp)
            free = np.flatnonzero(lut[costs] < (253 if gp else 254))
            if len(free) < 2:
                continue
            seed, target = (int(v) for v in rng.choice(free, 2, replace=False))
            cycles = int(rng.choice([3, 10, 2 * nx * ny]))
            args = (np.array([seed], np.int64), np.array([0.0], np.float32),
                    np.array([seed + 1, seed - 1, seed - nx, seed + nx], np.int64), target,
                    float(tables[0][0]), 100.0, cycles, bool(plan % 2), int(trial % 2), 40.0)
            fresh = Workspace()
            fresh.ensure(nx, ny)
            want = run_wavefront(fresh, costs, tables, nx, ny, *args)
            got = run_wavefront(kept, costs, tables, nx, ny, *args)
            assert got == want, (trial, plan)
            np.testing.assert_array_equal(kept.pot, fresh.pot)
            # the gates each run leaves behind are the ones a fresh reset builds
            rec = np.empty_like(kept.rec)
            reset_records(rec, costs, tables[0], nx, ny)
            np.testing.assert_array_equal(kept.rec[1::2], rec[1::2])
            np.testing.assert_array_equal(fresh.rec[1::2], rec[1::2])
            assert (rec[0::2] == POT_HIGH).all()


def test_zero_tolerance_search_is_the_goal_cell_test() -> None:
    """With no tolerance the search has one sample, the goal itself: it must answer as the
    sampled square does for it (goal kept when its cell is on the map and reached), also for
    goals on cell edges and just off the map, and read through a strided view of records."""
    from navcore.planners.common import search_tolerance
    from navcore.planners.wavefront import POT_HIGH

    rng = np.random.default_rng(4)
    for trial in range(40):
        nx, ny = int(rng.integers(3, 30)), int(rng.integers(3, 30))
        cm = Costmap2D(nx, ny, 0.05, float(rng.uniform(-1, 1)), float(rng.uniform(-1, 1)))
        pot = np.where(rng.random(nx * ny) < 0.3, POT_HIGH, rng.random(nx * ny) * 1e3)
        pot = pot.astype(np.float32)
        rec = np.full(2 * nx * ny, np.inf, np.float32)
        rec[0::2] = pot
        for grid in (pot, rec[0::2]):
            for _ in range(10):
                cx, cy = rng.integers(-2, nx + 2), rng.integers(-2, ny + 2)
                frac = rng.choice([0.0, 0.5, 0.999999, -0.0])
                goal = Pose2D(cm.origin_x + (cx + frac) * 0.05, cm.origin_y + (cy + frac) * 0.05)
                # the square's sampling (as for a tolerance) with its one sample
                sx = goal.x + (-0.0 + 0.05 * np.arange(1))
                sy = goal.y + (-0.0 + 0.05 * np.arange(1))
                mx = np.floor((sx - cm.origin_x) / 0.05).astype(np.int64)
                my = np.floor((sy - cm.origin_y) / 0.05).astype(np.int64)
                inside = (sx >= cm.origin_x) & (sy >= cm.origin_y) & (mx < nx) & (my < ny)
                want = (float(sx[0]), float(sy[0])) \
                    if inside[0] and pot[my[0] * nx + mx[0]] < POT_HIGH else None
                got = search_tolerance(cm, grid, goal, 0.0)
                assert got == want, (trial, goal, got, want)


def test_descent_direction_is_zero_on_the_whole_last_row_without_reading_past_the_map():
    from navcore.planners.traceback import _grad_cell
    nx, ny = 5, 4
    ns = nx * ny
    # a finite field everywhere, and one finite value just past the map's end: a cell test that
    # lets the last row's first cell through reads it and returns a non-zero direction
    memory = np.arange(ns + nx, dtype=np.float32)[::-1].copy()
    pot = memory[:ns]
    for n in range(ns - nx, ns):
        assert _grad_cell(pot, n, nx, ns, 1.0) == (0.0, 0.0)
    assert _grad_cell(pot, ns - 2 * nx, nx, ns, 1.0) != (0.0, 0.0)  # the row above has one


# ---------------------------------------------------------------- replanning by repair

def _replan_sequence(rng: np.random.Generator, quadratic: bool, nx: int, ny: int,
                     plans: int = 6) -> list:
    """Plans toward one goal on a random costmap whose costs change a little between plans
    while the robot moves: (repaired field, fresh field, target, margin, repaired?) each."""
    from navcore.planners.wavefront import Workspace, descent_margin, kernel_tables, plan_field

    costs2d = random_costmap(rng, nx, ny).costs
    lut = navfn_cost_table(True)
    tables = kernel_tables(lut, 254.0, False)
    free = np.argwhere(lut[costs2d[1:-1, 1:-1]] < 254) + 1
    gy, gx = free[rng.integers(len(free))]
    g = int(gy * nx + gx)
    seeds = (np.array([g], np.int64), np.array([0.0], np.float32),
             np.array([g + 1, g - 1, g - nx, g + nx], np.int64))
    kept = Workspace()
    kept.ensure(nx, ny)
    out = []
    for plan in range(plans):
        if plan:
            k = rng.integers(nx * ny, size=int(rng.integers(1, 12)))
            costs2d.reshape(-1)[k] = rng.choice([0, 40, 128, 252, 253, 254, 255], size=len(k))
            costs2d.reshape(-1)[g] = 0  # the goal stays passable (a changed seed: plan afresh)
        ry, rx = free[rng.integers(len(free))]
        target = int(ry * nx + rx)
        costs = costs2d.reshape(-1).copy()
        margin = descent_margin(lut, costs2d, (int(rx), int(ry)), 254.0)
        args = (costs, tables, nx, ny, *seeds, target, 254.0, 100.0, 2 * nx * ny, quadratic,
                margin)
        got = plan_field(kept, *args)
        fresh = Workspace()
        fresh.ensure(nx, ny)
        want = plan_field(fresh, *args)
        assert got[0] == want[0] and not want[3]
        out.append((kept.pot.copy(), fresh.pot.copy(), target, margin, got[3]))
    return out


def test_replan_repairs_to_the_from_scratch_field_on_random_changes() -> None:
    """A goal-rooted field repaired after random cost changes (lethal, free, unknown, on the
    border too) with the robot moved equals the field planned afresh, bit for bit, on every cell
    the descent from the robot can read (below the robot's potential plus the margin), with the
    plain update and with the quadratic one (its monotone form, which makes the field
    independent of the visiting order). Most replans are repairs; the result is
    deterministic."""
    rng = np.random.default_rng(5)
    repairs = compared = 0
    for trial in range(12):
        quadratic = bool(trial % 3)
        nx, ny = int(rng.integers(12, 40)), int(rng.integers(12, 40))
        state = rng.bit_generator.state
        seq = _replan_sequence(rng, quadratic, nx, ny)
        rng2 = np.random.default_rng()
        rng2.bit_generator.state = state
        again = _replan_sequence(rng2, quadratic, nx, ny)
        for (got, want, target, margin, repaired), (got2, *_rest) in zip(seq, again):
            np.testing.assert_array_equal(got, got2)  # deterministic
            if want[target] >= 1e10:
                continue
            final = (want < want[target] + margin) | (got < want[target] + margin)
            compared += int(final.sum())
            repairs += repaired
            np.testing.assert_array_equal(got[final], want[final])
    assert repairs >= 30 and compared > 1000, (repairs, compared)


def reference_fixed_point(lut: np.ndarray, block: float, truncate: bool, costs: np.ndarray,
                          nx: int, ny: int, seed: int) -> np.ndarray:
    """The monotone quadratic field written plainly: navfn's update with its factor capped at 1
    (float64, rounded to float32), every cell re-queued (FIFO) whenever a neighbour drops below
    it, run until nothing changes: a fixed point that does not depend on the order."""
    from collections import deque
    lut32 = np.asarray(lut, np.float32)
    hf_lut = (np.floor(lut32) if truncate else lut32).astype(np.float32)
    pot = np.full(nx * ny, np.float32(1e10), np.float32)
    pot[seed] = 0.0

    def open_cell(n: int) -> bool:
        x, y = n % nx, n // nx
        return 0 < x < nx - 1 and 0 < y < ny - 1 and lut32[costs[n]] < block

    queue = deque(m for m in (seed - 1, seed + 1, seed - nx, seed + nx) if open_cell(m))
    queued = set(queue)
    while queue:
        n = queue.popleft()
        queued.discard(n)
        hf = hf_lut[costs[n]]
        l, r, u, d = (pot[m] for m in (n - 1, n + 1, n - nx, n + nx))
        tc, ta0 = min(l, r), min(u, d)
        q = min(abs(float(tc) - float(ta0)) * float(np.float32(1.0) / hf), 1.0)
        p = np.float32(float(min(tc, ta0)) + float(hf) * min(0.7040 + q * (0.5307 - 0.2301 * q),
                                                               1.0))
        if not p < pot[n]:
            continue
        pot[n] = p
        for m in (n - 1, n + 1, n - nx, n + nx):
            if pot[m] > p and m not in queued and open_cell(m):
                queue.append(m)
                queued.add(m)
    return pot


@pytest.mark.parametrize("variant", [(False, False), (True, True)], ids=["plain", "fast"])
def test_goal_rooted_quadratic_field_is_the_order_free_fixed_point(variant: tuple) -> None:
    """``plan_field``'s quadratic field (what ``reuse_search`` plans and repairs) is the fixed
    point of the plain FIFO propagation above, bit for bit: run to the end on every reached
    cell, and stopped at the robot on every cell below its potential plus the margin, for any
    band width. Plain kernel and the fast variant (prefetch, compressing push)."""
    from navcore.planners import wavefront
    from navcore.planners.wavefront import Workspace, descent_margin, kernel_tables, plan_field

    key = (wavefront.UPDATE_MONOTONE, False, *variant)
    if key not in wavefront._PROPAGATE:
        wavefront._PROPAGATE[key] = wavefront._make_propagate(*key)
    saved, wavefront.KERNEL_VARIANT = wavefront.KERNEL_VARIANT, variant
    try:
        rng = np.random.default_rng(12)
        for trial in range(10):
            nx, ny = int(rng.integers(8, 36)), int(rng.integers(8, 36))
            costs2d = random_costmap(rng, nx, ny).costs
            gp = bool(trial % 2)
            lut = global_planner_cost_table(253, int(rng.integers(5, 80)),
                                            float(rng.uniform(0.3, 3.0)), True) \
                if gp else navfn_cost_table(True)
            block = 253.0 if gp else 254.0
            free = np.argwhere(lut[costs2d[1:-1, 1:-1]] < block) + 1
            if len(free) < 2:
                continue
            (gy, gx), (ry, rx) = free[rng.choice(len(free), 2, replace=False)]
            g, target = int(gy * nx + gx), int(ry * nx + rx)
            costs = costs2d.reshape(-1).copy()
            view = costs.copy()
            view[target] = 0  # plan_field reads the robot's cell as free
            want = reference_fixed_point(lut, block, gp, view, nx, ny, g)
            seeds = (np.array([g], np.int64), np.array([0.0], np.float32),
                     np.array([g + 1, g - 1, g - nx, g + nx], np.int64))
            margin = descent_margin(lut, costs2d, (int(rx), int(ry)), block)
            for band, stop in ((37.0, 1e30), (500.0, 1e30), (100.0, margin), (20.0, margin)):
                ws = Workspace()
                ws.ensure(nx, ny)
                plan_field(ws, costs, kernel_tables(lut, block, gp), nx, ny, *seeds, target,
                           block, band, 10**9, True, stop)
                final = want < (1e10 if stop > 1e20 else want[target] + margin)
                np.testing.assert_array_equal(ws.pot[final], want[final], err_msg=str(trial))
                assert (ws.pot >= want).all()
    finally:
        wavefront.KERNEL_VARIANT = saved


@pytest.mark.parametrize("make", [NavFn, GlobalPlanner], ids=["navfn", "global_planner"])
def test_reuse_search_replans_by_repair_with_the_fresh_path(make) -> None:
    """``reuse_search``: a replan toward the same goal after a small cost change near the moved
    robot repairs the last field (few updates) and gives exactly the path a fresh goal-rooted
    plan gives; a new goal or a large change plans afresh; the robot-rooted
    default is untouched."""
    cm = walled(60, 50)
    goal = centre(cm, 50, 40)
    planner = make(cm, {"reuse_search": True})
    r = planner.make_plan(centre(cm, 5, 5), goal)
    assert r.ok and not planner.last_repaired
    full = planner.last_updates
    rng = np.random.default_rng(3)
    for step in range(6):
        start = Pose2D(*r.path.poses[min(5, len(r.path) - 1), :2], 0.0)
        sx, sy = cm.world_to_map(start.x, start.y)
        cm.costs[sy + 3:sy + 5, sx + int(rng.integers(-4, 4))] = 254  # a few cells near it
        r = planner.make_plan(start, goal)
        assert r.ok and planner.last_repaired, step
        assert planner.last_updates < full / 5
        fresh = make(cm, {"reuse_search": True}).make_plan(start, goal)
        np.testing.assert_array_equal(r.path.poses, fresh.path.poses)
        assert not (cm.costs[tuple(np.array([cm.world_to_map(x, y) for x, y in
                                             r.path.poses[:, :2]]).T[::-1])] >= 254).any()
    planner.make_plan(start, centre(cm, 45, 10))
    assert not planner.last_repaired  # another goal
    cm.costs[20:45, 36:44] = 254
    assert planner.make_plan(start, centre(cm, 45, 10)).ok
    assert not planner.last_repaired  # 200 cells changed, more than 2 % of the map
