"""Condition nodes against a FakeRobot and a SimClock."""

from __future__ import annotations


import numpy as np
from py_trees.common import Status

from navcore.error_codes import ControllerError, PlannerError
from behaviors.testing import FakeCostmap, FakeRobot, NodeRig, straight_path
from hw.interfaces import BatteryState
from navcore.clock import SimClock
from navcore.types import Pose2D

S, F, I = Status.SUCCESS, Status.FAILURE, Status.INVALID


class Env(NodeRig):
    """A node on a fake robot and a sim clock, plus the components given."""

    def __init__(self, **components):
        self.clock, self.robot = SimClock(), FakeRobot()
        super().__init__({"clock": self.clock, "robot": self.robot, "control_period": 0.05,
                          **components})


tick = NodeRig.tick


def test_goal_reached():
    env = Env()
    node = env.node("GoalReached", goal_reached_tol=0.2)
    assert tick(node) == F                              # no goal yet
    env.put("goal", Pose2D(1.0, 0.0, 0.0))
    assert tick(node) == F
    env.robot.teleport(Pose2D(0.85, 0.05, 0.0))
    assert tick(node) == S


def test_goal_updated_fires_once_per_change():
    env = Env()
    env.put("goal", Pose2D(1.0, 0.0, 0.0))
    node = env.node("GoalUpdated")
    assert [tick(node) for _ in range(2)] == [F, F]
    env.put("goal", Pose2D(2.0, 0.0, 0.0))
    assert [tick(node) for _ in range(2)] == [S, F]


def test_is_path_valid_against_global_costmap():
    cm = FakeCostmap()
    env = Env(global_costmap=cm)
    env.put("path", straight_path(Pose2D(0, 0, 0), Pose2D(2, 0, 0)))
    node = env.node("IsPathValid")
    assert tick(node) == S
    mx, my = cm.costmap.world_to_map(1.0, 0.0)
    cm.costmap.costs[my, mx] = 254
    assert tick(node) == F and "blocked" in node.feedback_message


def test_is_stuck_needs_progress_within_allowance():
    env = Env()
    node = env.node("IsStuck", required_movement_radius=0.5, movement_time_allowance=2.0)
    results = []
    for i in range(60):            # creep at 0.1 m/s: 0.2 m per 2 s is not enough
        env.robot.teleport(Pose2D(0.005 * i, 0.0, 0.0))
        results.append(tick(node))
        env.clock.advance(0.05)
    assert results[:40].count(S) == 0 and results[-1] == S
    env2 = Env()
    node2 = env2.node("IsStuck", required_movement_radius=0.5, movement_time_allowance=2.0)
    for i in range(100):           # 0.5 m/s: never stuck
        env2.robot.teleport(Pose2D(0.025 * i, 0.0, 0.0))
        assert tick(node2) == F
        env2.clock.advance(0.05)


def test_is_oscillating_disabled_by_default_and_resets_after_a_gap():
    env = Env()
    env.put("goal", Pose2D(5.0, 0.0, 0.0))
    off = env.node("IsOscillating")
    for _ in range(100):
        assert tick(off) == F
        env.clock.advance(0.05)
    on = env.node("IsOscillating", oscillation_timeout=1.0, oscillation_distance=0.5)
    statuses = []
    for _ in range(30):
        statuses.append(tick(on))
        env.clock.advance(0.05)
    first = statuses.index(S)      # 1 s of ticks (one more or less as the float clock rounds)
    assert statuses[0] == F and 19 <= first <= 21 and statuses.count(S) == 1
    assert statuses[first + 1] == F  # reported once: the timer restarts (as after a recovery)
    for _ in range(20):
        statuses.append(tick(on))
        env.clock.advance(0.05)
    second = statuses.index(S, first + 1)                  # a second full timeout later
    assert 19 <= second - first - 1 <= 21 and statuses.count(S) == 2
    env.clock.advance(5.0)         # not ticked for a while (a recovery ran): timer restarts
    assert tick(on) == F


def test_is_localized_uses_covariance():
    class Loc:
        cov = np.diag([0.01, 0.01, 0.01])

        def covariance(self):
            return self.cov

    loc = Loc()
    env = Env(localizer=loc)
    node = env.node("IsLocalized", max_xy_std=0.2, max_yaw_std=0.2)
    assert tick(node) == S
    loc.cov = np.diag([0.25, 0.01, 0.01])
    assert tick(node) == F
    assert tick(Env().node("IsLocalized")) == S      # ground truth


def test_is_battery_low():
    env = Env()
    node = env.node("IsBatteryLow", min_battery=0.3)
    assert tick(node) == F                           # unknown battery
    env.robot._battery = BatteryState(12.0, 0.25)
    assert tick(node) == S
    env.robot._battery = BatteryState(12.0, 0.8)
    assert tick(node) == F


def test_time_expired_and_distance_traveled():
    env = Env()
    te = env.node("TimeExpired", seconds=1.0)
    out = []
    for _ in range(41):
        out.append(tick(te))
        env.clock.advance(0.05)
    assert out.count(S) == 2
    dt = env.node("DistanceTraveled", distance=1.0)
    out = []
    for i in range(31):
        env.robot.teleport(Pose2D(0.1 * i, 0.0, 0.0))
        out.append(tick(dt))
    assert [i for i, s in enumerate(out) if s == S] == [10, 20, 30]


def test_is_goal_nearby_uses_remaining_path_length():
    env = Env()
    env.put("path", straight_path(Pose2D(0, 0, 0), Pose2D(3, 0, 0)))
    node = env.node("IsGoalNearby", proximity_threshold=1.0)
    assert tick(node) == F
    env.robot.teleport(Pose2D(2.2, 0.1, 0.0))
    assert tick(node) == S


def test_would_a_recovery_help_reads_error_codes():
    env = Env()
    planner = env.node("WouldAPlannerRecoveryHelp")
    controller = env.node("WouldAControllerRecoveryHelp")
    assert tick(planner) == F and tick(controller) == F          # no codes yet
    env.put("compute_path_error_code", int(PlannerError.NO_VALID_PATH))
    env.put("follow_path_error_code", int(ControllerError.INVALID_PATH))
    assert tick(planner) == S
    assert tick(controller) == F                                 # not recoverable
    env.put("compute_path_error_code", int(PlannerError.GOAL_OCCUPIED))
    assert tick(planner) == F
    custom = env.node("WouldAPlannerRecoveryHelp", error_codes_to_check=[206])
    assert tick(custom) == S


def test_are_error_codes_present():
    env = Env()
    node = env.node("AreErrorCodesPresent", error_code="{follow_path_error_code}",
                    error_codes_to_check=[105, 106])
    assert tick(node) == F
    env.put("follow_path_error_code", 106)
    assert tick(node) == S
    env.put("follow_path_error_code", 0)
    assert tick(node) == F
