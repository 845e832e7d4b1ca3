"""Whole-tree tests of the shipped trees against scripted components (Nav2 system-test style).

Each shipped tree runs on a kinematic FakeRobot with a ScriptedPlanner / ScriptedController that
fail when told to; the tests assert the final status and how often the planner, the controller,
the costmap clearings and each recovery ran.
"""

from __future__ import annotations

import itertools
from collections import Counter as Tally

import pytest
from py_trees.common import Status
from py_trees.visitors import VisitorBase

from behaviors.testing import (FakeCostmap, ScriptedController, ScriptedPlanner, ScriptedWorld,
                               run_tree)
from executive.tree_loader import SHIPPED_TREES, load_tree_file, shipped_tree
from navcore.planners.result import PlanReason
from navcore.types import Pose2D

S, F, R = Status.SUCCESS, Status.FAILURE, Status.RUNNING
GOAL = Pose2D(3.0, 1.0, 0.0)
_ns = itertools.count()


class Runs(VisitorBase):
    """Counts finished runs (SUCCESS or FAILURE) per node type."""

    def __init__(self) -> None:
        super().__init__(full=False)
        self.done: Tally = Tally()
        self.running: Tally = Tally()

    def run(self, behaviour) -> None:
        kind = type(behaviour).__name__
        if behaviour.status in (S, F):
            self.done[kind] += 1
        elif behaviour.status == R:
            self.running[kind] += 1


def start(name: str, world: ScriptedWorld, goal: Pose2D = GOAL):
    tree = load_tree_file(shipped_tree(name), namespace=f"/sys{next(_ns)}")
    runs = Runs()
    tree.tree.add_visitor(runs)
    tree.setup(**world.components())
    tree.set("goal", goal)
    return tree, runs


def clears(cm: FakeCostmap) -> int:
    return cm.clearings


@pytest.mark.parametrize("name", SHIPPED_TREES)
def test_all_succeed(name):
    w = ScriptedWorld()
    tree, runs = start(name, w)
    status, ticks = run_tree(tree, w)
    assert status == S
    assert w.robot.pose().distance_to(GOAL) <= 0.1
    assert clears(w.local_costmap) == clears(w.global_costmap) == 0
    assert runs.done["Spin"] == runs.done["BackUp"] == runs.done["Wait"] == 0
    replans = 1 if name == "move_base" else 1 + int(ticks * w.control_period)  # 1 Hz
    assert w.planner.calls == replans
    assert w.controller.calls == ticks


def test_move_base_everything_fails():
    w = ScriptedWorld(planner=ScriptedPlanner(fail_always=True))
    tree, runs = start("move_base", w)
    status, ticks = run_tree(tree, w, max_ticks=20000)
    assert status == F
    # conservative_reset, rotate, aggressive_reset, rotate; then abort
    assert w.local_costmap.clear_outside_calls[0][2] == 3.0
    assert [c[2] for c in w.global_costmap.clear_outside_calls] == [3.0, 1.84]
    assert len(w.local_costmap.clear_outside_calls) == 2
    assert runs.done["Spin"] == 2
    # five planning attempts of planner_patience 5 s each, one planner call per 50 ms tick
    assert abs(w.planner.calls - 5 * 100) <= 5
    assert w.controller.calls == 0


def test_nav2_everything_fails():
    w = ScriptedWorld(planner=ScriptedPlanner(fail_always=True))
    tree, runs = start("nav2", w)
    status, _ = run_tree(tree, w)
    assert status == F
    assert w.planner.calls == 7 * 2          # 1 + 6 retries, each with one context retry
    # context: clear global 7x; global recoveries in order clear-both, spin, wait, backup,
    # clear-both, spin (RoundRobin wraps)
    assert w.global_costmap.resets == 7 + 2 and w.local_costmap.resets == 2
    assert (runs.done["Spin"], runs.done["Wait"], runs.done["BackUp"]) == (2, 1, 1)


def test_smach_everything_fails():
    w = ScriptedWorld(planner=ScriptedPlanner(fail_always=True))
    tree, runs = start("smach_recovery", w)
    status, _ = run_tree(tree, w)
    assert status == F
    # 11 navigation attempts (2 planner calls each); 10 recoveries: clear-local, spin, temporary
    # goal, back off, the temporary goal through unseen space (EscapeThroughUnseen),
    # clear-all+wait, then clear-local, spin, temporary goal, back off (the goal-weighted follow
    # has no path to follow and hands over to spin in the same tick). In this open world the
    # temporary goal is one clear arc away (no planner call) and the back-off retraces that arc.
    assert runs.done["SetParameters"] == runs.done["FollowPath"] == 2   # only in the recovery
    assert runs.done["TemporaryGoal"] == 3 and runs.done["BackOffToPreviousPose"] == 2
    assert w.planner.calls == 11 * 2
    assert runs.done["Spin"] == 2 and runs.done["Wait"] == 1
    assert w.global_costmap.resets == 11 + 1          # context clears + clear-all
    assert len(w.local_costmap.clear_outside_calls) == 2


def test_near_goal_everything_fails():
    w = ScriptedWorld(planner=ScriptedPlanner(fail_always=True))
    tree, runs = start("near_goal_reconfigure", w)
    status, _ = run_tree(tree, w)
    assert status == F
    assert w.planner.calls == 5
    assert (runs.done["Spin"], runs.done["BackUp"]) == (1, 1)
    assert w.local_costmap.resets == w.global_costmap.resets == 2


@pytest.mark.parametrize("name,global_resets,local_resets,planner_min", [
    ("move_base", 0, 0, 2),               # RetryUntilSuccessful: next tick, no recovery
    ("nav2", 1, 0, 2),                    # context recovery: clear the global costmap
    ("smach_recovery", 1, 0, 2),
    ("near_goal_reconfigure", 1, 1, 2),   # no context recovery: first global one (clear both)
])
def test_planning_fails_once(name, global_resets, local_resets, planner_min):
    w = ScriptedWorld(planner=ScriptedPlanner(fail_calls=[1]))
    tree, runs = start(name, w)
    status, _ = run_tree(tree, w)
    assert status == S and w.robot.pose().distance_to(GOAL) <= 0.1
    assert w.global_costmap.resets == global_resets and w.local_costmap.resets == local_resets
    assert w.planner.calls >= planner_min
    assert runs.done["Spin"] == 0


@pytest.mark.parametrize("name", SHIPPED_TREES)
def test_goal_changes_while_a_recovery_runs(name):
    """Planning fails until a Spin is under way; then a new goal arrives and planning works."""
    state = {"blocked": True, "switched_at": None}
    planner = ScriptedPlanner(fail_calls=lambda i: state["blocked"])
    w = ScriptedWorld(planner=planner)
    tree, runs = start(name, w)
    new_goal = Pose2D(-1.0, 2.0, 0.0)

    def on_tick(i, world):
        if state["switched_at"] is None and runs.running["Spin"] >= 3:
            tree.set("goal", new_goal)
            state["blocked"] = False
            state["switched_at"] = i

    status, _ = run_tree(tree, w, max_ticks=20000, on_tick=on_tick)
    assert state["switched_at"] is not None
    assert status == S
    assert w.robot.pose().distance_to(new_goal) <= 0.1
    assert runs.done["Spin"] == 0                      # the spin was preempted, never finished
    assert planner.goals[-1] == new_goal


def test_nav2_picks_recoveries_by_error_code():
    # goal occupied: no recovery can help, so nav2 gives up after one planning attempt
    w = ScriptedWorld(planner=ScriptedPlanner(fail_always=True, reason=PlanReason.GOAL_OCCUPIED))
    tree, runs = start("nav2", w)
    status, _ = run_tree(tree, w)
    assert status == F and w.planner.calls == 1
    assert w.global_costmap.resets == w.local_costmap.resets == 0
    # controller failures: the local costmap is cleared in context, then global recoveries
    w = ScriptedWorld(controller=ScriptedController(fail_always=True))
    tree, runs = start("nav2", w)
    status, _ = run_tree(tree, w)
    assert status == F
    assert w.controller.calls == 7 * 2
    assert w.local_costmap.resets == 7 + 2 and w.global_costmap.resets == 2


def _boxed_in_world() -> ScriptedWorld:
    """No valid command toward the goal while the robot is within 0.35 m of where it started;
    any other plan (a way out) can be followed. Clearing and turning on the spot do not help."""
    w = ScriptedWorld()

    class Boxed(ScriptedController):
        def compute_velocity(self, pose, velocity, path=None):
            res = super().compute_velocity(pose, velocity, path)
            aims_at_goal = self.plan is not None and self.plan.pose(len(self.plan) - 1) == GOAL
            if aims_at_goal and pose.distance_to(Pose2D()) < 0.35:
                return type(res)(res.cmd.__class__.zero(), "no_valid_trajectory")
            return res

    w.controller = Boxed(parameters=w.parameters["DWAPlannerROS"])
    return w


def test_smach_recovers_where_move_base_gives_up():
    w = _boxed_in_world()
    tree, runs = start("move_base", w)
    status, _ = run_tree(tree, w, max_ticks=20000)
    assert status == F and runs.done["Spin"] == 2          # every move_base recovery ran
    w = _boxed_in_world()
    tree, runs = start("smach_recovery", w)
    status, _ = run_tree(tree, w, max_ticks=20000)
    assert status == S and w.robot.pose().distance_to(GOAL) <= 0.1
    assert runs.done["TemporaryGoal"] == 1


def test_near_goal_reconfigure_lowers_the_bias_only_near_the_goal():
    w = ScriptedWorld()
    tree, _ = start("near_goal_reconfigure", w)
    status, _ = run_tree(tree, w)
    assert status == S
    log = w.controller.bias_log
    assert log[0] == 32.0 and log[-1] == 8.0
    first_near = log.index(8.0)
    assert set(log[first_near:]) == {8.0}                   # stays lowered once near
    assert w.parameters["DWAPlannerROS"].path_distance_bias == 32.0   # restored at the end


@pytest.mark.parametrize("name", SHIPPED_TREES)
def test_goal_changes_while_driving(name):
    """A new goal during FollowPath: every tree replans (move_base at once, the others at their
    replanning rate) and reaches the new goal without any recovery."""
    w = ScriptedWorld()
    tree, runs = start(name, w)
    new_goal = Pose2D(0.5, -2.0, 0.0)

    def on_tick(i, world):
        if i == 40:
            tree.set("goal", new_goal)

    status, ticks = run_tree(tree, w, on_tick=on_tick)
    assert status == S and w.robot.pose().distance_to(new_goal) <= 0.1
    assert w.planner.goals[-1] == new_goal
    assert clears(w.local_costmap) == clears(w.global_costmap) == 0
    if name == "move_base":
        assert w.planner.calls == 2                  # once per goal (planner_frequency 0)


def test_interrupt_for_a_new_goal_restarts_the_recovery_list():
    w = ScriptedWorld(planner=ScriptedPlanner(fail_calls=[1, 2, 3]))
    tree, runs = start("nav2", w)
    status, _ = run_tree(tree, w)
    assert status == S and w.local_costmap.resets == 1   # one global recovery: clearing
    rr = next(n for n in tree.nodes() if n.name == "RecoveryActions")
    assert rr._index == 1                                  # next time: Spin
    tree.restart()
    assert rr._index == 0 and tree.status == Status.INVALID
    w.planner.fail_calls = {w.planner.calls + 1, w.planner.calls + 2}
    tree.set("goal", Pose2D(0.0, 0.0, 0.0))
    status, _ = run_tree(tree, w)
    assert status == S and w.local_costmap.resets == 2 and runs.done["Spin"] == 0


def test_move_base_restarts_its_recovery_list_after_navigating_again():
    """Control fails for 16 s (past controller_patience), works for 25 s, fails again: like
    move_base, the second episode starts with the conservative reset again, not rotate."""
    w = ScriptedWorld()
    t = w.clock.now
    w.controller = ScriptedController(fail_calls=lambda i: t() < 16.0 or 41.0 <= t() < 57.0,
                                      parameters=w.parameters["DWAPlannerROS"])
    far = Pose2D(40.0, 0.0, 0.0)
    tree, runs = start("move_base", w, goal=far)
    status, _ = run_tree(tree, w, max_ticks=1400)             # 70 s
    assert [c[2] for c in w.global_costmap.clear_outside_calls] == [3.0, 3.0]
    assert runs.done["Spin"] == 0


def test_fixed_path_and_command_doubles_keep_navigating_and_still_fail_on_cue():
    # the benchmark doubles: one path whatever the goal, one command whatever the plan, never
    # at the goal; the scripted failures still apply
    from behaviors.testing import straight_path
    from navcore.controllers.result import ControlStatus
    from navcore.types import Twist
    path = straight_path(Pose2D(), Pose2D(5.0, 0.0))
    planner = ScriptedPlanner(fixed_path=path, fail_calls=[2])
    first = planner.make_plan(Pose2D(1.0, 1.0), GOAL)
    assert first.ok and first.path is path
    assert not planner.make_plan(Pose2D(), GOAL).ok
    assert planner.make_plan(Pose2D(2.0, 0.0), Pose2D(-3.0, 0.0)).path is path
    controller = ScriptedController(fixed_command=Twist(0.2, 0.0, 0.0), fail_calls=[3])
    answers = [controller.compute_velocity(Pose2D(x, 0.0), Twist()) for x in (0.0, 5.0, 5.0)]
    assert [a.status for a in answers] == [ControlStatus.FOLLOWING, ControlStatus.FOLLOWING,
                                           ControlStatus.NO_VALID_TRAJECTORY]
    assert answers[0].cmd == Twist(0.2, 0.0, 0.0) and answers[2].cmd.is_zero()
    assert not controller.is_goal_reached()
