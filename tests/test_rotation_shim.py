"""Turning to a new path's heading before following it (FollowPath's ``rotate_to_heading``,
navcore.controllers.rotation_shim), tick by tick against a controller that would reverse."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from py_trees.blackboard import Client
from py_trees.common import Access, Status

from behaviors.base import make
from behaviors.testing import (FakeCostmap, FakeRobot, ReversingController, ScriptedWorld,
                               straight_path)
from navcore.controllers.rotation_shim import ShimParams, heading_error, turn_command
from navcore.error_codes import ControllerError
from navcore.types import Pose2D, Twist, angle_diff

S, F, R = Status.SUCCESS, Status.FAILURE, Status.RUNNING
_ns = itertools.count()


def test_heading_error_aims_at_the_path_ahead_and_leaves_a_near_goal_alone():
    poses = np.array([[x, 0.0, 0.0] for x in np.arange(0.0, 3.0, 0.05)])
    assert heading_error(Pose2D(0.0, 0.0, 0.0), poses, 0.5) == pytest.approx(0.0)
    assert abs(heading_error(Pose2D(0.0, 0.0, math.pi), poses, 0.5)) == pytest.approx(math.pi)
    assert heading_error(Pose2D(0.0, 0.1, 0.0), poses, 0.5) == pytest.approx(
        math.atan2(-0.1, 0.5), abs=0.02)
    # the sample starts at the pose nearest the robot: what lies behind it does not count
    assert heading_error(Pose2D(1.5, 0.0, 0.0), poses, 0.5) == pytest.approx(0.0)
    assert heading_error(Pose2D(2.7, 0.0, math.pi), poses, 0.5) is None
    p = ShimParams()
    assert turn_command(3.0, 0.0, 0.1, p) == pytest.approx(0.32)       # acceleration-limited
    assert turn_command(3.0, 1.8, 0.1, p) == pytest.approx(1.8)        # full rate
    assert turn_command(0.05, 0.6, 0.1, p) == pytest.approx(math.sqrt(2 * 3.2 * 0.05))
    assert turn_command(0.05, 1.8, 0.1, p) == pytest.approx(1.8 - 0.32)  # braking
    assert turn_command(-3.0, 0.0, 0.1, p) == pytest.approx(-0.32)


class Rig:
    def __init__(self, start: Pose2D, costmap: FakeCostmap | None = None):
        self.world = ScriptedWorld(robot=FakeRobot(start), controller=None,
                           local_costmap=costmap or FakeCostmap())
        self.controller = ReversingController()
        self.ns = f"/shim{next(_ns)}"
        self.bb = Client(name="shim", namespace=self.ns)
        for k in ("path", "cmd_vel", "code"):
            self.bb.register_key(k, access=Access.WRITE)

    def node(self, **ports):
        comps = dict(self.world.components(), controllers={"FollowPath": self.controller})
        n = make("FollowPath", namespace=self.ns, error_code_id="{code}", **ports)
        n.setup(**comps)
        return n

    def tick(self, node) -> Twist:
        self.bb.set("cmd_vel", Twist.zero())
        node.tick_once()
        cmd = self.bb.get("cmd_vel")
        self.world.step(cmd)
        return cmd


def test_a_robot_facing_away_turns_on_the_spot_then_the_controller_drives():
    rig = Rig(Pose2D(0.0, 0.0, 0.0))
    path = straight_path(Pose2D(0.0, 0.0, math.pi), Pose2D(-3.0, 0.0, math.pi))
    rig.bb.set("path", path)
    node = rig.node(rotate_to_heading=True)
    cmds = [rig.tick(node) for _ in range(60)]
    assert node.status == R
    turning = [c for c in cmds if c.wz != 0.0]
    first_drive = next(i for i, c in enumerate(cmds) if c.vx != 0.0)
    # it turned first, never reversed, and handed over within the threshold
    assert all(c.vx == 0.0 for c in cmds[:first_drive])
    assert all(c.vx > 0.0 for c in cmds[first_drive:])
    assert len(turning) == first_drive
    heading = rig.world.robot.trajectory[first_drive].theta
    assert abs(angle_diff(heading, math.pi)) <= ShimParams().angular_dist_threshold + 1e-9
    assert max(abs(c.wz) for c in turning) == pytest.approx(1.8)
    assert rig.world.robot.pose().x < -0.25   # driven forwards, toward the goal
    # the shim is off by default: the same controller reverses along the path
    rig2 = Rig(Pose2D(0.0, 0.0, 0.0))
    rig2.bb.set("path", path)
    plain = rig2.node()
    assert rig2.tick(plain).vx == pytest.approx(-0.3)


def test_a_replan_rearms_the_turn_and_an_aligned_robot_is_left_to_the_controller():
    rig = Rig(Pose2D(0.0, 0.0, 0.0))
    ahead = straight_path(Pose2D(0.0, 0.0, 0.0), Pose2D(3.0, 0.0, 0.0))
    rig.bb.set("path", ahead)
    node = rig.node(rotate_to_heading=True)
    assert rig.tick(node).vx == pytest.approx(0.3)
    # a new path behind the robot (a replan after a goal change): turn again
    p = rig.world.robot.pose()
    rig.bb.set("path", straight_path(p, Pose2D(p.x - 3.0, 0.0, math.pi)))
    cmd = rig.tick(node)
    assert cmd.vx == 0.0 and cmd.wz != 0.0


def test_a_blocked_turn_is_no_valid_command_until_the_failure_tolerance_runs_out():
    def lethal_when_turned(x, y, t):
        return 254 if abs(angle_diff(t, 0.0)) > 0.05 else 0
    rig = Rig(Pose2D(0.0, 0.0, 0.0), FakeCostmap(footprint=lethal_when_turned))
    rig.bb.set("path", straight_path(Pose2D(0.0, 0.0, math.pi), Pose2D(-3.0, 0.0, math.pi)))
    node = rig.node(rotate_to_heading=True, failure_tolerance=0.5)
    cmds = []
    for _ in range(40):
        cmds.append(rig.tick(node))
        if node.status != R:
            break
    assert node.status == F
    assert all(c == Twist.zero() for c in cmds)
    assert rig.bb.get("code") == ControllerError.PATIENCE_EXCEEDED
    assert rig.controller.calls == 0   # never handed a path it would have reversed along
    assert 0.5 <= rig.world.clock.now() <= 0.5 + 2 * rig.world.control_period


def test_the_shim_ports_reach_the_turn_by_name():
    rig = Rig(Pose2D(0.0, 0.0, 0.0))
    rig.bb.set("path", straight_path(Pose2D(0.0, 0.0, math.pi), Pose2D(-3.0, 0.0, math.pi)))
    node = rig.node(rotate_to_heading=True, angular_dist_threshold=0.3,
                    forward_sampling_distance=0.7, rotate_to_heading_angular_vel=0.9,
                    max_angular_accel=5.0, simulate_ahead_time=1.5)
    assert node._shim_params() == ShimParams(angular_dist_threshold=0.3,
                                             forward_sampling_distance=0.7,
                                             rotate_to_heading_angular_vel=0.9,
                                             max_angular_accel=5.0, simulate_ahead_time=1.5)
    cmds = [rig.tick(node) for _ in range(150)]
    first_drive = next(i for i, c in enumerate(cmds) if c.vx != 0.0)
    turning = cmds[:first_drive]
    # the first turn command is one period of max_angular_accel, the top rate is the turn's own
    assert abs(turning[0].wz) == pytest.approx(5.0 * node.control_period)
    assert max(abs(c.wz) for c in turning) == pytest.approx(0.9)
    heading = rig.world.robot.trajectory[first_drive].theta
    assert abs(angle_diff(heading, math.pi)) <= 0.3 + 1e-9
