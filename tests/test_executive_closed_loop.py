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
MAPS = ["turtlebot3_world", "aws_small_house"]


def _clearance(grid) -> np.ndarray:
    from navcore.raycast import distance_field
    return np.asarray(distance_field((grid.data != 0).astype(np.uint8)), float) * grid.resolution


def pick_start_goal(grid, config):
    """The most open free cell, and a reachable open cell 2.5..5 m from it."""
    from executive.config import make_costmap
    from navcore.planners import make_planner
    from navcore.types import Pose2D
    d = _clearance(grid)
    sy, sx = np.unravel_index(int(np.argmax(d)), d.shape)
    start = Pose2D(*grid.map_to_world(sx + 0.5, sy + 0.5), 0.0)
    ys, xs = np.nonzero(d >= 0.6)
    wx = grid.origin.x + (xs + 0.5) * grid.resolution
    wy = grid.origin.y + (ys + 0.5) * grid.resolution
    dist = np.hypot(wx - start.x, wy - start.y)
    ok = (dist >= 2.5) & (dist <= 5.0)
    order = np.argsort(-d[ys[ok], xs[ok]])
    g = config.ns("global_costmap")
    g.setdefault("footprint", [list(p) for p in config.footprint()])
    cm = make_costmap(g, grid, "global_costmap")
    cm.update_map(start)
    planner = make_planner("navfn/NavfnROS", cm.costmap, {})
    for i in order[:50]:
        goal = Pose2D(float(wx[ok][i]), float(wy[ok][i]),
                      math.atan2(wy[ok][i] - start.y, wx[ok][i] - start.x))
        if planner.make_plan(start, goal).ok:
            return start, goal
    pytest.skip("no reachable goal 2.5..5 m from the start")


@pytest.mark.parametrize("map_name", MAPS)
@pytest.mark.parametrize("tree", TREES)
def test_tree_reaches_goal_on_real_map(shared_data, map_name, tree, tmp_path):
    from executive.config import load_config
    from executive.loading import shipped_tree
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
    assert result.distance >= 0.9 * start.distance_to(goal)
    m.executive.shutdown()
