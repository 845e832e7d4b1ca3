"""navcore.planners.free_goal and NearestFreeGoal, tick by tick on scripted worlds (not the
scenario catalogue): a goal on a sensed box, a goal behind a wall, a goal deep in a map block."""

from __future__ import annotations


import numpy as np
from py_trees.common import Status

from behaviors.testing import FakeRobot, NodeRig
from navcore.clock import SimClock
from navcore.costmap.cost_values import INSCRIBED_INFLATED_OBSTACLE
from navcore.costmap.costmap2d import Costmap2D
from navcore.costmap.layered import LayeredCostmap
from navcore.error_codes import PlannerError
from navcore.planners import make_planner
from navcore.planners.free_goal import (free_candidates, label_free, label_free_reference,
                                        nearest_reachable_free_goal)
from navcore.synthetic_maps import ascii_map
from navcore.types import Pose2D

S, F = Status.SUCCESS, Status.FAILURE

# 8 m x 4 m at 0.2 m; a wall at x 4.0..4.2 with no door below y 3.0 (a way round at the top)
ROOM = "\n".join(["########################################"]
                 + ["#......................................#"] * 4
                 + ["#...................#..................#"] * 14
                 + ["########################################"])


def costmap(text: str = ROOM) -> LayeredCostmap:
    cm = LayeredCostmap.from_params(
        {"plugins": ["static_layer", "obstacle_layer", "inflation_layer"], "robot_radius": 0.15,
         "inflation_layer": {"inflation_radius": 0.3}}, static_map=ascii_map(text, 0.2),
        clock=SimClock())
    cm.update_map(Pose2D(1.0, 1.0, 0.0))
    return cm


def sense_box(cm: LayeredCostmap, x0: float, y0: float, x1: float, y1: float,
              seen_from: Pose2D) -> None:
    """The outline of a box the map does not know, as a laser marks it."""
    xs = np.arange(x0, x1 + 1e-9, 0.05)
    ys = np.arange(y0, y1 + 1e-9, 0.05)
    pts = np.concatenate([np.column_stack([xs, np.full_like(xs, y0)]),
                          np.column_stack([xs, np.full_like(xs, y1)]),
                          np.column_stack([np.full_like(ys, x0), ys]),
                          np.column_stack([np.full_like(ys, x1), ys])])
    pts = np.column_stack([pts, np.full(len(pts), 0.2)])
    cm.add_points(pts, (seen_from.x, seen_from.y, 0.2))
    cm.update_map(seen_from)


def test_label_free_kernel_matches_the_reference():
    rng = np.random.default_rng(7)
    for _ in range(20):
        free = rng.random((int(rng.integers(1, 30)), int(rng.integers(1, 30)))) < 0.55
        got = label_free(free)
        assert np.array_equal(got, label_free_reference(free))
        # each label is one 4-connected piece: neighbours that are both free share it
        assert np.all((got[:, 1:] == got[:, :-1]) | ~(free[:, 1:] & free[:, :-1]))
        assert np.all((got[1:] == got[:-1]) | ~(free[1:] & free[:-1]))
        assert np.array_equal(got > 0, free)


def test_candidates_are_one_per_piece_nearest_first_within_the_square():
    g = Costmap2D(20, 20, 0.1)
    g.costs[:, 10] = INSCRIBED_INFLATED_OBSTACLE          # a wall at x 1.0..1.1
    g.costs[9:11, 8:13] = 254                             # the goal's surroundings taken
    goal = Pose2D(1.05, 1.0, 0.3)
    c = free_candidates(g, goal, 0.25)
    # the wall and the taken rows leave four pieces (west/east, south/north): one cell each
    assert len(c) == 4
    assert all(abs(x - goal.x) <= 0.25 + 1e-9 and abs(y - goal.y) <= 0.25 + 1e-9 for x, y in c)
    assert sorted((x < 1.0, y < 1.0) for x, y in c) == [(False, False), (False, True),
                                                        (True, False), (True, True)]
    d = [np.hypot(x - goal.x, y - goal.y) for x, y in c]
    assert d == sorted(d)
    g.costs[9:11, 8:10] = 0                               # the west rows free again
    assert len(free_candidates(g, goal, 0.25)) == 3
    assert free_candidates(g, goal, 0.05) == []          # nothing free that close
    assert free_candidates(g, goal, 0.0) == []


def test_a_free_goal_is_kept_and_an_occupied_one_moves_to_the_reachable_side():
    cm = costmap()
    planner = make_planner("navfn/NavfnROS", cm.costmap)
    start = Pose2D(1.0, 2.0, 0.0)
    reach = lambda p: planner.make_plan(start, p).ok  # noqa: E731
    free = nearest_reachable_free_goal(cm.costmap, Pose2D(3.0, 2.0, 0.0), 0.5, reach)
    assert free.pose == Pose2D(3.0, 2.0, 0.0) and not free.substituted and free.plans == 0
    # a goal on the wall's west face: the nearest free cell west of it, on the robot's side
    on_wall = Pose2D(4.0, 1.0, 1.0)
    got = nearest_reachable_free_goal(cm.costmap, on_wall, 0.6, reach)
    assert got.substituted and got.pose is not None and got.pose.x < 4.0
    assert got.pose.theta == 1.0 and got.pose.distance_to(on_wall) <= 0.6 * np.sqrt(2)
    g = cm.costmap
    i, j = g.world_to_map(got.pose.x, got.pose.y)
    assert g.costs[j, i] < INSCRIBED_INFLATED_OBSTACLE
    # with the way round closed, the east side is unreachable: one plan says so for the piece
    closed = costmap(ROOM.replace("#......................................#",
                                  "#...................#..................#"))
    p2 = make_planner("navfn/NavfnROS", closed.costmap)
    east = Pose2D(4.15, 1.0, 0.0)                         # in the wall, nearer its east face
    r = nearest_reachable_free_goal(closed.costmap, east, 0.4,
                                    lambda p: p2.make_plan(start, p).ok)
    assert r.pose is not None and r.pose.x < 4.0          # the west piece, though farther
    assert r.plans == 2
    none = nearest_reachable_free_goal(closed.costmap, Pose2D(4.1, 1.0, 0.0), 0.4,
                                       lambda p: False)
    assert none.pose is None and not none.substituted


class Env(NodeRig):
    """A node on a real costmap with navfn planning on it and a fake robot at ``pose``."""

    def __init__(self, cm: LayeredCostmap, pose: Pose2D) -> None:
        self.planner = make_planner("navfn/NavfnROS", cm.costmap)
        super().__init__({"clock": SimClock(), "robot": FakeRobot(pose), "control_period": 0.05,
                          "global_costmap": cm, "planners": {"GridBased": self.planner}})


tick = NodeRig.tick


def test_nearest_free_goal_node_follows_the_goal_as_the_sensors_cover_it():
    cm = costmap()
    robot = Pose2D(1.0, 1.0, 0.0)
    env = Env(cm, robot)
    node = env.node("NearestFreeGoal", tolerance=0.5)
    assert tick(node) == F
    assert env.get("free_goal_error_code") == PlannerError.INVALID_GOAL
    goal = Pose2D(2.55, 1.6, 0.0)
    env.put("goal", goal)
    assert tick(node) == S                                # free: the goal itself
    assert env.get("free_goal") == goal and env.get("goal_substituted") is False
    sense_box(cm, 2.5, 1.2, 3.3, 2.4, Pose2D(2.0, 1.8, 0.0))   # a box the map lacks covers it
    assert tick(node) == S
    sub = env.get("free_goal")
    assert env.get("goal_substituted") is True and sub != goal
    assert sub.distance_to(goal) <= 0.5 * np.sqrt(2) and sub.x < 2.4
    assert env.planner.make_plan(robot, sub).ok
    assert env.get("free_goal_error_code") == 0
    strict = env.node("NearestFreeGoal", tolerance=0.1)   # nothing free that close
    assert tick(strict) == F
    assert env.get("free_goal_error_code") == PlannerError.GOAL_OCCUPIED


def test_nearest_free_goal_fails_with_goal_occupied_inside_a_map_block():
    block = ROOM.replace("#......................................#",
                         "#.......######.........................#", 1)
    block = "\n".join(r if i not in (2, 3, 4, 5) else r[:8] + "######" + r[14:]
                      for i, r in enumerate(block.split("\n")))
    cm = costmap(block)
    env = Env(cm, Pose2D(1.0, 1.0, 0.0))
    env.put("goal", Pose2D(2.2, 3.3, 0.0))                # the middle of the block
    node = env.node("NearestFreeGoal", tolerance=0.3)
    assert tick(node) == F
    assert env.get("free_goal_error_code") == PlannerError.GOAL_OCCUPIED
    assert tick(env.node("NearestFreeGoal", tolerance=1.2)) == S   # room enough further out
    assert env.get("goal_substituted") is True


def test_pieces_in_sight_of_the_robot_come_before_the_unseen_inside_of_a_box():
    g = Costmap2D(30, 30, 0.1)
    g.costs[5:26, 10] = 254                               # the face of a box the laser marked
    goal = Pose2D(1.08, 1.5, 0.0)                         # on it, nearer the unseen inside
    inside, outside = free_candidates(g, goal, 0.3)
    assert inside[0] > 1.1 and outside[0] < 1.0
    assert free_candidates(g, goal, 0.3, seen_from=(0.3, 1.5)) == [outside, inside]
    assert free_candidates(g, goal, 0.3, seen_from=(2.5, 1.5)) == [inside, outside]


def test_the_smach_tree_ends_at_the_substitute_and_says_so():
    """A goal just inside a box the map lacks (the catalogue's pallet, run here to read the
    blackboard): SUCCESS at the free pose NearestFreeGoal chose, goal_substituted true."""
    from pathlib import Path as FsPath

    import py_trees

    from executive.scenarios.parse import load_scenario
    from executive.scenarios.run import run_scenario
    root = FsPath(__file__).resolve().parent.parent
    seen = {}

    def on_tick(ex) -> None:
        storage = py_trees.blackboard.Blackboard.storage
        for key in ("free_goal", "goal_substituted"):
            value = storage.get(f"{ex.namespace}/{key}")
            if value is not None:
                seen[key] = value

    sc = load_scenario(root / "tests" / "scenarios" / "goal_on_unseen_pallet.yaml")
    r = run_scenario(sc, str(root / "trees" / "smach_recovery.yaml"), on_tick=on_tick)
    assert r.outcome == "succeeded" and r.collisions == 0
    assert seen["goal_substituted"] is True
    sub, goal = seen["free_goal"], Pose2D(4.1, 1.6, 0.0)
    assert 0.2 < sub.distance_to(goal) <= 0.5 * np.sqrt(2) and sub.x < 4.0    # outside the box
    x, y, _ = r.final_pose
    assert np.hypot(x - sub.x, y - sub.y) <= 0.25        # the controller's xy_goal_tolerance
