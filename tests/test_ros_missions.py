"""Missions with ROS users' unchanged files reach a goal on the TurtleBot3 world map, with the
footprint each file declares as the simulated body and the costmaps' footprint."""

from __future__ import annotations

import math

import numpy as np
import pytest
import yaml

from executive import ConfigSources, load_config
from tests.conftest import REAL_MAPS

# TurtleBot3's Gazebo spawn pose in turtlebot3_world, and a goal past the pillars
START = (-2.0, -0.5, 0.0)
GOAL = (1.6, -0.55, 0.0)


@pytest.fixture(scope="module")
def world(shared_data):
    from navcore.maps import load_map
    return load_map(shared_data / "maps" / REAL_MAPS["turtlebot3_world"])


def _run(config, grid, tree):
    """A mission through the public API (executive.open_mission), as a user would run it."""
    from executive import open_mission
    from navcore.types import Pose2D
    goal = Pose2D(*GOAL)
    with open_mission(tree, config, grid, start=Pose2D(*START)) as nav:
        nav.go_to_pose(goal, time_limit=90.0)
        result = nav.run()
        return nav.mission, result, goal


def _check(m, result, goal, tolerance):
    truth = m.sim.true_pose()
    assert result.outcome == "succeeded", (result.outcome, result.reason, truth)
    assert math.hypot(truth.x - goal.x, truth.y - goal.y) <= tolerance + 0.05
    assert result.collisions == 0


@pytest.mark.parametrize("model", ("burger", "waffle", "waffle_pi"))
def test_turtlebot3_launch_mission_reaches_goal(shared_data, world, model, monkeypatch):
    monkeypatch.delenv("TURTLEBOT3_MODEL", raising=False)
    root = shared_data / "ros_params" / "turtlebot3_navigation"
    if not root.is_dir():
        pytest.skip(f"TurtleBot3 files not found under {root}")
    declared = yaml.safe_load((root / "param" / f"costmap_common_params_{model}.yaml")
                              .read_text())["footprint"]
    config = load_config(ConfigSources(launch=str(root / "launch" / "move_base.launch"),
                                       args={"model": model}))
    m, result, goal = _run(config, world, "move_base")
    # the declared footprint is the simulated body and (padded by 0.01) the costmaps'
    assert np.allclose(m.sim.config.footprint, declared)
    padded = np.asarray(declared) + 0.01 * np.sign(declared)
    for cm in ("global_costmap", "local_costmap"):
        assert np.allclose(m.components[cm].footprint, padded)
    _check(m, result, goal, 0.05)   # the DWA files' xy_goal_tolerance


@pytest.mark.parametrize("distro", ("humble", "jazzy", "kilted", "main"))
def test_nav2_params_mission_reaches_goal(shared_data, world, distro):
    path = shared_data / "ros_params" / "nav2" / f"nav2_params_{distro}.yaml"
    if not path.exists():
        pytest.skip(f"{path} not found")
    config = load_config(ConfigSources(nav2_params=[str(path)]))
    m, result, goal = _run(config, world, "nav2")
    body = np.asarray(m.sim.config.footprint)
    assert np.allclose(np.hypot(body[:, 0], body[:, 1]), 0.22)   # robot_radius 0.22
    local = np.asarray(m.components["local_costmap"].footprint)
    assert np.allclose(np.hypot(local[:, 0], local[:, 1]).max(), 0.22 + 0.01 * math.sqrt(2),
                       atol=0.01)
    _check(m, result, goal, 0.25)   # the goal checker's xy_goal_tolerance
