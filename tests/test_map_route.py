"""navcore.planners.map_route and the nodes on it (IsDetourLong, IsGoalReachableOnMap), tick by
tick on scripted worlds: a wall with a doorway that sensed points fill, and a closed room."""

from __future__ import annotations


import numpy as np
from py_trees.common import Status

from behaviors.testing import FakeRobot, NodeRig
from navcore.clock import SimClock
from navcore.costmap.cost_values import LETHAL_OBSTACLE
from navcore.costmap.layered import LayeredCostmap
from navcore.planners import make_planner
from navcore.planners.map_route import MapOnlyRoute, is_detour, map_only_costmap
from navcore.synthetic_maps import ascii_map
from navcore.types import Pose2D

S, F = Status.SUCCESS, Status.FAILURE

# 8 m x 6.4 m (0.2 m cells); a wall at x 4.0..4.2 m with a doorway at y 0.4..1.0 and a gap
# near the top (y 5.6..5.8)
WALL = """
########################################
#...................#..................#
#...................#..................#
#......................................#
#...................#..................#
#...................#..................#
#...................#..................#
#...................#..................#
#...................#..................#
#...................#..................#
#...................#..................#
#...................#..................#
#...................#..................#
#...................#..................#
#...................#..................#
#...................#..................#
#...................#..................#
#...................#..................#
#...................#..................#
#...................#..................#
#...................#..................#
#...................#..................#
#...................#..................#
#...................#..................#
#...................#..................#
#...................#..................#
#...................#..................#
#......................................#
#......................................#
#......................................#
#...................#..................#
########################################
"""


def costmap(text: str = WALL) -> LayeredCostmap:
    return LayeredCostmap.from_params(
        {"plugins": ["static_layer", "obstacle_layer", "inflation_layer"], "robot_radius": 0.15,
         "inflation_layer": {"inflation_radius": 0.3}}, static_map=ascii_map(text, 0.2),
        clock=SimClock())


def block_doorway(cm: LayeredCostmap) -> None:
    """Sensed points fill the low doorway."""
    ys = np.arange(0.3, 1.3, 0.05)
    pts = np.column_stack([np.full_like(ys, 4.1), ys, np.full_like(ys, 0.2)])
    cm.add_points(pts, (3.0, 0.8, 0.2))
    cm.update_map(Pose2D(3.0, 0.8, 0.0))


def test_map_only_costmap_leaves_sensed_obstacles_out_and_keeps_walls():
    cm = costmap()
    block_doorway(cm)
    i, j = cm.costmap.world_to_map(4.1, 0.9)
    assert cm.costmap.costs[j, i] == LETHAL_OBSTACLE
    mo = map_only_costmap(cm)
    assert mo.costs[j, i] < LETHAL_OBSTACLE
    assert np.count_nonzero(mo.costs == LETHAL_OBSTACLE) == \
        np.count_nonzero(map_only_costmap(costmap()).costs == LETHAL_OBSTACLE)
    wi, wj = cm.costmap.world_to_map(4.1, 2.0)            # the wall itself stays
    assert mo.costs[wj, wi] == LETHAL_OBSTACLE


def test_is_detour_needs_both_the_ratio_and_the_extra_length():
    assert is_detour(10.0, 4.0, 2.0, 2.0)
    assert not is_detour(7.0, 4.0, 2.0, 2.0)             # only 1.75 times
    assert not is_detour(0.9, 0.4, 2.0, 2.0)             # 2.25 times but 0.5 m
    assert is_detour(0.9, 0.4, 2.0, 0.4)


def test_map_only_route_is_the_short_one_while_the_real_planner_detours():
    cm = costmap()
    planner = make_planner("navfn/NavfnROS", cm.costmap)
    start, goal = Pose2D(2.0, 0.9, 0.0), Pose2D(6.0, 0.9, 0.0)
    block_doorway(cm)
    real = planner.make_plan(start, goal)
    assert real.ok
    route = MapOnlyRoute(cm, planner)
    short = route.length(start, goal)
    assert short is not None and 3.9 < short < 5.0
    assert real.path.length() > 2.0 * short               # round the top gap


class Env(NodeRig):
    """A node on a real costmap with navfn planning on it and a fake robot at ``pose``."""

    def __init__(self, cm: LayeredCostmap, pose: Pose2D) -> None:
        self.robot = FakeRobot(pose)
        self.planner = make_planner("navfn/NavfnROS", cm.costmap)
        super().__init__({"clock": SimClock(), "robot": self.robot, "control_period": 0.05,
                          "global_costmap": cm, "planners": {"GridBased": self.planner}})


tick = NodeRig.tick


def test_is_detour_long_fires_once_per_goal_on_a_detour_and_never_on_the_direct_plan():
    cm = costmap()
    start, goal = Pose2D(2.0, 0.9, 0.0), Pose2D(6.0, 0.9, 0.0)
    env = Env(cm, start)
    node = env.node("IsDetourLong", ratio=2.0, min_extra=2.0)
    assert tick(node) == F                                # no path yet
    env.put("goal", goal)
    env.put("path", env.planner.make_plan(start, goal).path)
    assert tick(node) == F                                # the direct plan
    block_doorway(cm)
    env.put("path", env.planner.make_plan(start, goal).path)
    assert tick(node) == S                                # the detour: look again first
    assert tick(node) == F                                # once per goal: now drive it
    env.put("path", env.planner.make_plan(start, goal).path)
    assert tick(node) == F
    goal2 = Pose2D(6.0, 1.1, 0.0)                          # a new goal: one more look
    env.put("goal", goal2)
    env.put("path", env.planner.make_plan(start, goal2).path)
    assert tick(node) == S
    lenient = env.node("IsDetourLong", ratio=20.0, min_extra=2.0)
    assert tick(lenient) == F                              # not 20 times longer


def test_is_detour_long_judges_as_is_detour_on_the_map_only_length_and_plans_only_when_it_can():
    """Its verdict is is_detour(plan length, map-only length) on every plan; a plan shorter than
    ``min_extra`` is no detour whatever the map-only route, and gets no map-only plan."""
    rng = np.random.default_rng(3)
    planned = 0
    for blocked in (False, True):
        cm = costmap()
        if blocked:
            block_doorway(cm)
        for _ in range(12):
            start = Pose2D(float(rng.uniform(1.0, 3.8)), float(rng.uniform(0.5, 5.5)), 0.0)
            goal = Pose2D(float(rng.uniform(1.0, 7.5)), float(rng.uniform(0.5, 1.0)), 0.0)
            env = Env(cm, start)
            path = env.planner.make_plan(start, goal).path
            if path is None or len(path) < 2:
                continue
            route = MapOnlyRoute(cm, env.planner)
            map_length = route.length(Pose2D(*path.poses[0]), goal)
            for ratio, min_extra in ((1.2, 0.5), (2.0, 2.0), (1.5, 5.0)):
                node = env.node("IsDetourLong", ratio=ratio, min_extra=min_extra, max_per_goal=0)
                calls = []
                plan = node.route.plan
                node.route.plan = lambda a, b: calls.append(1) or plan(a, b)
                env.put("goal", goal)
                env.put("path", path)
                want = map_length is not None and is_detour(path.length(), map_length, ratio,
                                                            min_extra)
                assert tick(node) == (S if want else F)
                assert len(calls) == (0 if path.length() < min_extra else 1)
                planned += len(calls)
    assert 0 < planned < 72                          # some plans skipped, some made


def test_is_goal_reachable_on_map_fails_for_a_closed_room_only():
    room = WALL.replace("#......................................#", "#...................#..................#")
    cm = costmap(room)
    env = Env(cm, Pose2D(2.0, 0.9, 0.0))
    node = env.node("IsGoalReachableOnMap")
    assert tick(node) == F                                 # no goal
    env.put("goal", Pose2D(6.0, 0.9, 0.0))
    assert tick(node) == F                                 # walled off on the map itself
    env.put("goal", Pose2D(3.0, 3.0, 0.0))
    assert tick(node) == S
    env.put("goal", Pose2D(4.1, 3.0, 0.0))                 # inside the wall
    assert tick(node) == F
    carrot = Env(cm, Pose2D(2.0, 0.9, 0.0))
    carrot.components["planners"] = {"GridBased": object()}   # not navfn / global_planner
    carrot.put("goal", Pose2D(6.0, 0.9, 0.0))
    assert tick(carrot.node("IsGoalReachableOnMap")) == S   # cannot judge: recover
    open_cm = costmap()
    block_doorway(open_cm)                                 # sensed only: a recovery may help
    env2 = Env(open_cm, Pose2D(2.0, 0.9, 0.0))
    env2.put("goal", Pose2D(6.0, 0.9, 0.0))
    assert tick(env2.node("IsGoalReachableOnMap")) == S


def doorway_scan(now: float) -> "LaserScan":
    """A scan from (3.0, 0.8) facing +x whose beams end on the blocked doorway at x 4.1."""
    from navcore.types import LaserScan
    angles = np.arange(-0.3, 0.3 + 1e-9, 0.02)
    return LaserScan(now, float(angles[0]), float(angles[-1]), 0.02, 0.0, 0.1, 0.1, 5.0,
                     1.1 / np.cos(angles))


def test_is_detour_long_age_clears_only_what_has_gone_unseen():
    from navcore.clock import SimClock as Clock
    from navcore.costmap.blocking import blocking_cells, last_seen_occupied
    from navcore.costmap.observed_space import ObservedSpace
    cm = costmap()
    block_doorway(cm)
    start, goal = Pose2D(2.0, 0.9, 0.0), Pose2D(6.0, 0.9, 0.0)
    env = Env(cm, start)
    clock = Clock()
    env.components["clock"] = clock
    observed = ObservedSpace.around(0.2, 12.0, 12.0, [[0.15, 0.15], [0.15, -0.15],
                                                       [-0.15, -0.15], [-0.15, 0.15]])
    observed.recentre(3.0, 0.8)
    env.components["observed_space"] = observed
    detour = env.planner.make_plan(start, goal).path
    route = MapOnlyRoute(cm, env.planner).plan(start, goal).path
    cells = blocking_cells(cm, route, 0.15)
    assert len(cells) > 0 and np.all(np.abs(cells[:, 0] - 4.1) < 0.2)   # the doorway's fill
    assert last_seen_occupied(observed, cells) == -np.inf               # never seen: a phantom
    env.put("goal", goal)
    aged = env.node("IsDetourLong", ratio=2.0, min_extra=2.0, age=5.0)
    env.put("path", detour)
    assert tick(aged) == S                                  # nobody saw it: clear first
    clock.advance(10.0)
    observed.add_scan(doorway_scan(clock.now()), Pose2D(3.0, 0.8, 0.0), clock.now())
    assert last_seen_occupied(observed, cells) == clock.now()
    clock.advance(1.0)
    fresh = env.node("IsDetourLong", ratio=2.0, min_extra=2.0, age=5.0)
    env.put("path", env.planner.make_plan(start, goal).path)
    assert tick(fresh) == F                                 # seen 1 s ago: drive the detour
    assert tick(env.node("IsDetourLong", ratio=2.0, min_extra=2.0)) == S    # age not checked
    clock.advance(5.0)                                      # 6 s unseen (the laser looks away)
    env.put("path", env.planner.make_plan(start, goal).path)
    assert tick(fresh) == F                 # that look counted: not questioned again behind it
    unlimited = env.node("IsDetourLong", ratio=2.0, min_extra=2.0, age=5.0, max_per_goal=0)
    assert tick(unlimited) == S                             # unseen for 6 s: look again
    env.components["observed_space"] = None                 # no memory: the ratio alone
    blind = env.node("IsDetourLong", ratio=2.0, min_extra=2.0, age=100.0)
    assert tick(blind) == S
