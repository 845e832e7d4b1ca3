"""Tight spots (issue 17, class 6): the room across a goal, the pre-pose in front of a bay, the
straight entry, the straightest escape from inflated space, and global_planner's
START_OCCUPIED. Scripted worlds of their own (bays of other widths and headings, starts against
walls on every side), none of them a catalogue scenario."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from py_trees.common import Status

from behaviors.testing import FakeRobot, NodeRig, ScriptedWorld
from navcore.clock import SimClock
from navcore.costmap.cost_values import INSCRIBED_INFLATED_OBSTACLE
from navcore.costmap.layered import LayeredCostmap
from navcore.error_codes import DriveOnHeadingError, RecoveryError
from navcore.motion.line_up import entry_blocked, goal_room, line_offsets, pre_pose, segment_poses
from navcore.motion.start_escape import motion_poses, nearer_than, start_gap, straightest_escape
from navcore.planners import make_planner
from navcore.synthetic_maps import ascii_map
from navcore.types import Pose2D, Twist

RES = 0.05
FOOTPRINT = [[0.25, 0.22], [0.25, -0.22], [-0.25, -0.22], [-0.25, 0.22]]
BODY_HALF = 0.22 + 0.03           # the padded footprint the costmap checks
HEADINGS = {"south": -math.pi / 2, "north": math.pi / 2, "west": math.pi, "east": 0.0}


def room(w: float = 5.0, h: float = 4.0) -> np.ndarray:
    g = np.full((int(round(h / RES)), int(round(w / RES))), ".")
    g[0, :] = g[-1, :] = g[:, 0] = g[:, -1] = "#"
    return g


def wall(g: np.ndarray, x0: float, y0: float, x1: float, y1: float) -> None:
    """Fill the cells of the rectangle [x0, x1] x [y0, y1] (m; row 0 is the top)."""
    h = g.shape[0]
    c0, c1 = int(round(x0 / RES)), int(round(x1 / RES))
    r0, r1 = int(round(y0 / RES)), int(round(y1 / RES))
    g[h - r1:h - r0, c0:c1] = "#"


def bay(g: np.ndarray, side: str, width: float, depth: float = 0.8, at: float = 2.0
        ) -> Pose2D:
    """Two walls 5 cm thick forming a bay ``width`` m wide and ``depth`` m deep at the room's
    ``side`` wall, centred ``at`` m along it; the goal 0.45 m from the bay's end, facing in."""
    h, w = g.shape[0] * RES, g.shape[1] * RES
    t, half = 0.05, width / 2.0
    if side in ("south", "north"):
        y0, y1 = (RES, RES + depth) if side == "south" else (h - RES - depth, h - RES)
        wall(g, at - half - t, y0, at - half, y1)
        wall(g, at + half, y0, at + half + t, y1)
        y = RES + 0.45 if side == "south" else h - RES - 0.45
        return Pose2D(at, y, HEADINGS[side])
    x0, x1 = (RES, RES + depth) if side == "west" else (w - RES - depth, w - RES)
    wall(g, x0, at - half - t, x1, at - half)
    wall(g, x0, at + half, x1, at + half + t)
    x = RES + 0.45 if side == "west" else w - RES - 0.45
    return Pose2D(x, at, HEADINGS[side])


def costmap(g: np.ndarray, inflation: float = 0.55) -> LayeredCostmap:
    grid = ascii_map("\n".join("".join(r) for r in g), RES)
    cm = LayeredCostmap.from_params(
        {"plugins": ["static_layer", "inflation_layer"], "footprint": FOOTPRINT,
         "footprint_padding": 0.03,
         "inflation_layer": {"inflation_radius": inflation, "cost_scaling_factor": 10.0}},
        static_map=grid, clock=SimClock())
    cm.update_map(Pose2D(1.0, 1.0, 0.0))
    return cm


# ------------------------------------------------------------------------------ navcore


@pytest.mark.parametrize("side,width", [("south", 0.62), ("north", 0.7), ("west", 0.8),
                                        ("east", 1.4)])
def test_goal_room_measures_the_bay_across_the_goal_heading(side, width):
    g = room()
    goal = bay(g, side, width)
    cm = costmap(g)
    r = goal_room(cm.costmap, goal, np.asarray(cm.footprint))
    assert r.width == pytest.approx(width, abs=RES)          # to a cell, whatever the heading
    assert r.margin == pytest.approx(width / 2 - BODY_HALF, abs=RES)
    # in the open middle of the room: metres of room
    assert goal_room(cm.costmap, Pose2D(2.5, 2.0, 0.7), np.asarray(cm.footprint)).width >= 2.5


@pytest.mark.parametrize("side", ["south", "west", "north", "east"])
def test_pre_pose_is_on_the_goal_line_outside_the_bay_with_a_passable_way_in(side):
    g = room()
    goal = bay(g, side, 0.7, depth=1.0)
    cm = costmap(g)
    fp = np.asarray(cm.footprint)
    p = pre_pose(cm, goal, fp, 0.5, 0.15)
    assert p is not None
    to_go, lateral, heading = line_offsets(goal, p)
    assert abs(lateral) < 1e-6 and abs(heading) < 1e-6
    # the bay's mouth is 0.55 m behind the goal: the body (front 0.28 m) and its turning
    # circle (0.38 m) are out of it, although 0.5 m was asked for, and its footprint is free
    # there; a cell nearer it is not
    assert 0.55 + 0.38 - RES <= to_go <= 0.55 + 0.38 + 0.3
    assert 0 <= cm.footprint_cost(p.x, p.y, p.theta) < INSCRIBED_INFLATED_OBSTACLE
    nearer = p.compose(Pose2D(RES, 0.0, 0.0))
    assert to_go - RES < 0.55 + 0.38 - RES or \
        cm.footprint_cost(nearer.x, nearer.y, nearer.theta) >= INSCRIBED_INFLATED_OBSTACLE
    assert entry_blocked(cm, segment_poses(p, goal, RES / 2)) is None
    # far enough out anyway when more is asked for
    far = pre_pose(cm, goal, fp, 1.6, 0.15)
    assert far is not None and line_offsets(goal, far)[0] == pytest.approx(1.6, abs=1e-6)


def test_no_pre_pose_when_the_way_in_is_blocked_or_the_goal_does_not_fit():
    g = room()
    goal = bay(g, "south", 0.7)
    wall(g, 1.9, 1.2, 2.1, 1.3)                      # a box across the bay's mouth
    cm = costmap(g)
    assert pre_pose(cm, goal, np.asarray(cm.footprint), 1.0, 0.15) is None
    g = room()
    goal = bay(g, "south", 0.4)                       # narrower than the robot
    cm = costmap(g)
    assert entry_blocked(cm, segment_poses(goal.compose(Pose2D(-1.0, 0, 0)), goal, RES)) \
        is not None
    assert pre_pose(cm, goal, np.asarray(cm.footprint), 1.0, 0.15) is None


def test_entry_blocked_allows_inscribed_cost_but_not_the_body_on_a_wall():
    g = room()
    goal = bay(g, "west", 0.6)                        # 7 cm of room beside the padded body
    cm = costmap(g)
    inside = segment_poses(goal.compose(Pose2D(-1.2, 0, 0)), goal, RES)
    costs = cm.footprint_costs(inside)
    assert costs.max() >= INSCRIBED_INFLATED_OBSTACLE  # the whole bay is inscribed cost
    assert entry_blocked(cm, inside) is None
    sideways = segment_poses(goal.compose(Pose2D(-1.2, 0.12, 0)),
                             goal.compose(Pose2D(0.0, 0.12, 0)), RES)
    i = entry_blocked(cm, sideways)
    assert i is not None and 0 < i < len(sideways) - 1   # it hits the bay wall on the way


def test_motion_poses_follow_straight_lines_and_arcs():
    p = Pose2D(1.0, 2.0, math.pi / 2)
    s = motion_poses(p, -1.0, 0.0, 0.1, 3)
    assert s[-1] == pytest.approx([1.0, 1.7, math.pi / 2])
    a = motion_poses(p, 1.0, 2.0, math.pi / 16, 4)                # a quarter turn, radius 0.5
    assert a[-1][:2] == pytest.approx([0.5, 2.5], abs=1e-9)
    assert abs(math.remainder(a[-1][2] - math.pi, 2 * math.pi)) < 1e-9


@pytest.mark.parametrize("side,start,expect", [
    ("south", Pose2D(2.5, 0.42, math.pi), "arc"),        # wall beside: no straight way out
    ("north", Pose2D(1.5, 3.6, -0.3), "arc"),
    ("east", Pose2D(4.62, 2.0, 0.0), "backwards"),        # facing the wall, 13 cm from it
    ("west", Pose2D(0.37, 1.0, 0.0), "forwards"),         # back to the wall
    ("corner", Pose2D(0.42, 0.42, math.pi / 4), "forwards"),
])
def test_straightest_escape_frees_the_footprint_soonest_without_touching(side, start, expect):
    cm = costmap(room())
    assert cm.footprint_cost(start.x, start.y, start.theta) >= INSCRIBED_INFLATED_OBSTACLE
    m = straightest_escape(cm, start, 1.0)
    assert m is not None
    kind = "arc" if m.curvature else ("forwards" if m.direction > 0 else "backwards")
    assert kind == expect
    assert 0 <= cm.footprint_cost(m.end.x, m.end.y, m.end.theta) < INSCRIBED_INFLATED_OBSTACLE
    way = motion_poses(start, m.direction, m.curvature, 0.02, int(round(m.distance / 0.02)))
    costs = cm.footprint_costs(way)
    assert np.all(costs[:-1] >= INSCRIBED_INFLATED_OBSTACLE)     # free no sooner than said
    assert entry_blocked(cm, way) is None                         # and the body never on a wall
    # nothing frees it sooner: a 1 m limit shorter than the motion finds nothing
    assert straightest_escape(cm, start, m.distance - 0.03) is None


def test_straightest_escape_never_closes_in_on_the_wall_beside_it():
    # parallel to a shelf 3 cm away: every arc swings a corner towards it, so the way out is
    # straight along it, past its end
    g = room()
    wall(g, 1.0, 0.05, 3.0, 0.5)
    cm = costmap(g)
    start = Pose2D(2.6, 0.5 + 0.22 + 0.03, 0.0)
    gap = start_gap(cm, start)
    assert 0.0 < gap < 0.05
    assert straightest_escape(cm, start, 0.6) is None
    m = straightest_escape(cm, start, 2.0)
    assert m is not None and m.curvature == 0.0 and m.direction > 0
    way = motion_poses(start, m.direction, m.curvature, 0.02, int(round(m.distance / 0.02)))
    assert nearer_than(cm, [Pose2D(*p) for p in way], gap) is None
    arc = motion_poses(start, 1.0, 1.0, 0.02, 30)
    assert nearer_than(cm, [Pose2D(*p) for p in arc], gap) is not None


def test_straightest_escape_none_when_boxed_in():
    g = room()
    wall(g, 1.0, 1.0, 1.6, 1.05)
    wall(g, 1.0, 1.5, 1.6, 1.55)
    wall(g, 1.0, 1.0, 1.05, 1.55)
    wall(g, 1.55, 1.0, 1.6, 1.55)
    cm = costmap(g)
    assert straightest_escape(cm, Pose2D(1.3, 1.275, 0.0), 1.0) is None


def test_global_planner_reports_a_start_in_inscribed_cost_navfn_plans_from_it():
    g = room()
    cm = costmap(g)
    start, goal = Pose2D(2.5, 0.28, 0.0), Pose2D(2.5, 2.5, 0.0)    # centre 23 cm off the wall
    cell = cm.costmap.world_to_map(start.x, start.y)
    assert cm.costmap.costs[cell[1], cell[0]] == INSCRIBED_INFLATED_OBSTACLE
    gp = make_planner("global_planner/GlobalPlanner", cm.costmap)
    r = gp.make_plan(start, goal)
    assert (r.ok, r.reason) == (False, "start_occupied")
    assert make_planner("navfn/NavfnROS", cm.costmap).make_plan(start, goal).ok
    old = make_planner("global_planner/GlobalPlanner", cm.costmap, {"old_navfn_behavior": True})
    assert old.make_plan(start, goal).ok
    # from free space it plans as before
    assert gp.make_plan(Pose2D(2.5, 1.0, 0.0), goal).ok


# ------------------------------------------------------------------------------ nodes

_ns = itertools.count()


class Rig(NodeRig):
    """One node on a real costmap (local and global alike) with a kinematic robot."""

    def __init__(self, g: np.ndarray, pose: Pose2D) -> None:
        cm = costmap(g)
        super().__init__(ScriptedWorld(robot=FakeRobot(pose), local_costmap=cm, global_costmap=cm,
                               control_period=0.1))

    def run(self, node, max_ticks=1000):
        """Tick until it finishes, the robot following cmd_vel; (status, ticks, poses)."""
        poses = []
        for i in range(max_ticks):
            self.put("cmd_vel", Twist.zero())
            node.tick_once()
            if node.status != Status.RUNNING:
                assert self.get("cmd_vel") == Twist.zero()     # every exit stops the robot
                return node.status, i + 1, poses
            cmd = self.get("cmd_vel")
            self.world.step(cmd)
            poses.append(self.world.robot.pose())
        return node.status, max_ticks, poses


@pytest.mark.parametrize("side,width", [("east", 0.66), ("north", 0.72)])
def test_narrow_condition_pre_pose_and_straight_entry_park_in_a_bay(side, width):
    g = room()
    goal = bay(g, side, width)
    rig = Rig(g, Pose2D(2.5, 1.2, 1.0))
    rig.put("goal", goal)
    cond = rig.node("IsGoalInNarrowSpace", narrow_margin=0.15, free_width="{free_width}")
    cond.tick_once()
    assert cond.status == Status.SUCCESS
    assert rig.get("free_width") == pytest.approx(width, abs=RES)
    # the same bay counts as open with a smaller margin asked for
    loose = rig.node("IsGoalInNarrowSpace", narrow_margin=width / 2 - BODY_HALF - 2 * RES)
    loose.tick_once()
    assert loose.status == Status.FAILURE
    pre = rig.node("ComputePrePose", prepose_distance=1.0)
    pre.tick_once()
    p = rig.get("pre_pose")
    assert pre.status == Status.SUCCESS and line_offsets(goal, p)[0] >= 1.0
    lined = rig.node("IsLinedUp")
    lined.tick_once()
    assert lined.status == Status.FAILURE                 # the robot is off the line
    # stand roughly at the pre-pose (6 cm beside, 0.1 rad off, as a local planner leaves it)
    for off in (Pose2D(0.0, 0.15, 0.0), Pose2D(0.0, 0.0, 0.3), Pose2D(-1.2, 0.0, 0.0)):
        rig.world.robot.teleport(p.compose(off))      # beside, askew, too far out
        lined.tick_once()
        assert lined.status == Status.FAILURE, off
    rig.world.robot.teleport(goal.compose(Pose2D(0.1, 0.0, 0.0)))   # past the goal
    lined.tick_once()
    assert lined.status == Status.FAILURE
    rig.world.robot.teleport(p.compose(Pose2D(0.0, 0.06, 0.1)))
    lined.tick_once()
    assert lined.status == Status.SUCCESS
    status, ticks, poses = rig.run(rig.node("ApproachStraight", entry_speed=0.1))
    assert status == Status.SUCCESS and rig.get("approach_straight_error_code") == 0
    end = rig.world.robot.pose()
    assert end.distance_to(goal) <= 0.05 and abs(line_offsets(goal, end)[2]) <= 0.05
    way = np.array([[q.x, q.y, q.theta] for q in poses])
    assert entry_blocked(rig.world.local_costmap, way) is None   # never on a wall
    # inside the bay (its mouth 0.35 m behind the goal) it drives straight: within 3 cm of
    # the line, the start's 6 cm taken out before
    inside = [q for q in poses if line_offsets(goal, q)[0] < 0.35]
    assert inside and max(abs(line_offsets(goal, q)[1]) for q in inside) < 0.03
    assert ticks * 0.1 < 25.0


def test_approach_straight_refuses_to_start_off_the_line_and_stops_before_an_obstacle():
    g = room()
    goal = bay(g, "south", 0.72)
    rig = Rig(g, goal.compose(Pose2D(-1.2, 0.5, 0.0)))
    rig.put("goal", goal)
    status, ticks, _ = rig.run(rig.node("ApproachStraight"))
    assert (status, ticks) == (Status.FAILURE, 1)
    assert rig.get("approach_straight_error_code") == DriveOnHeadingError.INVALID_INPUT
    g2 = g.copy()
    wall(g2, goal.x - 0.1, 0.55, goal.x + 0.1, 0.6)       # a box in the bay, before the goal
    rig = Rig(g2, goal.compose(Pose2D(-1.2, 0.0, 0.0)))
    rig.put("goal", goal)
    status, _, poses = rig.run(rig.node("ApproachStraight"))
    assert status == Status.FAILURE
    assert rig.get("approach_straight_error_code") == DriveOnHeadingError.COLLISION_AHEAD
    way = np.array([[q.x, q.y, q.theta] for q in poses])
    assert entry_blocked(rig.world.local_costmap, way) is None


@pytest.mark.parametrize("start", [Pose2D(2.5, 0.42, 0.0), Pose2D(4.62, 3.0, 0.2),
                                   Pose2D(0.36, 2.0, -1.5708)])
def test_start_escape_drives_out_of_inflation_then_succeeds_and_is_idle_when_free(start):
    rig = Rig(room(), start)
    cm = rig.world.local_costmap
    assert cm.footprint_cost(start.x, start.y, start.theta) >= INSCRIBED_INFLATED_OBSTACLE
    node = rig.node("StartEscape", speed=0.1)
    status, ticks, poses = rig.run(node)
    assert status == Status.SUCCESS and rig.get("start_escape_error_code") == 0
    end = rig.world.robot.pose()
    assert 0 <= cm.footprint_cost(end.x, end.y, end.theta) < INSCRIBED_INFLATED_OBSTACLE
    way = np.array([[q.x, q.y, q.theta] for q in poses])
    assert entry_blocked(cm, way) is None                  # the body never on a wall
    m = straightest_escape(cm, start, 1.0)
    assert end.distance_to(start) <= m.distance + 0.02     # the motion planned, no farther
    # a second run from a free footprint succeeds at once without moving
    status, ticks, _ = rig.run(rig.node("StartEscape"))
    assert (status, ticks) == (Status.SUCCESS, 1)


def test_start_escape_fails_cleanly_when_nothing_frees_the_footprint():
    g = room()
    wall(g, 1.0, 1.0, 1.6, 1.05)
    wall(g, 1.0, 1.5, 1.6, 1.55)
    wall(g, 1.0, 1.0, 1.05, 1.55)
    wall(g, 1.55, 1.0, 1.6, 1.55)
    rig = Rig(g, Pose2D(1.3, 1.275, 0.0))
    status, ticks, _ = rig.run(rig.node("StartEscape"))
    assert (status, ticks) == (Status.FAILURE, 1)
    assert rig.get("start_escape_error_code") == RecoveryError.NO_FREE_POSE


# ------------------------------------------------------------------------------ the tree


def test_smach_tree_lines_up_then_enters_a_bay_straight():
    """The shipped tree on scripted components and a real costmap: a narrow goal is reached by
    the pre-pose leg (FollowPath to the pre-pose) and then ApproachStraight, no recovery."""
    from py_trees.visitors import VisitorBase

    from behaviors.testing import ScriptedController, ScriptedPlanner, run_tree
    from executive.tree_loader import load_tree_file, shipped_tree

    g = room()
    goal = bay(g, "south", 0.72)
    cm = costmap(g)
    w = ScriptedWorld(robot=FakeRobot(Pose2D(goal.x, 3.4, -math.pi / 2)), local_costmap=cm,
              global_costmap=cm, planner=ScriptedPlanner(), controller=ScriptedController(),
              control_period=0.1)
    tree = load_tree_file(shipped_tree("smach_recovery"), namespace=f"/tightree{next(_ns)}")
    done = {}

    class Visits(VisitorBase):
        def run(self, node):
            if node.status in (Status.SUCCESS, Status.FAILURE):
                done.setdefault(node.name, []).append(node.status)

    tree.tree.add_visitor(Visits(full=False))
    tree.setup(**w.components())
    tree.set("goal", goal)
    status, ticks = run_tree(tree, w, max_ticks=3000)
    end = w.robot.pose()
    assert status == Status.SUCCESS
    assert end.distance_to(goal) <= 0.05 and abs(line_offsets(goal, end)[2]) <= 0.05
    assert done["IsGoalInNarrowSpace"][0] == Status.SUCCESS
    assert Status.SUCCESS in done["FollowPathToPrePose"]          # lined up first
    assert done["ApproachStraight"] == [Status.SUCCESS]           # then in, straight, once
    assert "FollowPath" not in done                                # never the usual follow
    assert w.planner.goals[0].distance_to(goal) >= 1.0            # planned to the pre-pose
