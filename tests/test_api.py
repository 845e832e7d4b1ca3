"""executive.api: the Navigator's task bookkeeping and the API's errors (docs/api.md has the
worked examples, run by test_api_docs.py)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from executive import (Navigator, Pose2D, TreeLoadError, WiringError, World, load_config,
                       load_tree, open_mission, parse_tree)
from executive.executive import Executive
from executive.task import _remaining
from hw.testing import KinematicRobot
from navcore.clock import SimClock
from navcore.synthetic_maps import ascii_map
from navcore.types import Path

ROOM = ascii_map("\n".join(["#" * 25] + ["#" + "." * 23 + "#"] * 10 + ["#" * 25]),
                 resolution=0.2)


@pytest.fixture(scope="module")
def config():
    return load_config()


def _robot_mission(config, tree="nav2") -> tuple[Navigator, KinematicRobot]:
    robot = KinematicRobot(Pose2D(1.0, 1.2), ranges=None)
    return open_mission(tree, config, ROOM, Pose2D(1.0, 1.2), io=robot), robot


def test_parse_tree_errors_name_the_text_and_line():
    with pytest.raises(TreeLoadError, match=r"^<mine>:4: .*NoSuchNode"):
        parse_tree("main_tree: M\ntrees:\n  M:\n    NoSuchNode: {}\n", name="<mine>")


def test_load_tree_by_shipped_name_gets_a_namespace_of_its_own():
    a, b = load_tree("nav2"), load_tree("nav2")
    assert a.source.endswith("trees/nav2.yaml") and a.namespace != b.namespace


def test_load_tree_takes_the_configs_port_defaults_and_a_nav2_distro():
    config = load_config({"behavior_server": {"max_rotational_vel": 0.5}})

    def spin_limits(tree):
        return [n.get_input("max_rotational_vel") for n in tree.root.iterate()
                if type(n).__name__ == "Spin"]
    plain, tuned = load_tree("nav2"), load_tree("nav2", config, nav2_distro="humble")
    assert spin_limits(plain) == [1.0] and spin_limits(tuned) == [0.5]
    assert plain.distro is None and tuned.distro == "humble"


def test_executive_refuses_a_namespace_other_than_its_trees(config):
    tree = load_tree("nav2")
    with pytest.raises(ValueError, match="not the tree's"):
        Executive(tree, KinematicRobot(ranges=None), SimClock(), 0.1, namespace="/elsewhere")


def test_open_mission_refuses_world_or_localisation_it_cannot_honour(config):
    with pytest.raises(WiringError, match="'world' and 'hardware'"):
        open_mission("nav2", config, ROOM, io=KinematicRobot(ranges=None), world=World())
    with pytest.raises(WiringError, match="needs a laser"):
        open_mission("nav2", config, ROOM, io=KinematicRobot(ranges=None), localise=True)
    with pytest.raises(WiringError, match="give a map"):
        open_mission("nav2", config)


def test_a_task_goes_through_its_waypoints_and_then_steps_no_more(config):
    nav, robot = _robot_mission(config)
    with pytest.raises(RuntimeError, match="no task"):
        nav.step()
    assert nav.status == "idle" and nav.is_task_complete() and nav.get_feedback() is None
    nav.follow_waypoints([Pose2D(2.5, 1.2), Pose2D(2.5, 1.6)])
    assert nav.status == "running" and not nav.is_task_complete()
    waypoints = []
    while not nav.step():
        waypoints.append(nav.get_feedback().current_waypoint)
    assert waypoints[0] == 0 and 1 in waypoints       # the second waypoint became current
    result = nav.get_result()
    assert result.succeeded and (result.goals_reached, result.goals_total) == (2, 2)
    ticks = nav.executive.tick_count
    assert nav.step() is True and nav.executive.tick_count == ticks   # ended: nothing runs
    assert robot.pose.distance_to(Pose2D(2.5, 1.6)) < 0.5
    nav.close()
    nav.close()                                        # once is enough; twice does nothing
    with pytest.raises(RuntimeError, match="closed"):
        nav.go_to_pose(Pose2D(2.0, 1.2))


def test_a_new_goal_replaces_the_running_task_and_cancel_stops_the_base(config):
    nav, robot = _robot_mission(config)
    nav.go_to_pose(Pose2D(4.0, 1.2))
    for _ in range(15):
        nav.step()
    assert robot.cmd.vx > 0.0
    first = nav._task
    nav.go_to_pose(Pose2D(1.0, 1.6))
    assert nav._task is not first and nav.get_result() is None
    assert nav.blackboard("goal") == Pose2D(1.0, 1.6)
    for _ in range(5):
        assert not nav.step()           # turning back: not there in half a second
    nav.cancel_task()
    assert nav.status == "canceled" and robot.cmd.is_zero()
    assert nav.executive.tree.root.status.name == "INVALID"     # halted
    nav.cancel_task()                                            # nothing left to cancel
    result = nav.get_result()
    assert result.outcome == "canceled"
    # the second task's own figures: its 5 cycles, not the first task's 15 too
    assert result.ticks == 5 and nav.executive.tick_count == 20
    assert 0.0 < result.distance < nav.executive.trace.distance() - 0.1
    nav.close()


def test_update_goal_keeps_the_task_running_and_add_waypoint_extends_it(config):
    nav, robot = _robot_mission(config)
    with pytest.raises(RuntimeError, match="no running task"):
        nav.update_goal(Pose2D(2.0, 1.2))
    nav.go_to_pose(Pose2D(4.0, 1.2))
    for _ in range(15):
        nav.step()
    task, started = nav._task, len(nav.executive.trace.goals)
    nav.update_goal(Pose2D(2.5, 1.6))
    # Nav2's pre-emption: the same task and the tree still running, the new goal on the board
    assert nav._task is task and nav.executive.tree.root.status.name == "RUNNING"
    assert nav.blackboard("goal") == Pose2D(2.5, 1.6)
    assert nav.blackboard("goals") == [Pose2D(2.5, 1.6)]
    assert len(nav.executive.trace.goals) == started          # no new goal was started
    fb = nav.get_feedback()
    assert fb.goal == Pose2D(2.5, 1.6) and fb.current_waypoint == 0
    assert fb.navigation_time == pytest.approx(1.5)          # the task's clock goes on
    nav.add_waypoint(Pose2D(1.5, 1.2))
    result = nav.run(time_limit=60.0)
    assert result.succeeded and (result.goals_reached, result.goals_total) == (2, 2)
    assert result.ticks > 15                                  # counted from the task's start
    assert robot.pose.distance_to(Pose2D(1.5, 1.2)) < 0.5
    with pytest.raises(RuntimeError, match="no running task"):
        nav.add_waypoint(Pose2D(2.0, 1.2))
    nav.close()


def test_feedback_distance_runs_along_the_path_from_its_nearest_pose():
    path = Path(np.array([[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [2.0, 3.0, 0.0]]))
    # nearest pose (2, 0) is 0.5 m away, then 3 m of path
    assert _remaining(path, Pose2D(2.0, 0.5), Pose2D(9.0, 9.0)) == pytest.approx(3.5)
    assert _remaining(None, Pose2D(0.0, 0.0), Pose2D(3.0, 4.0)) == pytest.approx(5.0)
    assert _remaining(Path(np.zeros((0, 3))), Pose2D(), Pose2D(0.0, 2.0)) == pytest.approx(2.0)
    assert math.isfinite(_remaining(path, Pose2D(-1.0, 0.0), Pose2D()))


def test_the_package_offers_every_api_name_and_only_those():
    import executive
    from executive import api
    assert sorted(executive.__all__) == sorted(api.__all__)
    assert all(getattr(executive, name) is getattr(api, name) for name in api.__all__)
    with pytest.raises(AttributeError, match="no attribute 'nope'"):
        executive.nope
