"""DWAPlannerROS: sampling, grids, critics, goal handling and closed-loop behaviour."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from navcore.controllers import DWAPlanner, make_controller
from navcore.controllers.critics import (REJECTED, W_ALIGNMENT, W_GOAL, W_GOAL_FRONT, W_PATH,
                                       DwaWeights, footprint_scale, grid_critic, grid_critics)
from navcore.controllers.map_grid import densify_plan, distance_grid, local_plan, plan_cells
from navcore.controllers.oscillation import OscillationFlags
from navcore.controllers.rollout import (CONSTANT, RAMPED, filter_and_steps, simulate,
                                         velocity_iterator)
from navcore.costmap.costmap2d import Costmap2D
from navcore.costmap.footprint import footprint_cost
from navcore.params import ParameterError
from navcore.types import Path, Pose2D, Twist
from tests.test_controllers_support import RECT, drive, inflate, straight_path

DIFF = {"max_vel_y": 0.0, "min_vel_y": 0.0}  # a differential-drive robot


def empty_map(size: int = 120, res: float = 0.05, ox: float = -3.0, oy: float = -3.0) -> Costmap2D:
    return Costmap2D(size, size, res, ox, oy)


# --- building blocks ----------------------------------------------------------------------------

def test_velocity_iterator_matches_ros_sampling():
    assert velocity_iterator(0.3, 0.3, 5).tolist() == [0.3]
    assert velocity_iterator(0.0, 0.1, 1).tolist() == [0.0, 0.1]     # at least two samples
    s = velocity_iterator(-0.1, 0.1, 4).tolist()                      # crosses zero: 0 added
    assert len(s) == 5 and 0.0 in s and s[0] == -0.1 and s[-1] == 0.1
    assert velocity_iterator(-0.1, 0.1, 3).tolist() == pytest.approx([-0.1, 0.0, 0.1])


def test_filter_refuses_slow_fast_and_still_samples():
    samples = np.array([[0.05, 0.0, 0.1],   # too slow both ways -> refused
                        [0.05, 0.0, 0.5],   # slow but turning fast enough -> kept
                        [0.6, 0.0, 0.0],    # faster than max_vel_trans -> refused
                        [0.3, 0.0, 0.0]])
    kept, steps = filter_and_steps(samples, 1.7, 0.025, 0.1, 0.1, 0.4, 0.55)
    assert kept.tolist() == [[0.05, 0.0, 0.5], [0.3, 0.0, 0.0]]
    # steps = ceil(max(|v| T / sg, |w| T / ag))
    assert steps.tolist() == [math.ceil(0.5 * 1.7 / 0.1), math.ceil(0.3 * 1.7 / 0.025)]


def test_simulate_constant_arc_and_ramped_velocity():
    samples = np.array([[0.5, 0.0, 0.5]])
    steps = np.array([10])
    pts, cmd, _ = simulate(samples, steps, 1.0, 2.0, 0.0, np.zeros(3), np.array([2.5, 2.5, 3.2]),
                           1.0, CONSTANT, 0.0)
    assert pts.shape == (1, 10, 3)
    assert pts[0, 0].tolist() == [1.0, 2.0, 0.0]            # the start pose is the first point
    assert pts[0, -1, 2] == pytest.approx(0.5 * 0.9)         # the final integration is not kept
    assert cmd[0].tolist() == [0.5, 0.0, 0.5]
    pts_r, cmd_r, _ = simulate(samples, steps, 0.0, 0.0, 0.0, np.zeros(3),
                               np.array([2.5, 2.5, 3.2]), 1.0, RAMPED, 0.0)
    assert cmd_r[0, 0] == pytest.approx(0.25)                # first ramped step: a * dt
    assert np.nanmax(pts_r[0, :, 0]) < np.nanmax(pts[0, :, 0] - 1.0) + 1e-9  # slower start


def test_distance_grid_is_4_connected_bfs_with_obstacle_and_unreachable_values():
    costs = np.zeros((10, 10), dtype=np.uint8)
    costs[:, 5] = 254                      # a wall splits the map
    d = distance_grid(costs, np.array([[1, 1]]), np.zeros((0, 0), dtype=np.bool_))
    n = 100
    assert d[1, 1] == 0 and d[4, 4] == 6   # Manhattan distance
    assert (d[:, 5] == n).all()            # touched obstacles read "size"
    assert (d[:, 6:] == n + 1).all()       # the far side is unreachable: size + 1
    passable = np.zeros((10, 10), dtype=np.bool_)
    passable[3, 5] = True                  # a door the footprint covers
    d2 = distance_grid(costs, np.array([[1, 1]]), passable)
    assert d2[3, 6] == 5 + 2               # Manhattan, through the door


def _bfs_reference(costs, seeds, passable):
    """MapGrid's wavefront written plainly: a deque and bounds checks."""
    from collections import deque
    h, w = costs.shape
    n = h * w
    dist = np.full((h, w), n + 1, dtype=np.int64)
    queue = deque()
    for mx, my in seeds:
        if dist[my, mx] != 0:
            dist[my, mx] = 0
            queue.append((mx, my))
    while queue:
        mx, my = queue.popleft()
        for nx, ny in ((mx - 1, my), (mx + 1, my), (mx, my - 1), (mx, my + 1)):
            if not (0 <= nx < w and 0 <= ny < h) or dist[ny, nx] != n + 1:
                continue
            if costs[ny, nx] in (253, 254, 255) and not (passable.size and passable[ny, nx]):
                dist[ny, nx] = n
            else:
                dist[ny, nx] = dist[my, mx] + 1
                queue.append((nx, ny))
    return dist


def test_distance_grid_agrees_with_a_plain_wavefront_on_random_maps():
    rng = np.random.default_rng(6)
    for trial in range(150):
        h, w = (int(v) for v in rng.integers(1, 25, 2))
        costs = rng.choice(np.array([0, 0, 0, 50, 253, 254, 255], np.uint8), (h, w))
        seeds = np.column_stack([rng.integers(0, w, 3), rng.integers(0, h, 3)])
        passable = (rng.random((h, w)) < 0.3) if trial % 2 else np.zeros((0, 0), np.bool_)
        got = distance_grid(costs, seeds, passable)
        assert np.array_equal(got, _bfs_reference(costs, seeds, passable)), trial


def test_plan_densified_cut_and_seeded_as_ros_does():
    dense = densify_plan(np.array([[0.0, 0.0, 0.3], [0.5, 0.0, 0.0]]), 0.05)
    assert len(dense) == 11 and np.allclose(np.diff(dense[:, 0]), 0.05)
    assert (dense[:-1, 2] == 0.3).all()                       # heading copied, not interpolated
    plan = np.column_stack([np.linspace(-5, 5, 101), np.zeros(101), np.zeros(101)])
    loc = local_plan(plan, 0.0, 0.0, 6.0)
    assert loc[0, 0] == pytest.approx(-3.0) and loc[-1, 0] == pytest.approx(3.0)
    costs = np.zeros((120, 120), dtype=np.uint8)
    cells = plan_cells(costs, -3.0, -3.0, 0.05, densify_plan(loc, 0.05))
    assert cells[0].tolist() == [0, 60] and cells[-1][0] == 119   # stops at the map border


def test_local_plan_is_the_first_run_of_poses_inside_on_random_plans():
    rng = np.random.default_rng(4)
    for _ in range(500):
        poses = rng.uniform(-5, 5, (int(rng.integers(0, 30)), 3))
        x, y, size = rng.uniform(-3, 3), rng.uniform(-3, 3), rng.uniform(0.5, 8)
        inside = [(px - x) ** 2 + (py - y) ** 2 <= (size / 2) ** 2 for px, py, _ in poses]
        first = inside.index(True) if True in inside else len(poses)
        end = first
        while end < len(poses) and inside[end]:
            end += 1
        assert np.array_equal(local_plan(poses, x, y, size), poses[first:end])


def test_oscillation_flags_latch_and_release():
    f = OscillationFlags()
    f.update(0, 0, 0, 0.2, 0, 0, 0.1, 0.05, 0.2)
    assert not f.any()
    f.update(0, 0, 0, -0.2, 0, 0, 0.1, 0.05, 0.2)             # forward then backward
    assert f.active() == ["forward_neg_only"]
    f.update(0.03, 0, 0, -0.2, 0, 0, 0.1, 0.05, 0.2)          # moved 3 cm: still latched
    assert f.any()
    f.update(0.06, 0, 0, -0.2, 0, 0, 0.1, 0.05, 0.2)          # 6 cm > oscillation_reset_dist
    assert not f.any()
    f.update(0, 0, 0, 0.0, 0, 0.5, 0.1, 0.05, 0.2)            # rotations count when not driving
    f.update(0, 0, 0, 0.0, 0, -0.5, 0.1, 0.05, 0.2)
    assert f.active() == ["rot_neg_only"]
    f.update(0, 0, 0.25, 0.0, 0, -0.5, 0.1, 0.05, 0.2)        # turned 0.25 > 0.2 rad
    assert not f.any()


@settings(max_examples=20, deadline=None)
@given(st.integers(0, 2**31 - 1), st.sampled_from([0.0, 0.02]), st.sampled_from([0.0, 0.03]))
def test_fused_grid_critics_equal_the_critic_chain(seed, align, goal):
    rng = np.random.default_rng(seed)
    costs = np.where(rng.random((40, 40)) < 0.05, 254, 0).astype(np.uint8)
    none = np.zeros((0, 0), dtype=np.bool_)
    path_g = distance_grid(costs, rng.integers(0, 40, (5, 2)), none)
    goal_g = distance_grid(costs, rng.integers(0, 40, (1, 2)), none)
    front_g = distance_grid(costs, rng.integers(0, 40, (1, 2)), none)
    samples = np.column_stack([rng.uniform(-0.2, 0.6, 30), np.zeros(30), rng.uniform(-1, 1, 30)])
    steps = rng.integers(1, 60, 30)
    pts, _, nose = simulate(samples, steps, 1.0, 1.0, rng.uniform(-3, 3), np.zeros(3),
                            np.ones(3), 1.7, CONSTANT, 0.325)
    w = DwaWeights(occdist=0.01, goal_front=0.04, alignment=align, path=0.03, goal=goal,
                   twirling=0.0, forward_point_distance=0.325, scaling_speed=0.25,
                   max_vel_trans=0.55, max_scaling_factor=0.2, sum_scores=0.0).array()
    for k in range(30):
        n = int(steps[k])
        chain = []
        for scale, grid, shift, stop in ((w[W_GOAL_FRONT], front_g, 0.325, False),
                                         (w[W_ALIGNMENT], path_g, 0.325, False),
                                         (w[W_PATH], path_g, 0.0, True),
                                         (w[W_GOAL], goal_g, 0.0, True)):
            if scale != 0.0:
                chain.append((scale, grid_critic(pts, k, n, grid, 0.0, 0.0, 0.05, shift, stop)))
        neg = [c for _, c in chain if c < 0]
        expected = neg[0] if neg else sum(s * c for s, c in chain)
        got, _ = grid_critics(pts, nose, k, n, 0.0, 0.0, 0.05, path_g, goal_g, front_g, w, costs,
                              0)
        assert got == pytest.approx(expected)


# --- closed-loop behaviour ----------------------------------------------------------------------

def test_empty_corridor_drives_forward_at_the_speed_limit():
    cm = empty_map()
    dwa = DWAPlanner(cm, RECT, DIFF)
    path = straight_path(0.0, 0.0, 20.0, 0.0)
    pose, vel, results = drive(dwa, Pose2D(), Twist(), path, 40, cm, rolling=True)
    assert all(r.status == "following" for _, r in results)
    assert vel.vx == pytest.approx(dwa.params.max_vel_x)
    assert abs(vel.wz) < 1e-9 and abs(pose.y) < 1e-6
    # accelerates within the dynamic window: +acc_lim_x / controller_frequency per cycle at most
    speeds = [r.cmd.vx for _, r in results]
    assert max(np.diff([0.0] + speeds)) <= 2.5 / 20.0 + 1e-9


def test_holonomic_sampling_uses_vy_and_differential_does_not():
    cm = empty_map()
    path = straight_path(0.0, 0.4, 5.0, 0.4)   # the path runs beside the robot
    holo = DWAPlanner(cm, RECT, {"max_vel_y": 0.3, "min_vel_y": -0.3, "vy_samples": 7,
                                 "path_distance_bias": 32.0})
    r = holo.compute_velocity(Pose2D(), Twist(0.1, 0.0, 0.0), path)
    assert r.status == "following"
    assert np.unique(r.samples[:, 1]).size > 1
    assert r.cmd.vy > 0.0                       # strafes toward the path
    diff = DWAPlanner(cm, RECT, DIFF)
    r2 = diff.compute_velocity(Pose2D(), Twist(0.1, 0.0, 0.0), path)
    assert (r2.samples[:, 1] == 0.0).all()


def _lethal_box(cm: Costmap2D, x0: float, y0: float, x1: float, y1: float) -> np.ndarray:
    lethal = np.zeros(cm.costs.shape, dtype=bool)
    mx0, my0 = cm.world_to_map_no_bounds(x0, y0)
    mx1, my1 = cm.world_to_map_no_bounds(x1, y1)
    lethal[max(0, my0):max(0, my1 + 1), max(0, mx0):max(0, mx1 + 1)] = True
    return lethal


# The weak path / goal weights (TrajectoryPlanner's) these two scenes were tuned for: with the
# DWA defaults (32 / 24) the robot hugs the box and its unpadded corner can clip a lethal cell
# between two trajectory points (the footprint is checked at the points only, as in ROS).
WEAK = {"path_distance_bias": 0.6, "goal_distance_bias": 0.8}


def _never_touched(cm: Costmap2D, results: list) -> bool:
    return all(footprint_cost(cm.costs, cm.origin_x, cm.origin_y, cm.resolution, RECT,
                              p.x, p.y, p.theta) < 254 for p, _ in results)


def test_obstacle_on_the_plan_stops_it_short_without_touching():
    cm = Costmap2D(160, 100, 0.05, -1.0, -2.5)
    inflate(cm, _lethal_box(cm, 1.5, -0.3, 1.8, 0.2))
    dwa = DWAPlanner(cm, RECT, dict(DIFF, sim_time=3.0, vth_samples=30, vx_samples=6, **WEAK))
    path = straight_path(0.0, 0.0, 6.0, 0.0)   # the global plan runs straight through it
    pose, _, results = drive(dwa, Pose2D(), Twist(), path, 160)
    assert _never_touched(cm, results)
    assert max(p.x for p, _ in results) < 1.5 - 0.25


def test_obstacle_beside_a_detouring_plan_is_passed_without_touching():
    cm = Costmap2D(160, 100, 0.05, -1.0, -2.5)
    inflate(cm, _lethal_box(cm, 1.5, -0.3, 1.8, 0.2))
    t = np.linspace(0.0, 1.0, 121)
    xs = 6.0 * t
    ys = 0.75 * np.exp(-((xs - 1.65) / 0.6) ** 2)          # a planner's bend around the box
    path = Path(np.column_stack([xs, ys, np.zeros_like(xs)]))
    dwa = DWAPlanner(cm, RECT, dict(DIFF, sim_time=3.0, vth_samples=30, vx_samples=6, **WEAK))
    pose, _, results = drive(dwa, Pose2D(), Twist(), path, 300)
    assert _never_touched(cm, results)
    assert max(p.y for p, _ in results) > 0.4              # it swerved
    assert pose.x > 3.0                                     # and got past


def test_wall_across_the_path_stops_the_robot_with_a_reason():
    cm = empty_map()
    inflate(cm, _lethal_box(cm, 0.45, -3.0, 0.55, 3.0))
    dwa = DWAPlanner(cm, RECT, DIFF)
    path = straight_path(0.0, 0.0, 2.5, 0.0)
    pose, vel, results = drive(dwa, Pose2D(), Twist(0.3, 0.0, 0.0), path, 30)
    assert results[-1][1].status == "no_valid_trajectory"
    assert results[-1][1].cmd.is_zero()
    assert "lethal" in results[-1][1].reason or "cut off" in results[-1][1].reason
    assert pose.x < 0.45 - 0.25


@settings(max_examples=25, deadline=None)
@given(st.lists(st.tuples(st.floats(0.3, 2.0), st.floats(-1.0, 1.0), st.floats(0.05, 0.4)),
                min_size=1, max_size=4),
       st.floats(0.0, 0.55), st.floats(-0.8, 0.8))
def test_never_picks_a_trajectory_that_touches_a_lethal_cell(obstacles, v0, w0):
    cm = empty_map(80, 0.05, -2.0, -2.0)
    lethal = np.zeros(cm.costs.shape, dtype=bool)
    for x, y, half in obstacles:
        lethal |= _lethal_box(cm, x - half, y - half, x + half, y + half)
    inflate(cm, lethal)
    dwa = DWAPlanner(cm, RECT, dict(DIFF, vth_samples=10))
    r = dwa.compute_velocity(Pose2D(), Twist(v0, 0.0, w0), straight_path(0.0, 0.0, 3.0, 0.0))
    if r.status != "following":
        assert r.cmd.is_zero()
        return
    s = footprint_scale(r.cmd.vx, r.cmd.vy, 0.25, 0.55, 0.2)
    for x, y, th in r.best:
        assert footprint_cost(cm.costs, cm.origin_x, cm.origin_y, cm.resolution, RECT * s,
                              x, y, th) < 254


@settings(max_examples=15, deadline=None)
@given(st.integers(0, 2**31 - 1))
def test_branch_and_bound_picks_what_exhaustive_scoring_picks(seed):
    rng = np.random.default_rng(seed)
    cm = empty_map(80, 0.05, -2.0, -2.0)
    lethal = rng.random(cm.costs.shape) < 0.004
    lethal[35:45, 35:45] = False              # the robot itself stands on free cells
    inflate(cm, lethal)
    dwa = DWAPlanner(cm, RECT, dict(DIFF, vx_samples=6, vth_samples=15))
    path = Path(np.column_stack([np.linspace(0, 2, 41), 0.6 * np.sin(np.linspace(0, 3, 41)),
                                 np.zeros(41)]))
    dwa.set_plan(path)
    pose, vel = Pose2D(0.0, 0.0, float(rng.uniform(-1, 1))), Twist(0.3, 0.0, 0.2)
    local = dwa._local_plan(pose, False)
    ctx = dwa._prepare(pose, local)
    samples = dwa.sample_window(vel)
    *_, s_fast, st_fast, b_fast = dwa._score(pose, vel, samples, ctx, False)
    *_, s_full, st_full, b_full = dwa._score(pose, vel, samples, ctx, True)
    assert b_fast == b_full
    if b_full >= 0:
        assert s_fast[b_fast] == pytest.approx(s_full[b_full])
        # a pruned score is a lower bound of the full one (unless the full one rejects it)
        pruned = (st_fast == 1) & (s_full >= 0)
        assert (s_fast[pruned] <= s_full[pruned] + 1e-9).all()
        assert (s_fast[pruned] >= s_full[b_full]).all()   # ties go to the earlier sample
    assert ((st_full == REJECTED) == (s_full < 0)).all()


@pytest.mark.parametrize("seed", range(12))
def test_footprint_bound_skips_rasterising_without_changing_any_score(seed):
    """score_dwa with the square_max bound gives the same scores, states and choice as
    rasterising every footprint, pruned and exhaustive, max and sum, small and grown footprints."""
    rng = np.random.default_rng(100 + seed)
    cm = empty_map(80, 0.05, -2.0, -2.0)
    lethal = rng.random(cm.costs.shape) < rng.uniform(0.0005, 0.004)
    lethal[36:44, 36:44] = False
    inflate(cm, lethal)
    params = dict(sum_scores=bool(seed % 2), occdist_scale=[0.01, 0.5, 2.0][seed % 3],
                  max_scaling_factor=[0.2, 0.0, 1.0][seed % 3])
    fp = RECT if seed % 4 < 2 else [[0.3, 0.0], [0.1, 0.2], [-0.3, 0.2], [-0.1, 0.0],
                                     [-0.3, -0.2], [0.1, -0.2]]
    dwa = DWAPlanner(cm, fp, params)
    path = Path(np.column_stack([np.linspace(0, 2, 41),
                                 rng.uniform(0.2, 0.8) * np.sin(np.linspace(0, 3, 41)),
                                 np.zeros(41)]))
    dwa.set_plan(path)
    pose = Pose2D(0.0, 0.0, float(rng.uniform(-1, 1)))
    vel = Twist(float(rng.uniform(0.0, 0.5)), 0.0, float(rng.uniform(-0.5, 0.5)))
    ctx = dwa._prepare(pose, dwa._local_plan(pose, False))
    assert ctx.reach > 0 and ctx.bound.shape == cm.costs.shape
    samples = dwa.sample_window(vel, pose, ctx.local_goal)
    for exhaustive in (False, True):
        with_bound = dwa._score(pose, vel, samples, ctx, exhaustive)
        plain = dwa._score(pose, vel, samples, ctx._replace(bound=np.zeros((0, 0), np.uint8)),
                           exhaustive)
        assert with_bound[-1] == plain[-1]
        assert np.array_equal(with_bound[-3], plain[-3])   # scores, bit for bit
        assert np.array_equal(with_bound[-2], plain[-2])   # states


def _mean_path_deviation(params: dict) -> float:
    """Closed loop along an S-shaped plan; mean distance of the robot from the plan."""
    cm = Costmap2D(160, 160, 0.05, -1.0, -4.0)
    t = np.linspace(0.0, 1.0, 121)
    xs, ys = 6.0 * t, 1.2 * np.sin(2 * np.pi * t)
    path = Path(np.column_stack([xs, ys, np.arctan2(np.gradient(ys), np.gradient(xs))]))
    dwa = DWAPlanner(cm, RECT, dict(DIFF, vth_samples=30, **params))
    _, _, results = drive(dwa, Pose2D(0.0, 0.0, path.poses[0, 2]), Twist(), path, 120, cm,
                          rolling=True)
    dense = densify_plan(path.poses, 0.01)
    dev = [np.min(np.hypot(dense[:, 0] - p.x, dense[:, 1] - p.y)) for p, _ in results]
    return float(np.mean(dev))


def test_path_and_goal_bias_defaults_are_dwaplanner_cfg_ones():
    # DWAPlannerROS applies its first reconfigure call, so DWAPlanner.cfg's 32 / 24 are the
    # effective defaults (0.6 / 0.8 are TrajectoryPlanner's)
    p = DWAPlanner(empty_map(), RECT, DIFF).params
    assert (p.path_distance_bias, p.goal_distance_bias, p.occdist_scale) == (32.0, 24.0, 0.01)


def test_beside_an_obstacle_it_drives_on_instead_of_spinning_in_place():
    """Regression: unknown_box under move_base turned on the spot near (2.3, 2.4) until the time
    limit. With 0.6 / 0.8 a cell of progress (0.04) could never pay for the footprint entering the
    box's inscribed band (occdist 0.01 x 253), so rotating in place, always valid, won forever."""
    res = 0.05
    padded = RECT + np.sign(RECT) * 0.03          # as the costmap hands it (footprint_padding)
    world = Costmap2D(160, 80, res, 0.0, 0.0)     # 8 m x 4 m
    lethal = np.zeros((80, 160), dtype=bool)
    lethal[26:42, 60:72] = True                   # the box: x 3.0..3.6, y 1.3..2.1
    inflate(world, lethal, inscribed=0.25)
    corners = np.array([[1.8, 2.1, 0.0], [2.5, 2.45, 0.0], [3.0, 2.6, 0.0], [3.6, 2.6, 0.0],
                        [4.2, 2.4, 0.0], [6.2, 1.7, 0.0]])
    plan = Path(densify_plan(corners, res))       # a navfn-like plan hugging the box's top
    window = Costmap2D(80, 80, res, 0.0, 0.0)     # the 4 m rolling window
    dwa = DWAPlanner(window, padded, dict(DIFF, vy_samples=1, max_vel_trans=0.5, max_vel_x=0.5,
                                          max_vel_theta=1.5, sim_granularity=0.05, vx_samples=5,
                                          vth_samples=15, controller_frequency=10.0))
    pose, vel = Pose2D(2.3, 2.45, -0.5), Twist(0.0, 0.0, -0.4)   # where the robot was spinning
    poses = []
    for _ in range(150):                          # 15 s at 10 Hz, perfect tracking
        mx0, my0 = int(round(pose.x / res)) - 40, int(round(pose.y / res)) - 40
        window.origin_x, window.origin_y = mx0 * res, my0 * res
        window.costs[:] = 0
        x0, x1, y0, y1 = max(mx0, 0), min(mx0 + 80, 160), max(my0, 0), min(my0 + 80, 80)
        window.costs[y0 - my0:y1 - my0, x0 - mx0:x1 - mx0] = world.costs[y0:y1, x0:x1]
        r = dwa.compute_velocity(pose, vel, plan)
        vel = r.cmd
        pose = pose.compose(Pose2D(vel.vx * 0.1, 0.0, vel.wz * 0.1))
        poses.append(pose)
    assert max(p.x for p in poses) > 4.5            # past the box, not turning on the spot
    assert all(footprint_cost(world.costs, 0.0, 0.0, res, RECT, p.x, p.y, p.theta) < 254
               for p in poses)


def test_path_distance_bias_holds_the_path_and_goal_distance_bias_loosens_it():
    base = _mean_path_deviation({"path_distance_bias": 0.6, "goal_distance_bias": 0.8})
    tight = _mean_path_deviation({"path_distance_bias": 32.0, "goal_distance_bias": 0.8})
    loose = _mean_path_deviation({"path_distance_bias": 0.6, "goal_distance_bias": 20.0})
    assert tight < base < loose
    assert tight < 0.05


# --- goal handling ------------------------------------------------------------------------------

def test_goal_reached_needs_position_yaw_and_standstill():
    cm = empty_map()
    dwa = DWAPlanner(cm, RECT, DIFF)
    path = straight_path(-1.0, 0.0, 0.0, 0.0)            # goal (0, 0, 0)
    r = dwa.compute_velocity(Pose2D(0.05, 0.0, 0.05), Twist(), path)
    assert r.status == "goal_reached" and r.cmd.is_zero() and dwa.is_goal_reached()
    r = dwa.compute_velocity(Pose2D(0.05, 0.0, 0.05), Twist(0.3, 0.0, 0.0), path)
    assert r.status == "rotating_to_goal" and r.cmd.is_zero() and not dwa.is_goal_reached()
    r = dwa.compute_velocity(Pose2D(0.3, 0.0, 0.0), Twist(), path)     # 0.3 m off: not there
    assert r.status == "following" and not dwa.is_goal_reached()


def test_at_the_goal_position_it_brakes_then_rotates_to_the_goal_yaw():
    cm = empty_map()
    dwa = DWAPlanner(cm, RECT, DIFF)
    path = Path(np.array([[-1.0, 0.0, 1.5], [0.0, 0.0, 1.5]]))      # goal yaw 1.5 rad
    r = dwa.compute_velocity(Pose2D(0.02, 0.0, 0.0), Twist(0.3, 0.0, 0.0), path)
    assert r.status == "rotating_to_goal"
    assert r.cmd.vx == pytest.approx(0.3 - 2.5 / 20) and r.cmd.wz == 0.0   # braking
    pose, vel, results = drive(dwa, Pose2D(0.02, 0.0, 0.0), Twist(0.1, 0.0, 0.0), path, 200)
    assert results[-1][1].status == "goal_reached"
    assert abs(pose.theta - 1.5) <= 0.1
    rot = [r.cmd for _, r in results if r.cmd.wz != 0.0]
    assert rot and all(c.vx == 0.0 and c.wz > 0.0 for c in rot)          # in place, left turn
    assert all(abs(c.wz) >= 0.4 - 1e-9 for c in rot)                    # min_vel_theta floor


@pytest.mark.parametrize("latch", [True, False])
def test_latch_xy_goal_tolerance(latch):
    cm = empty_map()
    dwa = DWAPlanner(cm, RECT, dict(DIFF, latch_xy_goal_tolerance=latch))
    path = Path(np.array([[-1.0, 0.0, 1.5], [0.0, 0.0, 1.5]]))
    assert dwa.compute_velocity(Pose2D(0.05, 0.0, 0.0), Twist(), path).status == \
        "rotating_to_goal"
    r = dwa.compute_velocity(Pose2D(0.15, 0.0, 0.3), Twist(), path)   # pushed out of tolerance
    assert r.status == ("rotating_to_goal" if latch else "following")
    dwa.reset()                                                      # a recovery forgets it
    assert dwa.compute_velocity(Pose2D(0.15, 0.0, 0.3), Twist(), path).status == "following"


def test_oscillation_flags_block_the_opposite_direction_until_moved_on():
    cm = empty_map()
    dwa = DWAPlanner(cm, RECT, dict(DIFF, min_vel_x=-0.3, vx_samples=5))
    path = straight_path(0.0, 0.0, 3.0, 0.0)
    dwa.set_plan(path)
    dwa.oscillation.update(0.0, 0.0, 0.0, 0.2, 0, 0, 0.1, 0.05, 0.2)
    dwa.oscillation.update(0.0, 0.0, 0.0, -0.2, 0, 0, 0.1, 0.05, 0.2)   # it just reversed
    r = dwa.compute_velocity(Pose2D(), Twist(0.0, 0.0, 0.0), path)
    fwd = r.samples[:, 0] > 0
    assert fwd.any() and (r.scores[fwd] == -5).all()                   # forward is forbidden
    assert r.cmd.vx <= 0.0
    r = dwa.compute_velocity(Pose2D(-0.08, 0.0, 0.0), Twist(0.0, 0.0, 0.0), path)
    # the flag was released after moving 8 cm, so this cycle may go forward again
    assert not dwa.oscillation.any() or r.cmd.vx > 0.0
    r = dwa.compute_velocity(Pose2D(-0.08, 0.0, 0.0), Twist(0.0, 0.0, 0.0), path)
    assert r.cmd.vx > 0.0
    assert not (r.scores == -5).any()


# --- interface ----------------------------------------------------------------------------------

def test_statuses_for_missing_or_unusable_plans_and_bad_input():
    cm = empty_map()
    dwa = make_controller("dwa_local_planner/DWAPlannerROS", cm, RECT, DIFF)
    r = dwa.compute_velocity(Pose2D(), Twist())
    assert r.status == "no_plan" and r.cmd.is_zero()
    far = straight_path(50.0, 50.0, 60.0, 50.0)
    r = dwa.compute_velocity(Pose2D(), Twist(), far)
    assert r.status == "no_valid_trajectory" and "local costmap" in r.reason
    r = dwa.compute_velocity(Pose2D(float("nan"), 0.0, 0.0), Twist(), far)
    assert r.status == "no_valid_trajectory" and "not finite" in r.reason
    bad = Path(np.array([[0.0, 0.0, 0.0], [np.nan, 1.0, 0.0]]))
    r = dwa.compute_velocity(Pose2D(), Twist(), bad)                 # bad input: a reason
    assert r.status == "no_valid_trajectory" and "non-finite" in r.reason
    with pytest.raises(ValueError, match="unknown local planner"):
        make_controller("nope/Planner", cm, RECT, {})


def test_parameters_are_ros_named_checked_and_live():
    cm = empty_map()
    with pytest.raises(ParameterError, match="did you mean 'max_vel_x'"):
        DWAPlanner(cm, RECT, {"max_vel_xx": 1.0})
    dwa = DWAPlanner(cm, RECT, {"restore_defaults": False})          # ROS keys with no meaning
    assert dwa.params.sim_time == 1.7 and dwa.params.vx_samples == 3   # the .cfg defaults
    path = straight_path(0.0, 0.0, 3.0, 0.0)
    n1 = len(dwa.compute_velocity(Pose2D(), Twist(0.3, 0, 0), path).samples)
    dwa.params.set({"vth_samples": 40, "max_vel_y": 0.0, "min_vel_y": 0.0})
    n2 = len(dwa.compute_velocity(Pose2D(), Twist(0.3, 0, 0), path).samples)
    assert n1 == 3 * 11 * 21 and n2 == 3 * 41                        # zeros inserted as in ROS


def test_rolling_costmap_origin_is_read_every_cycle():
    cm = empty_map()
    dwa = DWAPlanner(cm, RECT, DIFF)
    path = straight_path(10.0, 10.0, 14.0, 10.0)
    assert dwa.compute_velocity(Pose2D(10.0, 10.0, 0.0), Twist(), path).status != "following"
    cm.origin_x, cm.origin_y = 7.0, 7.0                               # the window followed
    r = dwa.compute_velocity(Pose2D(10.0, 10.0, 0.0), Twist(), path)
    assert r.status == "following" and r.cmd.vx > 0.0
