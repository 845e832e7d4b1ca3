"""Decorators tick by tick on a SimClock with scripted children."""

from __future__ import annotations

import itertools

from py_trees.common import Status

from behaviors.base import make
from behaviors.testing import FakeRobot
from navcore.clock import SimClock
from navcore.params import Param, Parameters
from navcore.types import Pose2D, Twist
from tests.test_behaviors_controls import Counter

S, F, R, I = Status.SUCCESS, Status.FAILURE, Status.RUNNING, Status.INVALID
_ns = itertools.count()


def build(node_type, child, clock=None, robot=None, **ports):
    node = make(node_type, namespace=f"/dec{next(_ns)}", child=child, **ports)
    node.setup(clock=clock or SimClock(), robot=robot or FakeRobot())
    return node


def run(node, n, clock=None, dt=0.0):
    out = []
    for _ in range(n):
        node.tick_once()
        out.append(node.status)
        if clock is not None:
            clock.advance(dt)
    return out


def test_inverter_force_success_force_failure():
    assert run(build("Inverter", Counter("c", [S, F, R], R)), 3) == [F, S, R]
    assert run(build("ForceSuccess", Counter("c", [F, R, S], S)), 3) == [S, R, S]
    assert run(build("ForceFailure", Counter("c", [S, R, F], F)), 3) == [F, R, F]


def test_retry_until_successful_retries_next_tick_up_to_the_limit():
    child = Counter("c", [F, F, F, S], S)
    node = build("RetryUntilSuccessful", child, num_attempts=3)
    assert run(node, 3) == [R, R, F]
    child = Counter("c", [F, S], S)
    node = build("RetryUntilSuccessful", child, num_attempts=-1)
    assert run(node, 2) == [R, S]


def test_repeat_counts_successes_and_stops_on_failure():
    node = build("Repeat", Counter("c", [S, S, S], S), num_cycles=3)
    assert run(node, 3) == [R, R, S]
    node = build("Repeat", Counter("c", [S, F], F), num_cycles=5)
    assert run(node, 2) == [R, F]


def test_timeout_fails_and_halts_child_on_the_injected_clock():
    clock = SimClock()
    child = Counter("c", [R] * 10, R)
    node = build("Timeout", child, clock=clock, msec=200)
    assert run(node, 5, clock, 0.05) == [R, R, R, R, F]
    assert child.halted == 1
    assert node.feedback_message == "timed out"


def test_delay_waits_then_runs_child():
    clock = SimClock()
    child = Counter("c", [S], S)
    node = build("Delay", child, clock=clock, delay_msec=100)
    assert run(node, 3, clock, 0.05) == [R, R, S]
    assert child.ticked == 1


def test_rate_controller_throttles_on_sim_time():
    clock = SimClock()
    child = Counter("plan", [S] * 100, S)
    node = build("RateController", child, clock=clock, hz=2.0)
    statuses = run(node, 21, clock, 0.05)       # 1.0 s of ticks at 20 Hz
    # the child's status when ticked, RUNNING while throttled (Nav2 RateController, issue 19)
    assert statuses == ([S] + [R] * 9) * 2 + [S]
    assert child.ticked == 3                     # t = 0, 0.5, 1.0


def test_rate_controller_zero_hz_ticks_once_per_run_and_passes_running():
    clock = SimClock()
    child = Counter("plan", [R, S] + [S] * 10, S)
    node = build("RateController", child, clock=clock, hz=0.0)
    assert run(node, 5, clock, 1.0) == [R, S, R, R, R]
    assert child.ticked == 2
    node.stop(I)                                  # a new run ticks the child again
    run(node, 1)
    assert child.ticked == 3


def test_distance_controller_ticks_after_travel():
    robot = FakeRobot()
    child = Counter("plan", [S] * 10, S)
    node = build("DistanceController", child, robot=robot, distance=1.0)
    node.tick_once()
    for x in (0.3, 0.6, 0.9):
        robot.teleport(Pose2D(x, 0.0, 0.0))
        node.tick_once()
    assert child.ticked == 1
    robot.teleport(Pose2D(1.05, 0.0, 0.0))
    node.tick_once()
    assert child.ticked == 2 and node.status == S


def test_speed_controller_rate_follows_speed():
    clock, robot = SimClock(), FakeRobot()
    child = Counter("plan", [S] * 100, S)
    node = build("SpeedController", child, clock=clock, robot=robot,
                 min_rate=0.5, max_rate=2.0, min_speed=0.0, max_speed=0.5)
    assert abs(node.rate(0.0) - 0.5) < 1e-9 and abs(node.rate(0.25) - 1.25) < 1e-9
    robot.apply(Twist(0.5, 0.0, 0.0), 0.0)        # full speed: 2 Hz
    run(node, 21, clock, 0.05)
    assert child.ticked == 3


def test_single_trigger_fires_once_per_activation():
    child = Counter("spin", [R, S, S], S)
    node = build("SingleTrigger", child)
    assert run(node, 4) == [R, S, F, F]
    assert child.ticked == 2
    node.stop(I)
    assert run(node, 1) == [S]


def test_goal_updater_forwards_a_newer_goal():
    child = Counter("c", [S, S], S)
    node = make("GoalUpdater", namespace="/gu", child=child)
    node.setup(clock=SimClock(), robot=FakeRobot())
    from py_trees.blackboard import Client
    from py_trees.common import Access
    bb = Client(name="t", namespace="/gu")
    for k in ("goal", "goal_update"):
        bb.register_key(k, access=Access.WRITE)
    bb.goal = Pose2D(1.0, 0.0, 0.0)
    node.tick_once()
    assert bb.goal == Pose2D(1.0, 0.0, 0.0)
    bb.goal_update = Pose2D(2.0, 2.0, 0.0)
    node.tick_once()
    assert bb.goal == Pose2D(2.0, 2.0, 0.0) and node.status == S


def _params():
    return {"DWAPlannerROS": Parameters((Param("path_distance_bias", 32.0, float, min=0.0),),
                                        where="DWAPlannerROS")}


def test_set_parameters_sets_while_child_runs_and_restores():
    params = _params()
    seen = []

    class Probe(Counter):
        def update(self):
            seen.append(params["DWAPlannerROS"].path_distance_bias)
            return super().update()

    child = Probe("follow", [R, R, S], S)
    node = make("SetParameters", namespace="/sp", child=child)
    node.wire("/sp", {}, {"namespace": "DWAPlannerROS", "values": {"path_distance_bias": 8.0}})
    node.setup(parameters=params)
    assert run(node, 3) == [R, R, S]
    assert seen == [8.0, 8.0, 8.0]
    assert params["DWAPlannerROS"].path_distance_bias == 32.0


def test_set_parameters_restores_when_halted_and_rejects_bad_values():
    params = _params()
    node = make("SetParameters", namespace="/sp2", child=Counter("c", [R] * 5, R))
    node.wire("/sp2", {}, {"namespace": "DWAPlannerROS", "values": {"path_distance_bias": 4.0}})
    node.setup(parameters=params)
    node.tick_once()
    assert params["DWAPlannerROS"].path_distance_bias == 4.0
    node.stop(I)
    assert params["DWAPlannerROS"].path_distance_bias == 32.0
    bad = make("SetParameters", namespace="/sp3", child=Counter("c", [S], S))
    bad.wire("/sp3", {}, {"namespace": "DWAPlannerROS", "values": {"path_distanse_bias": 1.0}})
    bad.setup(parameters=params)
    bad.tick_once()
    assert bad.status == F
    assert "did you mean 'path_distance_bias'" in bad.feedback_message
    unknown = make("SetParameters", namespace="/sp4", child=Counter("c", [S], S))
    unknown.wire("/sp4", {}, {"namespace": "TrajectoryPlannerROS", "values": {"a": 1.0}})
    unknown.setup(parameters=params)
    unknown.tick_once()
    assert unknown.status == F and "no parameter namespace" in unknown.feedback_message


def test_goal_updated_controller_replans_only_for_a_new_goal():
    from py_trees.blackboard import Client
    from py_trees.common import Access
    child = Counter("plan", [R, S] + [S] * 10, S)
    node = make("GoalUpdatedController", namespace="/guc", child=child)
    node.setup(clock=SimClock(), robot=FakeRobot())
    bb = Client(name="t", namespace="/guc")
    bb.register_key("goal", access=Access.WRITE)
    bb.goal = Pose2D(1.0, 0.0, 0.0)
    # RUNNING while it waits for a new goal, as Nav2's (issue 19)
    assert run(node, 4) == [R, S, R, R]
    assert child.ticked == 2                         # running, then done: not ticked again
    bb.goal = Pose2D(2.0, 0.0, 0.0)
    assert run(node, 2) == [S, R] and child.ticked == 3


def test_set_parameters_not_required_runs_the_child_unchanged():
    params = _params()
    child = Counter("c", [S], S)
    node = make("SetParameters", namespace="/sp5", child=child)
    node.wire("/sp5", {}, {"namespace": "TrajectoryPlannerROS", "values": {"a": 1.0},
                           "required": False})
    node.setup(parameters=params)
    node.tick_once()
    assert node.status == S and child.ticked == 1
    assert "no parameter namespace 'TrajectoryPlannerROS'" in node.feedback_message


def test_keep_running_until_failure_and_always_nodes():
    node = build("KeepRunningUntilFailure", Counter("c", [S, S, F], F))
    assert run(node, 3) == [R, R, F]
    ok = make("AlwaysSuccess", namespace="/al")
    no = make("AlwaysFailure", namespace="/al")
    ok.tick_once()
    no.tick_once()
    assert (ok.status, no.status) == (S, F)
