"""TrajectoryPlannerROS: ramped rollout sampling, rotations, escapes, goal handling."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from navcore.controllers import TrajectoryPlanner, make_controller
from navcore.controllers.trajectory_rollout import (RW_GOAL, RW_OCCDIST, RW_PATH, RolloutWeights,
                                                    footprint_cells, grid_bound, lower_bounds,
                                                    parse_y_vels, rollout_cost)
from navcore.costmap.costmap2d import Costmap2D
from navcore.costmap.footprint import footprint_cost
from navcore.params import ParameterError
from navcore.params import ParameterError
from navcore.types import Path, Pose2D, Twist
from tests.test_controllers_support import RECT, drive, inflate, straight_path

DIFF = {"holonomic_robot": False}


def empty_map(size: int = 120, ox: float = -3.0, oy: float = -3.0) -> Costmap2D:
    return Costmap2D(size, size, 0.05, ox, oy)


def box(cm: Costmap2D, x0: float, y0: float, x1: float, y1: float) -> np.ndarray:
    lethal = np.zeros(cm.costs.shape, dtype=bool)
    mx0, my0 = cm.world_to_map_no_bounds(x0, y0)
    mx1, my1 = cm.world_to_map_no_bounds(x1, y1)
    lethal[max(0, my0):max(0, my1 + 1), max(0, mx0):max(0, mx1 + 1)] = True
    return lethal


def test_defaults_are_the_effective_cfg_values():
    tr = TrajectoryPlanner(empty_map(), RECT)
    p = tr.params
    assert (p.sim_time, p.vx_samples, p.dwa, p.holonomic_robot) == (1.7, 20, False, True)
    assert (p.goal_distance_bias, p.angular_sim_granularity, p.escape_reset_theta) == \
        (0.8, 0.025, pytest.approx(math.pi / 2))
    assert (p.prune_plan, p.yaw_goal_tolerance, p.meter_scoring) == (True, 0.05, False)
    assert parse_y_vels(p.y_vels) == [-0.3, -0.1, 0.1, -0.3]
    with pytest.raises(ParameterError, match="heading_scoring"):
        TrajectoryPlanner(empty_map(), RECT, {"heading_scoring": True})   # not supported here


def test_empty_corridor_drives_forward_at_the_speed_limit():
    cm = empty_map()
    tr = make_controller("base_local_planner/TrajectoryPlannerROS", cm, RECT, DIFF)
    path = straight_path(0.0, 0.0, 20.0, 0.0)
    pose, vel, results = drive(tr, Pose2D(), Twist(), path, 30, cm, rolling=True)
    assert all(r.status == "following" for _, r in results)
    assert vel.vx == pytest.approx(0.55) and abs(vel.wz) < 1e-9 and abs(pose.y) < 1e-6
    # rollout samples are ramped: the trajectory reaches the sample speed at acc_lim_x
    r = results[0][1]
    v = np.hypot(*np.diff(r.best[:3, :2], axis=0).T) / (1.7 / len(r.best))
    assert v[0] <= 2.5 * 1.7 / len(r.best) * 2 + 1e-9


def test_holonomic_robot_samples_strafes():
    cm = empty_map()
    path = straight_path(0.0, 0.0, 3.0, 0.0)
    holo = TrajectoryPlanner(cm, RECT).compute_velocity(Pose2D(), Twist(0.2, 0, 0), path)
    assert {(0.1, 0.1), (0.1, -0.1)} <= {(s[0], s[1]) for s in holo.samples}
    assert set(parse_y_vels("-0.3,-0.1,0.1,-0.3")) <= set(holo.samples[:, 1])
    diff = TrajectoryPlanner(cm, RECT, DIFF).compute_velocity(Pose2D(), Twist(0.2, 0, 0), path)
    assert (diff.samples[:, 1] == 0.0).all()


def test_facing_away_it_turns_in_place_toward_the_goal():
    cm = empty_map()
    tr = TrajectoryPlanner(cm, RECT, DIFF)
    path = straight_path(0.0, 0.0, 2.5, 0.0)
    r = tr.compute_velocity(Pose2D(0.0, 0.0, 2.0), Twist(), path)   # the path lies behind-right
    assert r.status == "following"
    assert r.cmd.vx == 0.0 and r.cmd.wz <= -0.4                      # turns right, in place
    pose, _, _ = drive(tr, Pose2D(0.0, 0.0, 2.0), Twist(), path, 60)
    assert abs(pose.theta) < 0.5 and pose.x > 0.2                     # then drives off


def test_boxed_in_it_backs_off_at_escape_vel():
    cm = empty_map()
    inflate(cm, box(cm, 0.3, -0.6, 0.4, 0.6) | box(cm, -0.25, 0.28, 0.4, 0.35)
            | box(cm, -0.25, -0.35, 0.4, -0.28))
    tr = TrajectoryPlanner(cm, RECT, DIFF)
    path = straight_path(0.0, 0.0, 2.5, 0.0)
    r = tr.compute_velocity(Pose2D(), Twist(), path)
    assert r.status == "following" and r.cmd == Twist(-0.1, 0.0, 0.0)
    assert tr._escaping and "escaping" in r.reason
    r2 = tr.compute_velocity(Pose2D(-0.02, 0.0, 0.0), Twist(-0.1, 0.0, 0.0), path)
    assert not (r2.samples[:, 0] > 0).any()              # no forward samples while escaping
    tr.compute_velocity(Pose2D(-0.15, 0.0, 0.0), Twist(-0.1, 0.0, 0.0), path)
    assert not tr._escaping                              # escape_reset_dist 0.10 m passed


@settings(max_examples=20, deadline=None)
@given(st.lists(st.tuples(st.floats(0.4, 2.0), st.floats(-1.0, 1.0), st.floats(0.05, 0.4)),
                min_size=1, max_size=4),
       st.floats(0.0, 0.55), st.floats(-0.8, 0.8))
def test_never_picks_a_forward_trajectory_that_touches_a_lethal_cell(obstacles, v0, w0):
    cm = empty_map(80, -2.0, -2.0)
    lethal = np.zeros(cm.costs.shape, dtype=bool)
    for x, y, half in obstacles:
        lethal |= box(cm, x - half, y - half, x + half, y + half)
    inflate(cm, lethal)
    tr = TrajectoryPlanner(cm, RECT, dict(DIFF, vx_samples=8, vtheta_samples=10))
    r = tr.compute_velocity(Pose2D(), Twist(v0, 0.0, w0), straight_path(0.0, 0.0, 3.0, 0.0))
    if r.status != "following" or tr._escaping:
        return          # the escape may back into what the map calls blocked, as in ROS
    for x, y, th in r.best:
        assert footprint_cost(cm.costs, cm.origin_x, cm.origin_y, cm.resolution, RECT,
                              x, y, th) < 254


@settings(max_examples=10, deadline=None)
@given(st.integers(0, 2**31 - 1))
def test_branch_and_bound_picks_what_exhaustive_scoring_picks(seed):
    rng = np.random.default_rng(seed)
    cm = empty_map(80, -2.0, -2.0)
    lethal = rng.random(cm.costs.shape) < 0.004
    lethal[32:48, 32:48] = False
    inflate(cm, lethal)
    path = Path(np.column_stack([np.linspace(0, 2, 41), 0.6 * np.sin(np.linspace(0, 3, 41)),
                                 np.zeros(41)]))
    pose, vel = Pose2D(0.0, 0.0, float(rng.uniform(-1, 1))), Twist(0.3, 0.0, 0.2)
    fast = TrajectoryPlanner(cm, RECT, dict(DIFF, vx_samples=8, vtheta_samples=12))
    full = TrajectoryPlanner(cm, RECT, dict(DIFF, vx_samples=8, vtheta_samples=12))
    full.exhaustive = True
    a = fast.compute_velocity(pose, vel, path)
    b = full.compute_velocity(pose, vel, path)
    assert (a.status, a.cmd) == (b.status, b.cmd)


def test_goal_reached_and_rotate_to_goal_yaw():
    cm = empty_map()
    tr = TrajectoryPlanner(cm, RECT, DIFF)
    path = Path(np.array([[-1.0, 0.0, -1.2], [0.0, 0.0, -1.2]]))
    r = tr.compute_velocity(Pose2D(0.03, 0.0, 0.0), Twist(0.3, 0.0, 0.0), path)
    assert r.status == "rotating_to_goal" and r.cmd.vx == pytest.approx(0.3 - 2.5 / 20)
    pose, _, results = drive(tr, Pose2D(0.03, 0.0, 0.0), Twist(), path, 200)
    assert results[-1][1].status == "goal_reached" and tr.is_goal_reached()
    assert abs(pose.theta + 1.2) <= 0.05
    turns = [r.cmd.wz for _, r in results if r.status == "rotating_to_goal"]
    assert turns and all(-1.0 <= w <= -0.4 for w in turns)   # min_in_place_vel_theta floor
    tr.set_plan(straight_path(0.0, 0.0, 2.0, 0.0))
    assert not tr.is_goal_reached()                           # a new plan clears it


@pytest.mark.parametrize("latch", [True, False])
def test_latch_xy_goal_tolerance(latch):
    cm = empty_map()
    tr = TrajectoryPlanner(cm, RECT, dict(DIFF, latch_xy_goal_tolerance=latch))
    path = Path(np.array([[-1.0, 0.0, 1.5], [0.0, 0.0, 1.5]]))
    assert tr.compute_velocity(Pose2D(0.05, 0, 0), Twist(), path).status == "rotating_to_goal"
    r = tr.compute_velocity(Pose2D(0.15, 0.0, 0.3), Twist(), path)
    assert r.status == ("rotating_to_goal" if latch else "following")


def test_meter_scoring_scales_the_biases_by_the_resolution():
    cm = empty_map()
    path = straight_path(0.0, 0.0, 2.0, 0.0)
    cells = TrajectoryPlanner(cm, RECT, DIFF)
    metres = TrajectoryPlanner(cm, RECT, dict(DIFF, meter_scoring=True))
    a = cells.compute_velocity(Pose2D(), Twist(0.3, 0, 0), path)
    b = metres.compute_velocity(Pose2D(), Twist(0.3, 0, 0), path)
    assert a.cmd == b.cmd
    k = int(np.argmin(np.where(a.scores >= 0, a.scores, np.inf)))
    assert b.scores[k] == pytest.approx(a.scores[k] * 0.05)


def test_the_weights_are_read_by_name():
    assert RolloutWeights(path=1.0, goal=2.0, occdist=3.0).array()[
        [RW_PATH, RW_GOAL, RW_OCCDIST]].tolist() == [1.0, 2.0, 3.0]
    # one straight trajectory over cells of cost 50, 3 cells from the path, 5 from the goal
    costs = np.full((40, 40), 50, dtype=np.uint8)
    path_grid = np.full((40, 40), 3, dtype=np.int32)
    goal_grid = np.full((40, 40), 5, dtype=np.int32)
    pts = np.array([[[1.0 + 0.05 * i, 2.0, 0.0] for i in range(10)]])
    steps = np.array([10])
    args = (costs, 0.0, 0.0, 0.1)
    for named, expected in ((RolloutWeights(path=1.0, goal=0.0, occdist=0.0), 3.0),
                            (RolloutWeights(path=0.0, goal=1.0, occdist=0.0), 5.0),
                            (RolloutWeights(path=0.0, goal=0.0, occdist=1.0), 50.0),
                            (RolloutWeights(path=0.5, goal=0.25, occdist=0.01), 3.25)):
        w = named.array()
        assert rollout_cost(pts, 0, 10, *args, RECT, path_grid, goal_grid, w, 0.0,
                            np.inf) == pytest.approx(expected)
        assert grid_bound(pts, 0, 10, *args, path_grid, goal_grid, w) == (
            pytest.approx(expected), 50)
        # the path-and-goal part alone: the bound less the obstacle term
        base = lower_bounds(pts, steps, *args, path_grid, goal_grid, w)[2][0]
        assert base == pytest.approx(3.0 * named.path + 5.0 * named.goal)


def test_the_planner_s_weights_are_its_parameters_by_name():
    params = dict(DIFF, path_distance_bias=0.6, goal_distance_bias=0.8, occdist_scale=0.01)
    w = TrajectoryPlanner(empty_map(), RECT, params)._weights()
    assert (w.path, w.goal, w.occdist) == (0.6, 0.8, 0.01)
    m = TrajectoryPlanner(empty_map(), RECT, dict(params, meter_scoring=True))._weights()
    assert (m.path, m.goal, m.occdist) == pytest.approx((0.6 * 0.05, 0.8 * 0.05, 0.01 * 0.05))


def test_start_footprint_cells_are_its_inside():
    cm = empty_map()
    mask = footprint_cells(cm, RECT, Pose2D(0.0, 0.0, 0.0))
    assert mask.sum() == 10 * 8 or mask.sum() == 10 * 9        # 0.5 m x 0.44 m of 5 cm cells
    rot = footprint_cells(cm, RECT, Pose2D(0.0, 0.0, math.pi / 2))
    ys, xs = np.nonzero(rot)
    assert np.ptp(ys) > np.ptp(xs)                              # turned: long along y


def test_bad_input_gives_a_reason_and_a_bad_parameter_is_refused_when_set():
    cm = empty_map()
    tr = TrajectoryPlanner(cm, RECT, DIFF)
    assert tr.compute_velocity(Pose2D(), Twist()).status == "no_plan"
    r = tr.compute_velocity(Pose2D(), Twist(float("inf"), 0, 0), straight_path(0, 0, 1, 0))
    assert r.status == "no_valid_trajectory" and r.cmd.is_zero()
    holo = TrajectoryPlanner(cm, RECT)
    # before, a bad y_vels was accepted and every cycle then said "no valid trajectory" (a
    # blocked robot to the tree); now the change is refused and the old value stays
    with pytest.raises(ParameterError, match="y_vels"):
        holo.params.set({"y_vels": "a,b"})
    assert holo.params.y_vels == "-0.3,-0.1,0.1,-0.3"
    r = holo.compute_velocity(Pose2D(), Twist(), straight_path(0, 0, 1, 0))
    assert r.status in ("following", "rotating_to_goal")


def _mean_path_deviation(params: dict) -> float:
    cm = Costmap2D(160, 160, 0.05, -1.0, -4.0)
    t = np.linspace(0.0, 1.0, 121)
    xs, ys = 6.0 * t, 1.2 * np.sin(2 * np.pi * t)
    path = Path(np.column_stack([xs, ys, np.arctan2(np.gradient(ys), np.gradient(xs))]))
    tr = TrajectoryPlanner(cm, RECT, dict(DIFF, **params))
    _, _, results = drive(tr, Pose2D(0.0, 0.0, path.poses[0, 2]), Twist(), path, 120, cm,
                          rolling=True)
    d = np.array([np.min(np.hypot(xs - p.x, ys - p.y)) for p, _ in results])
    return float(d.mean())


def test_goal_distance_bias_loosens_the_hold_on_the_path():
    assert _mean_path_deviation({"goal_distance_bias": 0.8}) < \
        _mean_path_deviation({"goal_distance_bias": 3.0})


def _cells_inside_reference(costmap, footprint, pose):
    """The even-odd test of every cell centre, with numpy over the footprint's bounding box."""
    footprint = np.asarray(footprint, dtype=np.float64)
    c, s = math.cos(pose.theta), math.sin(pose.theta)
    wx = pose.x + c * footprint[:, 0] - s * footprint[:, 1]
    wy = pose.y + s * footprint[:, 0] + c * footprint[:, 1]
    res, ox, oy = costmap.resolution, costmap.origin_x, costmap.origin_y
    mask = np.zeros(costmap.costs.shape, dtype=np.bool_)
    x0 = max(0, int(math.floor((wx.min() - ox) / res)))
    x1 = min(costmap.size_x - 1, int(math.floor((wx.max() - ox) / res)))
    y0 = max(0, int(math.floor((wy.min() - oy) / res)))
    y1 = min(costmap.size_y - 1, int(math.floor((wy.max() - oy) / res)))
    if x1 < x0 or y1 < y0:
        return mask
    gx, gy = np.meshgrid(ox + (np.arange(x0, x1 + 1) + 0.5) * res,
                         oy + (np.arange(y0, y1 + 1) + 0.5) * res)
    inside = np.zeros(gx.shape, dtype=bool)
    ax, ay = wx[-1], wy[-1]
    for bx, by in zip(wx, wy):
        crosses = (ay <= gy) != (by <= gy)
        with np.errstate(divide="ignore", invalid="ignore"):
            xc = ax + (gy - ay) * (bx - ax) / (by - ay)
        inside ^= crosses & (gx < xc)
        ax, ay = bx, by
    mask[y0:y1 + 1, x0:x1 + 1] = inside
    return mask


def test_start_footprint_cells_agree_with_the_numpy_even_odd_test_on_random_poses():
    rng = np.random.default_rng(8)
    cm = Costmap2D(40, 50, 0.05, -1.0, -1.2)
    ell = [[0.3, 0.3], [0.3, -0.1], [0.0, -0.1], [0.0, -0.3], [-0.3, -0.3], [-0.3, 0.3]]
    for trial in range(300):
        fp = (RECT, ell)[trial % 2]
        pose = Pose2D(rng.uniform(-1.5, 1.8), rng.uniform(-1.5, 1.3), rng.uniform(-4, 4))
        if trial % 5 == 0:  # centres exactly on the grid and axis-aligned edges
            pose = Pose2D(-1.0 + 0.05 * rng.integers(0, 40), -1.2 + 0.05 * rng.integers(0, 50),
                          0.0)
        assert np.array_equal(footprint_cells(cm, fp, pose),
                              _cells_inside_reference(cm, fp, pose)), trial
