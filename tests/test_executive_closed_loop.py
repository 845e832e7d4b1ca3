"""Closed loop: every shipped tree drives the simulated robot to goals on two real maps.

Start and goal are chosen from the map itself (the most open free cell, then the most open cell
2.5..5 m away that the global planner reaches), so the test needs no hand-picked coordinates.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from tests.conftest import REAL_MAPS

TREES = ["move_base", "nav2", "smach_recovery", "near_goal_reconfigure"]
MAPS = ["robotis_office", "aws_small_house"]


def _clearance(grid) -> np.ndarray:
    from navcore.raycast import distance_field
    return np.asarray(distance_field((grid.data != 0).astype(np.uint8)), float) * grid.resolution


def pick_start_goal(grid, config):
    """The most open free cell, and a reachable open cell 2..5 m from it in open space."""
    from executive.config_costmaps import make_costmap
    from navcore.planners import make_planner
    from navcore.types import Pose2D
    d = _clearance(grid)
    sy, sx = np.unravel_index(int(np.argmax(d)), d.shape)
    start = Pose2D(*grid.map_to_world(sx + 0.5, sy + 0.5), 0.0)
    ys, xs = np.nonzero(d >= 0.5)
    wx = grid.origin.x + (xs + 0.5) * grid.resolution
    wy = grid.origin.y + (ys + 0.5) * grid.resolution
    dist = np.hypot(wx - start.x, wy - start.y)
    ok = (dist >= 2.0) & (dist <= 5.0)
    order = np.argsort(-d[ys[ok], xs[ok]])
    g = config.ns("global_costmap")
    g.setdefault("footprint", [list(p) for p in config.footprint()])
    cm = make_costmap(g, grid, "global_costmap")
    cm.update_map(start)
    planner = make_planner("navfn/NavfnROS", cm.costmap, {})
    for i in order[:400]:
        goal = Pose2D(float(wx[ok][i]), float(wy[ok][i]),
                      math.atan2(wy[ok][i] - start.y, wx[ok][i] - start.x))
        # open space all the way: this test is about the loop, not about tight spots
        t = np.linspace(0.0, 1.0, 40)
        cx = ((start.x + t * (goal.x - start.x) - grid.origin.x) / grid.resolution).astype(int)
        cy = ((start.y + t * (goal.y - start.y) - grid.origin.y) / grid.resolution).astype(int)
        if np.min(d[cy, cx]) < 0.45:
            continue
        if planner.make_plan(start, goal).ok:
            return start, goal
    pytest.skip("no reachable goal 2.5..5 m from the start")


@pytest.mark.parametrize("map_name", MAPS)
@pytest.mark.parametrize("tree", TREES)
def test_tree_reaches_goal_on_real_map(shared_data, map_name, tree, tmp_path):
    from executive.config import load_config
    from executive.tree_loader import shipped_tree
    from executive.mission import build_mission, run_mission
    from executive.recorder import Recorder
    from navcore.maps import load_map
    grid = load_map(shared_data / "maps" / REAL_MAPS[map_name])
    config = load_config()
    start, goal = pick_start_goal(grid, config)
    with open(tmp_path / "ticks.jsonl", "w") as log:
        m = build_mission(shipped_tree(tree), config, grid, start, recorder=Recorder(log))
        result = run_mission(m, [goal], time_limit=90.0)
    truth = m.sim.true_pose()
    assert result.outcome == "succeeded", (f"{tree} on {map_name}: {result.outcome} "
                                           f"({result.reason}) from {start} to {goal}, "
                                           f"ended at {truth}")
    assert truth.distance_to(goal) < 0.5
    assert result.collisions == 0
    assert result.distance >= start.distance_to(goal) - 0.3  # xy_goal_tolerance 0.25
    m.executive.shutdown()


def _config_with(**extra):
    import yaml

    from executive.config import DEFAULT_CONFIG, config_from_mapping
    doc = yaml.safe_load(DEFAULT_CONFIG.read_text())
    for ns, values in extra.items():
        if ns == "devices":
            doc["robot"]["devices"] = values
        else:
            doc[ns] = values
    return config_from_mapping(doc, "test-robot.yaml")


def test_amcl_localises_the_simulated_robot_to_its_goal():
    """With an ``amcl`` namespace the pose comes from AMCL, not from the simulator's truth."""
    from executive.mission import build_mission, run_mission
    from navcore.maps import load_map
    from navcore.types import Pose2D
    from executive.config import DEFAULT_CONFIG
    grid = load_map(DEFAULT_CONFIG.parent / "maps" / "two_rooms.yaml")
    config = _config_with(amcl={"min_particles": 200, "max_particles": 1000})
    m = build_mission(str(DEFAULT_CONFIG.parent.parent.parent / "trees" / "move_base.yaml"),
                      config, grid, Pose2D(5.5, 2.5, 0.0))
    assert m.components["localizer"] is not None
    goal = Pose2D(6.8, 1.2, -1.57)
    result = run_mission(m, [goal], time_limit=60.0)
    truth = m.sim.true_pose()
    estimate = m.executive.robot.pose()
    assert result.succeeded, result.reason
    assert truth.distance_to(estimate) < 0.2          # AMCL tracked the robot
    assert truth.distance_to(goal) < 0.45             # goal tolerance 0.25 + estimate error
    m.executive.shutdown()


def test_hardware_path_opens_robot_devices_on_the_wall_clock():
    """``hardware=True`` opens robot.devices (here device emulators) with reader threads on the
    wall clock and localises with AMCL. Only the wiring is checked: driving on the wall clock
    depends on the machine's load, so the closed loop through the drivers is tested in lock-step
    on the simulated clock (tests/test_hw_closed_loop.py, ``hardware="emulated"``)."""
    import hw.emulators as emu
    from executive.config import DEFAULT_CONFIG
    from executive.mission import HardwareIO, build_mission
    from navcore.clock import WallClock
    from navcore.maps import load_map
    from navcore.types import Pose2D
    grid = load_map(DEFAULT_CONFIG.parent / "maps" / "two_rooms.yaml")
    config = _config_with(devices={"base": "kobuki://sim?id=ecl-base",
                                   "laser": {"url": "urg04lx://sim?id=ecl-laser",
                                             "mount": [0.15, 0.0, 0.0]}},
                          amcl={"min_particles": 100, "max_particles": 500})
    m = build_mission(str(DEFAULT_CONFIG.parent.parent.parent / "trees" / "move_base.yaml"),
                      config, grid, Pose2D(5.0, 2.5, 0.0), hardware=True)
    ex = m.executive
    try:
        assert isinstance(ex.io, HardwareIO) and isinstance(ex.clock, WallClock)
        assert m.sim is None and ex.io.true_pose() is None
        assert m.components["localizer"] is not None        # no ground truth: AMCL
        base, laser = ex.io.devices["base"], ex.io.devices["laser"]
        assert base.url == "sim://kobuki?id=ecl-base" and laser.url == "sim://urg04lx?id=ecl-laser"
        assert base._thread is not None and base._thread.is_alive() and not base.polling
        assert laser._thread is not None and laser._thread.is_alive()
        assert ex.io.laser.mount == Pose2D(0.15, 0.0, 0.0)
    finally:
        ex.io.close()
        emu.unplug("ecl-base")
        emu.unplug("ecl-laser")
    assert base._thread is None and laser._thread is None and not base.connected


def test_setparameters_reaches_the_live_components():
    """The ``parameters`` handed to the tree are the components' own objects."""
    from executive.config import DEFAULT_CONFIG, load_config
    from executive.mission import build_mission
    from navcore.maps import load_map
    from navcore.types import Pose2D
    grid = load_map(DEFAULT_CONFIG.parent / "maps" / "two_rooms.yaml")
    m = build_mission(str(DEFAULT_CONFIG.parent.parent.parent / "trees" / "smach_recovery.yaml"),
                      load_config(), grid, Pose2D(5.0, 2.5, 0.0))
    params = m.components["parameters"]
    controller = m.components["controllers"]["FollowPath"]
    assert params["DWAPlannerROS"] is controller.params
    assert params["NavfnROS"] is m.components["planners"]["GridBased"].params
    assert "local_costmap/inflation_layer" in params and "move_base" in params
    previous = params["DWAPlannerROS"].set({"path_distance_bias": 5.0})
    assert controller.params.path_distance_bias == 5.0
    params["DWAPlannerROS"].set(previous)
    m.executive.shutdown()
