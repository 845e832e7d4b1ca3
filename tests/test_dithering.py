"""Dithering (issue 17, class 4): DitherCheck, IsDithering tick by tick, the gate on a path and
FindGateOnPath, on scripted motions and walls of their own (none a catalogue scenario)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from py_trees.common import Status

from behaviors.testing import FakeRobot, NodeRig, straight_path
from navcore.clock import SimClock
from navcore.costmap.layered import LayeredCostmap
from navcore.motion.dither import DitherCheck
from navcore.motion.gate import gate_on_path
from navcore.synthetic_maps import ascii_map
from navcore.types import Path, Pose2D

S, F = Status.SUCCESS, Status.FAILURE
RES = 0.05
FOOTPRINT = [[0.25, 0.22], [0.25, -0.22], [-0.25, -0.22], [-0.25, 0.22]]


def swing(t: float, period: float = 4.0, amplitude: float = 0.6) -> tuple[float, float]:
    """Back and forth across y = 2 at x = 3 (between two gaps), never nearer the goal."""
    return 3.0, 2.0 + amplitude * math.sin(2.0 * math.pi * t / period)


def test_dither_check_fires_on_swinging_not_on_driving_or_waiting():
    c = DitherCheck()
    fired = None
    for k in range(200):                       # 20 s at 10 Hz, distance to go stuck near 5 m
        t = 0.1 * k
        x, y = swing(t)
        c.update(t, x, y, 5.0 + 0.2 * math.sin(t), 0.5)
        if c.dithering(t, 10.0, 1.0):
            fired = t
            break
    assert fired is not None and 10.0 <= fired < 10.5
    drive = DitherCheck()                      # 0.5 m/s toward the goal: always progressing
    assert not any(drive.update(0.1 * k, 0.05 * k, 0.0, 10.0 - 0.05 * k, 0.5)
                   or drive.dithering(0.1 * k, 10.0, 1.0) for k in range(200))
    wait = DitherCheck()                       # standing still (a person in the way)
    assert not any(wait.update(0.1 * k, 1.0, 1.0, 4.0, 0.5) or wait.dithering(0.1 * k, 10.0, 1.0)
                   for k in range(300))
    detour = DitherCheck()                     # a longer plan once, then progress along it
    for k in range(200):
        t = 0.1 * k
        to_go = 5.0 - 0.05 * k if t < 3.0 else 9.0 - 0.05 * k
        detour.update(t, 0.05 * k, 0.0, to_go, 0.5)
        assert not detour.dithering(t, 10.0, 1.0) or t >= 13.0


Env, tick = NodeRig, NodeRig.tick


def test_is_dithering_tick_by_tick_with_commit_and_goal_reset():
    clock, robot = SimClock(), FakeRobot(Pose2D(3.0, 2.0, 0.0))
    env = Env({"clock": clock, "robot": robot, "control_period": 0.1})
    node = env.node("IsDithering", window=10.0, min_travel=1.0, min_progress=0.5,
                    commit_time=2.0)
    goal = Pose2D(8.0, 2.0, 0.0)
    assert tick(node) == F                                  # no path yet
    env.put("goal", goal)
    env.put("path", straight_path(Pose2D(0.0, 2.0, 0.0), goal))
    statuses = []
    for k in range(160):
        x, y = swing(clock.now())
        robot.teleport(Pose2D(x, y, 0.0))
        statuses.append((round(clock.now(), 1), tick(node)))
        assert env.get("dithering") is (statuses[-1][1] == S)   # the verdict, each tick
        clock.advance(0.1)
    first = next(t for t, s in statuses if s == S)
    assert 10.0 <= first <= 10.6
    held = [t for t, s in statuses if s == S]
    # SUCCESS for the 2 s commit, then the check starts afresh: FAILURE for the next 10 s
    assert held == [t for t, _ in statuses if first <= t <= held[-1]]   # one stretch
    assert held[-1] - first == pytest.approx(2.0, abs=0.1 + 1e-9)
    assert env.get("dithering") is False
    env.put("goal", Pose2D(8.0, 2.5, 0.0))                  # a new goal: a new check
    assert tick(node) == F
    driving = env.node("IsDithering", window=3.0)            # progressing: never
    for k in range(100):
        robot.teleport(Pose2D(0.05 * k, 2.0, 0.0))
        assert tick(driving) == F
        clock.advance(0.1)


def wall_with_gap(gap: float, centre: float = 2.0) -> LayeredCostmap:
    """A 6 m x 4 m room, a wall at x 3.0..3.2 with a gap ``gap`` m wide centred at y ``centre``."""
    g = np.full((80, 120), ".")
    g[0, :] = g[-1, :] = g[:, 0] = g[:, -1] = "#"
    g[:, 60:64] = "#"
    lo, hi = int(round((centre - gap / 2) / RES)), int(round((centre + gap / 2) / RES))
    g[80 - hi:80 - lo, 60:64] = "."
    cm = LayeredCostmap.from_params(
        {"plugins": ["static_layer", "inflation_layer"], "footprint": FOOTPRINT,
         "footprint_padding": 0.0,
         "inflation_layer": {"inflation_radius": 0.55, "cost_scaling_factor": 10.0}},
        static_map=ascii_map("\n".join("".join(r) for r in g), RES), clock=SimClock())
    cm.update_map(Pose2D(1.0, 1.0, 0.0))
    return cm


def bent_path(points: list[tuple[float, float]], step: float = 0.05) -> Path:
    out = []
    for (x0, y0), (x1, y1) in zip(points, points[1:]):
        n = max(1, int(math.ceil(math.hypot(x1 - x0, y1 - y0) / step)))
        th = math.atan2(y1 - y0, x1 - x0)
        out += [(x0 + (x1 - x0) * i / n, y0 + (y1 - y0) * i / n, th) for i in range(n)]
    out.append((*points[-1], 0.0))
    return Path(np.array(out))


@pytest.mark.parametrize("centre", [1.3, 2.0, 2.65])
def test_gate_is_centred_in_the_gap_facing_along_the_path_and_inside_the_narrow_part(centre):
    cm = wall_with_gap(0.62, centre)
    fp = np.asarray(cm.footprint)
    # a plan that crosses the wall a cell off the gap's middle, coming in at an angle
    path = bent_path([(1.0, 0.8), (2.6, centre + 0.05), (3.6, centre + 0.05), (5.0, 3.0)])
    gate = gate_on_path(cm.costmap, path, Pose2D(1.0, 0.8, 0.0), fp, 4.0, 0.15)
    assert gate is not None
    assert gate.y == pytest.approx(centre, abs=RES / 2 + 1e-6)     # centred, not on the path
    assert abs(gate.theta) < 0.2                                     # along the crossing
    assert 3.0 <= gate.x <= 3.2 + 0.25 + RES                          # body still in the gap
    # nothing narrow within the lookahead, or a gap wide enough: no gate
    assert gate_on_path(cm.costmap, path, Pose2D(1.0, 0.8, 0.0), fp, 1.0, 0.15) is None
    wide = wall_with_gap(1.2, centre)
    assert gate_on_path(wide.costmap, path, Pose2D(1.0, 0.8, 0.0), fp, 4.0, 0.15) is None
    # the place the robot stands in is not the gate: past the gap, nothing ahead is narrow
    assert gate_on_path(cm.costmap, path, Pose2D(3.3, centre + 0.05, 0.0), fp, 4.0,
                        0.15) is None


def test_find_gate_on_path_writes_the_gate_or_fails():
    cm = wall_with_gap(0.62)
    robot = FakeRobot(Pose2D(1.0, 2.0, 0.0))
    env = Env({"clock": SimClock(), "robot": robot, "global_costmap": cm,
               "local_costmap": cm})
    node = env.node("FindGateOnPath", lookahead=3.0)
    assert tick(node) == F                                   # no path
    env.put("path", straight_path(Pose2D(1.0, 2.05, 0.0), Pose2D(5.0, 2.05, 0.0)))
    assert tick(node) == S
    gate = env.get("gate")
    assert gate.y == pytest.approx(2.0, abs=RES / 2 + 1e-6) and 3.0 <= gate.x <= 3.5
    env.put("path", straight_path(Pose2D(1.0, 1.0, 0.0), Pose2D(2.5, 1.0, 0.0)))
    assert tick(node) == F                                   # this path passes nothing narrow
