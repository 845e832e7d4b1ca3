"""Navigation actions and recoveries against scripted components, tick by tick."""

from __future__ import annotations

import math

import numpy as np

import pytest
from py_trees.common import Status

from navcore.error_codes import (BackUpError, ControllerError, DriveOnHeadingError, PlannerError,
                                 RecoveryError, SpinError)
from behaviors.testing import (FakeCostmap, NodeRig, ScriptedController, ScriptedPlanner,
                               ScriptedWorld, straight_path)
from navcore.planners.result import PlanReason, PlanResult
from navcore.types import Path, Pose2D, Twist

S, F, R, I = Status.SUCCESS, Status.FAILURE, Status.RUNNING, Status.INVALID


class Rig(NodeRig):
    """One node, a ScriptedWorld (a fresh one by default), and the blackboard of its namespace."""

    def __init__(self, world: ScriptedWorld | None = None):
        super().__init__(world or ScriptedWorld())


def test_compute_path_to_pose_writes_path_or_error_code():
    rig = Rig(ScriptedWorld(planner=ScriptedPlanner(fail_calls=[2],
                                                    reason=PlanReason.GOAL_OCCUPIED)))
    rig.put("goal", Pose2D(2.0, 1.0, 0.0))
    node = rig.node("ComputePathToPose")
    node.tick_once()
    assert node.status == S
    path = rig.get("path")
    assert isinstance(path, Path) and path.pose(len(path) - 1) == Pose2D(2.0, 1.0, 0.0)
    assert rig.get("compute_path_error_code") == 0
    node.tick_once()
    assert node.status == F
    assert rig.get("compute_path_error_code") == PlannerError.GOAL_OCCUPIED
    bad = rig.node("ComputePathToPose", planner_id="Nope")
    bad.tick_once()
    assert bad.status == F and rig.get("compute_path_error_code") == PlannerError.INVALID_PLANNER


class _TextPlanner:
    """A planner from elsewhere: fails with ``reason`` as it gives it (text, not the enum)."""

    def __init__(self, reason, ok=False, path=None):
        self.result = PlanResult(ok, path, reason)

    def make_plan(self, start, goal):
        return self.result


def test_plan_gives_the_plan_reason_enum():
    from behaviors.actions.planning import PlanningAction
    start, goal = Pose2D(), Pose2D(2.0, 0.0, 0.0)
    path, reason = PlanningAction.plan(ScriptedPlanner(), start, goal)
    assert reason is PlanReason.NONE and len(path) > 1
    path, reason = PlanningAction.plan(
        ScriptedPlanner(fail_always=True, reason=PlanReason.START_OCCUPIED), start, goal)
    assert path is None and reason is PlanReason.START_OCCUPIED
    assert PlanningAction.code(reason) is PlannerError.START_OCCUPIED
    # a reason given as its text comes back as the enum member
    path, reason = PlanningAction.plan(_TextPlanner("goal_occupied"), start, goal)
    assert path is None and type(reason) is PlanReason and reason is PlanReason.GOAL_OCCUPIED
    # a failure naming no reason, or an empty path, is NO_PATH
    assert PlanningAction.plan(_TextPlanner(PlanReason.NONE), start, goal) == (
        None, PlanReason.NO_PATH)
    empty = Path(np.zeros((0, 3)))
    assert PlanningAction.plan(_TextPlanner(PlanReason.NONE, True, empty), start, goal)[1] \
        is PlanReason.NO_PATH
    # text that is no PlanReason is the planner's bug, named, not "no path"
    with pytest.raises(ValueError, match=r"_TextPlanner.make_plan: reason 'blocked' is not a "
                                         r"PlanReason"):
        PlanningAction.plan(_TextPlanner("blocked"), start, goal)


def test_scripted_planner_takes_a_failing_plan_reason_only():
    with pytest.raises(TypeError, match="reason must be a PlanReason, got 'goal_occupied'"):
        ScriptedPlanner(reason="goal_occupied")
    with pytest.raises(ValueError, match="got NONE"):
        ScriptedPlanner(reason=PlanReason.NONE)
    failing = ScriptedPlanner(fail_calls=[1], reason=PlanReason.GOAL_OUTSIDE_MAP)
    first = failing.make_plan(Pose2D(), Pose2D(1.0, 0.0, 0.0))
    assert (first.ok, first.path, first.reason) == (False, None, PlanReason.GOAL_OUTSIDE_MAP)
    assert failing.make_plan(Pose2D(), Pose2D(1.0, 0.0, 0.0)).ok


def test_compute_path_through_poses_joins_the_legs():
    rig = Rig()
    rig.put("goals", [Pose2D(1.0, 0.0, 0.0), Pose2D(1.0, 1.0, 0.0)])
    node = rig.node("ComputePathThroughPoses")
    node.tick_once()
    path = rig.get("path")
    assert node.status == S and rig.world.planner.calls == 2
    assert path.length() == pytest.approx(2.0, abs=1e-6)


def test_follow_path_reaches_goal_and_takes_new_paths():
    rig = Rig()
    rig.put("path", straight_path(Pose2D(), Pose2D(2.0, 0.0, 0.0)))
    node = rig.node("FollowPath")
    status, n = rig.run(node)
    assert status == S and rig.world.robot.pose().distance_to(Pose2D(2.0, 0.0, 0.0)) < 0.1
    assert rig.get("follow_path_error_code") == 0
    assert rig.world.controller.plans_set == 1
    assert 70 <= n <= 82                              # 1.9 m at 0.5 m/s, 20 Hz


def test_follow_path_failure_tolerance_and_codes():
    ctl = ScriptedController(fail_calls=range(1, 11))   # 10 bad calls = 0.5 s
    rig = Rig(ScriptedWorld(controller=ctl))
    rig.put("path", straight_path(Pose2D(), Pose2D(1.0, 0.0, 0.0)))
    status, _ = rig.run(rig.node("FollowPath", failure_tolerance=1.0))
    assert status == S                                  # within its patience
    ctl2 = ScriptedController(fail_always=True)
    rig2 = Rig(ScriptedWorld(controller=ctl2))
    rig2.put("path", straight_path(Pose2D(), Pose2D(1.0, 0.0, 0.0)))
    status, n = rig2.run(rig2.node("FollowPath", failure_tolerance=1.0))
    assert status == F and n == 21
    assert rig2.get("follow_path_error_code") == ControllerError.PATIENCE_EXCEEDED
    status, n = rig2.run(rig2.node("FollowPath"))
    assert status == F and n == 1
    assert rig2.get("follow_path_error_code") == ControllerError.NO_VALID_CONTROL
    empty = rig2.node("FollowPath", path="{nothing}")
    empty.tick_once()
    assert empty.status == F and rig2.get("follow_path_error_code") == ControllerError.INVALID_PATH


def test_follow_path_progress_checker():
    class Crawler(ScriptedController):
        def compute_velocity(self, pose, velocity, path=None):
            res = super().compute_velocity(pose, velocity, path)
            return type(res)(Twist(0.01, 0.0, 0.0), res.status)   # 1 cm/s: no progress

    rig = Rig(ScriptedWorld(controller=Crawler()))
    rig.put("path", straight_path(Pose2D(), Pose2D(3.0, 0.0, 0.0)))
    status, n = rig.run(rig.node("FollowPath", required_movement_radius=0.5,
                                 movement_time_allowance=2.0))
    assert status == F and rig.get("follow_path_error_code") == ControllerError.FAILED_TO_MAKE_PROGRESS
    assert 40 <= n <= 45


def test_spin_turns_within_limits_and_stops():
    rig = Rig()
    node = rig.node("Spin", spin_dist=1.57)
    status, n = rig.run(node)
    theta = rig.world.robot.pose().theta
    assert status == S and abs(theta - 1.57) <= 0.1 + 1e-9
    assert rig.get("spin_error_code") == SpinError.NONE
    ws = [abs(t.theta - s.theta) / 0.05 for s, t in zip(rig.world.robot.trajectory,
                                                         rig.world.robot.trajectory[1:])]
    assert max(ws) <= 1.0 + 1e-9                                   # max_rotational_vel
    steps = [b - a for a, b in zip(ws, ws[1:])]
    assert max(steps) <= 3.2 * 0.05 + 1e-9                         # acceleration limit
    assert rig.get("cmd_vel") == Twist.zero()


def test_spin_negative_direction_and_collision_ahead():
    rig = Rig()
    status, _ = rig.run(rig.node("Spin", spin_dist=-1.0))
    assert status == S and rig.world.robot.pose().theta == pytest.approx(-1.0, abs=0.1)

    # lethal once the robot faces beyond +0.5 rad
    blocked = FakeCostmap(footprint=lambda x, y, t: 254 if t > 0.5 else 0)
    rig2 = Rig(ScriptedWorld(local_costmap=blocked))
    status, _ = rig2.run(rig2.node("Spin", spin_dist=1.57))
    assert status == F and rig2.get("spin_error_code") == SpinError.COLLISION_AHEAD
    assert rig2.world.robot.pose().theta < 0.5


def test_spin_times_out():
    class Stuck(ScriptedWorld):
        def step(self, cmd):
            self.clock.advance(self.control_period)          # wheels slip: no motion

    rig = Rig(Stuck())
    status, n = rig.run(rig.node("Spin", spin_dist=1.57, time_allowance=1.0))
    assert status == F and rig.get("spin_error_code") == SpinError.TIMEOUT and n in (21, 22)


def test_backup_drives_backwards_and_stops_at_obstacle():
    rig = Rig()
    status, _ = rig.run(rig.node("BackUp", backup_dist=0.3, backup_speed=0.15))
    p = rig.world.robot.pose()
    assert status == S and p.x == pytest.approx(-0.3, abs=0.01) and abs(p.y) < 1e-9
    wall = FakeCostmap(footprint=lambda x, y, t: 254 if x < -0.2 else 0)
    rig2 = Rig(ScriptedWorld(local_costmap=wall))
    status, _ = rig2.run(rig2.node("BackUp", backup_dist=0.5, backup_speed=0.15))
    assert status == F and rig2.get("backup_error_code") == BackUpError.COLLISION_AHEAD
    assert rig2.world.robot.pose().x > -0.2
    rig3 = Rig(ScriptedWorld(local_costmap=wall))
    status, _ = rig3.run(rig3.node("BackUp", backup_dist=0.5, backup_speed=0.15,
                                   disable_collision_checks=True))
    assert status == S


def test_drive_on_heading_and_invalid_input():
    rig = Rig()
    rig.world.robot.teleport(Pose2D(0.0, 0.0, math.pi / 2))
    status, _ = rig.run(rig.node("DriveOnHeading", dist_to_travel=0.4, speed=0.2))
    assert status == S and rig.world.robot.pose().y == pytest.approx(0.4, abs=0.01)
    status, _ = rig.run(rig.node("DriveOnHeading", dist_to_travel=0.4, speed=-0.2))
    assert status == F and rig.get("drive_on_heading_error_code") == DriveOnHeadingError.INVALID_INPUT


def test_wait_on_sim_clock():
    rig = Rig()
    status, n = rig.run(rig.node("Wait", wait_duration=1.0))
    assert status == S and n == 21


def test_clear_costmap_nodes_call_the_right_maps():
    w = ScriptedWorld()
    rig = Rig(w)
    w.robot.teleport(Pose2D(1.0, 2.0, 0.0))
    for node_type, ports in [("ClearEntireCostmap", {"costmap": "local"}),
                             ("ClearEntireCostmap", {"costmap": "both"}),
                             ("ClearCostmapExceptRegion", {"reset_distance": 3.0}),
                             ("ClearCostmapAroundRobot", {"reset_distance": 0.5})]:
        node = rig.node(node_type, **ports)
        node.tick_once()
        assert node.status == S
    assert w.local_costmap.resets == 2 and w.global_costmap.resets == 1
    assert w.local_costmap.clear_outside_calls == [(1.0, 2.0, 3.0)]
    assert w.global_costmap.clear_outside_calls == [(1.0, 2.0, 3.0)]
    assert w.local_costmap.clear_inside_calls == [(1.0, 2.0, 0.5)]


def _tight_spot(x, y, t):
    """Walls all round within 0.6 m, except an opening toward -y (y < -0.2 corridor)."""
    r = math.hypot(x, y)
    if r < 0.2:
        return 200                                           # where the robot is: inflated
    if abs(x) < 0.25 and y < 0:
        return 50 if r > 0.8 else 150
    return 254 if r < 2.0 else 100


def test_temporary_goal_finds_the_opening_and_drives_there():
    cm = FakeCostmap(footprint=_tight_spot)
    rig = Rig(ScriptedWorld(local_costmap=cm))
    node = rig.node("TemporaryGoal", search_radius=1.5, min_distance=0.4)
    status, _ = rig.run(node)
    goal = rig.get("temporary_goal")
    assert status == S and goal.y < -0.8 and abs(goal.x) < 0.25
    assert rig.world.robot.pose().distance_to(goal) <= 0.15
    assert rig.world.planner.calls >= 1


def test_temporary_goal_fails_without_free_pose():
    cm = FakeCostmap(footprint=lambda x, y, t: 254)
    rig = Rig(ScriptedWorld(local_costmap=cm))
    status, _ = rig.run(rig.node("TemporaryGoal"))
    assert status == F and rig.get("temporary_goal_error_code") == RecoveryError.NO_FREE_POSE
    unreachable = Rig(ScriptedWorld(planner=ScriptedPlanner(fail_always=True)))
    status, n = unreachable.run(unreachable.node("TemporaryGoal", max_plans_per_tick=4,
                                                 arc_first=False))
    assert status == F and unreachable.world.planner.calls == 6 * 16  # every candidate (6 rings 0.4..1.4 m) tried
    # the same world, arcs first: a free pose one clear arc away needs no planner at all
    arcs = Rig(ScriptedWorld(planner=ScriptedPlanner(fail_always=True)))
    node = arcs.node("TemporaryGoal", max_plans_per_tick=4)
    status, n = arcs.run(node)
    goal = arcs.get("temporary_goal")
    assert status == S and arcs.world.planner.calls == 0, node.feedback_message
    assert arcs.world.robot.pose().distance_to(goal) <= 0.15


def test_back_off_to_previous_pose_follows_the_trail_in_reverse():
    rig = Rig()
    recorder = rig.node("RecordPoseHistory", spacing=0.04)
    # drive an L: 1 m along x, then 0.5 m along y
    robot = rig.world.robot
    for i in range(21):
        robot.teleport(Pose2D(0.05 * i, 0.0, 0.0))
        recorder.tick_once()
    for i in range(1, 11):
        robot.teleport(Pose2D(1.0, 0.05 * i, math.pi / 2))
        recorder.tick_once()
    assert len(rig.get("pose_history")) == 31
    node = rig.node("BackOffToPreviousPose", distance=0.75, speed=0.1)
    status, _ = rig.run(node)
    p = robot.pose()
    assert status == S
    assert p.distance_to(Pose2D(0.75, 0.0, 0.0)) <= 0.08 + 1e-9   # 0.5 m back up y, 0.25 along x
    assert all(-0.05 <= q.x <= 1.05 and -0.05 <= q.y <= 0.55 for q in robot.trajectory)
    assert math.cos(p.theta) > 0.5      # reversed round the corner: faces +x, as it came in


def test_back_off_without_history_fails():
    rig = Rig()
    status, _ = rig.run(rig.node("BackOffToPreviousPose"))
    assert status == F and rig.get("back_off_error_code") == RecoveryError.NO_POSE_HISTORY


def test_navigate_to_pose_subtree():
    rig = Rig()
    rig.put("goal", Pose2D(1.5, -1.0, 0.0))
    status, _ = rig.run(rig.node("NavigateToPose", replan_hz=1.0))
    assert status == S
    assert rig.world.robot.pose().distance_to(Pose2D(1.5, -1.0, 0.0)) <= 0.1
    assert rig.world.planner.calls >= 2                            # replanned while driving


def test_reinitialize_global_localization():
    class Loc:
        calls = 0

        def global_localization(self):
            Loc.calls += 1

    w = ScriptedWorld()
    rig = Rig(w)
    node = rig.node("ReinitializeGlobalLocalization")
    node.tick_once()
    assert node.status == F                           # no localiser in this world
    node.localizer = Loc()
    node.tick_once()
    assert node.status == S and Loc.calls == 1


def test_temporary_goal_and_back_off_give_up_without_progress():
    class Stuck(ScriptedWorld):
        def step(self, cmd):
            self.clock.advance(self.control_period)          # held in place (contact, stall)

    rig = Rig(Stuck())
    status, n = rig.run(rig.node("TemporaryGoal", movement_time_allowance=2.0))
    assert status == F and rig.get("temporary_goal_error_code") == RecoveryError.TIMEOUT
    assert 40 <= n <= 43
    rig.put("pose_history", [Pose2D(-1.0, 0.0, 0.0), Pose2D(-0.5, 0.0, 0.0), Pose2D()])
    status, n = rig.run(rig.node("BackOffToPreviousPose", movement_time_allowance=2.0))
    assert status == F and rig.get("back_off_error_code") == RecoveryError.TIMEOUT
    assert 40 <= n <= 43


def test_motion_refuses_to_enter_inscribed_cost_but_may_leave_it():
    # inscribed band for x < -0.2: backing into it from free space is refused
    band = FakeCostmap(footprint=lambda x, y, t: 253 if x < -0.2 else 0)
    rig = Rig(ScriptedWorld(local_costmap=band))
    status, _ = rig.run(rig.node("BackUp", backup_dist=0.5, backup_speed=0.15))
    assert status == F and rig.get("backup_error_code") == BackUpError.COLLISION_AHEAD
    # already in inscribed cost (next to a wall): backing out through it is allowed
    tight = FakeCostmap(footprint=lambda x, y, t: 253 if x > -0.3 else 0)
    rig2 = Rig(ScriptedWorld(local_costmap=tight))
    status, _ = rig2.run(rig2.node("BackUp", backup_dist=0.5, backup_speed=0.15))
    assert status == S and rig2.world.robot.pose().x == pytest.approx(-0.5, abs=0.01)


def test_temporary_goal_prefers_gentle_arcs_and_drives_itself_when_the_controller_refuses():
    # A wall along y = -0.3 (the robot's right side); the controller refuses to move at all.
    wall = FakeCostmap(footprint=lambda x, y, t: 254 if y < -0.3 else (253 if y < -0.1 else 0))
    w = ScriptedWorld(local_costmap=wall, controller=ScriptedController(fail_always=True))
    rig = Rig(w)
    node = rig.node("TemporaryGoal", search_radius=1.0, min_distance=0.6)
    status, _ = rig.run(node)
    goal = rig.get("temporary_goal")
    assert status == S, node.feedback_message
    assert abs(goal.y) < 0.3 and abs(goal.x) >= 0.55          # ahead or behind, not abeam
    assert w.robot.pose().distance_to(goal) <= 0.15
    assert all(q.y >= -0.1 - 1e-9 for q in w.robot.trajectory)   # never into the wall's band
    refuse = Rig(ScriptedWorld(controller=ScriptedController(fail_always=True)))
    status, _ = refuse.run(refuse.node("TemporaryGoal", escape_speed=0.0))
    assert status == F and refuse.get("temporary_goal_error_code") == RecoveryError.COLLISION_AHEAD


def test_planner_and_controller_selectors():
    rig = Rig()
    sel = rig.node("ControllerSelector", default_controller="FollowPath")
    sel.tick_once()
    assert sel.status == S and rig.get("selected_controller") == "FollowPath"
    rig.put("controller_selection", "Precise")
    sel.tick_once()
    assert rig.get("selected_controller") == "Precise"
    ps = rig.node("PlannerSelector")
    ps.tick_once()
    assert rig.get("selected_planner") == "GridBased"


class _WallCostmap(FakeCostmap):
    """A FakeCostmap with a real grid: lethal cells below y = ``face`` (a wall along x), the
    robot's padded footprint polygon, and an inscribed band (the footprint within 0.25 m of the
    wall), as the executive's layered costmaps give."""

    def __init__(self, face, padding=0.03):
        from navcore.costmap.footprint import footprint_cost, make_footprint
        super().__init__(size_m=6.0, resolution=0.05, origin=-3.0)
        costs = self.costmap.costs
        ys = -3.0 + (np.arange(costs.shape[0]) + 0.5) * 0.05
        costs[ys < face, :] = 254
        self.params = type("P", (), {"footprint_padding": padding})()
        self.footprint = make_footprint([[0.25, 0.22], [0.25, -0.22], [-0.25, -0.22],
                                         [-0.25, 0.22]], footprint_padding=padding)
        self._face = face
        self._cost = footprint_cost

    def footprint_cost(self, x, y, theta):
        cm = self.costmap
        c = int(self._cost(cm.costs, cm.origin_x, cm.origin_y, cm.resolution, self.footprint,
                           x, y, theta))
        lowest = y - 0.25 * abs(math.cos(theta)) - 0.28 * abs(math.sin(theta))
        return c if c == 254 else (253 if lowest < self._face + 0.25 else c)


def test_tight_spot_motion_is_judged_by_the_body_not_the_grid():
    # a wall 2 cm from the robot's right side (its face at y = -0.25, the body's at -0.23):
    # the padded footprint reaches into the wall's cells, so on the grid every pose collides
    cm = _WallCostmap(face=-0.25)
    rig = Rig(ScriptedWorld(local_costmap=cm))
    rig.world.robot.teleport(Pose2D(0.0, -0.01, 0.0))
    assert cm.footprint_cost(0.0, -0.01, 0.0) == 254
    status, _ = rig.run(rig.node("BackUp", backup_dist=0.5, backup_speed=0.15))
    assert status == S and rig.world.robot.pose().x == pytest.approx(-0.5, abs=0.01)
    # turning in place sweeps a corner through the wall: still refused
    status, _ = rig.run(rig.node("Spin", spin_dist=1.0))
    assert status == F and rig.get("spin_error_code") == SpinError.COLLISION_AHEAD
    # a temporary goal: away from the wall on a gentle arc, the body never into the wall
    w = ScriptedWorld(local_costmap=cm, controller=ScriptedController(fail_always=True))
    w.robot.teleport(Pose2D(0.0, -0.01, 0.0))
    rig2 = Rig(w)
    node = rig2.node("TemporaryGoal", search_radius=1.5, min_distance=0.6)
    status, _ = rig2.run(node)
    goal = rig2.get("temporary_goal")
    assert status == S, node.feedback_message
    assert goal.y > 0.2 and w.planner.calls == 0
    lowest = [q.y - 0.22 * math.cos(q.theta) - 0.25 * abs(math.sin(q.theta))
              for q in w.robot.trajectory]                 # the body's corner nearest the wall
    assert min(lowest) >= -0.25 - 0.003


def test_back_off_goes_on_to_the_first_free_pose_of_the_trail():
    # the last 0.55 m of the trail is in inscribed cost (a dead end): backing off 0.3 m would
    # stop half-way out, so the target moves back to the first free pose (x = 0.45)
    bay = FakeCostmap(footprint=lambda x, y, t: 253 if x > 0.45 + 1e-9 else 0)
    rig = Rig(ScriptedWorld(local_costmap=bay))
    rig.put("pose_history", [Pose2D(0.05 * i, 0.0, 0.0) for i in range(21)])
    rig.world.robot.teleport(Pose2D(1.0, 0.0, 0.0))
    status, _ = rig.run(rig.node("BackOffToPreviousPose", distance=0.3, speed=0.15))
    assert status == S and rig.world.robot.pose().x == pytest.approx(0.45, abs=0.08)
    assert rig.world.robot.pose().x < 0.53
    # no further than max_distance, even if still in inscribed cost there
    rig2 = Rig(ScriptedWorld(local_costmap=bay))
    rig2.put("pose_history", [Pose2D(0.05 * i, 0.0, 0.0) for i in range(21)])
    rig2.world.robot.teleport(Pose2D(1.0, 0.0, 0.0))
    status, _ = rig2.run(rig2.node("BackOffToPreviousPose", distance=0.3, max_distance=0.4,
                                   speed=0.15))
    assert status == S and rig2.world.robot.pose().x == pytest.approx(0.6, abs=0.08)
