"""A kinematic robot (a RobotIO) and no-op components: the executive and trees without any real
algorithm.

Used by ``bench/bench_executive.py`` to measure pure tree + executive overhead, and by tests that
check a tree's control flow without planners, controllers or a simulator. The components are
behaviors.testing's doubles (a planner returning a straight line, a controller driving toward
its end), so trees run their real paths to success.
"""

from __future__ import annotations

import math

import numpy as np

from behaviors.testing import FakeCostmap, ScriptedController, ScriptedPlanner
from hw.interfaces import BaseEvents
from navcore.types import LaserScan, Odometry, Pose2D, Twist


# Odometry is frozen and these are never written: one read-only pair serves every message.
_ZERO_COVARIANCE = np.zeros((3, 3))
_ZERO_COVARIANCE.flags.writeable = False
_NO_EVENTS = BaseEvents()
_NO_INTENSITIES = np.zeros(0, np.float32)
_NO_INTENSITIES.flags.writeable = False


class _Base:
    def __init__(self, robot: KinematicRobot) -> None:
        self.robot = robot

    def send(self, cmd: Twist) -> None:
        self.robot.cmd = cmd

    def odometry(self) -> Odometry:
        return Odometry(self.robot.t, self.robot.pose, self.robot.cmd, _ZERO_COVARIANCE,
                        _ZERO_COVARIANCE)

    def battery(self):
        return None

    def events(self) -> BaseEvents:
        return _NO_EVENTS


ROOM_HALF_WIDTH = 5.0  # m: the walls the laser sees, the square of the no-op costmaps


def room_range(x: float, y: float, angle: float) -> float:
    """Distance from (x, y) along ``angle`` to the walls of the square room of half-width
    ROOM_HALF_WIDTH around the origin (within the scan's 0.05-10 m)."""
    c, s = math.cos(angle), math.sin(angle)
    t = 10.0
    if c != 0.0:
        t = min(t, ((ROOM_HALF_WIDTH if c > 0.0 else -ROOM_HALF_WIDTH) - x) / c)
    if s != 0.0:
        t = min(t, ((ROOM_HALF_WIDTH if s > 0.0 else -ROOM_HALF_WIDTH) - y) / s)
    return max(t, 0.05)


class _Laser:
    """One beam straight ahead at the walls of a square room: the range changes as the robot
    moves, as a real scan's do (the safety gate stops a robot whose laser repeats itself while
    it moves)."""

    mount = Pose2D()

    def __init__(self, robot: KinematicRobot) -> None:
        self.robot = robot
        self._scan: LaserScan | None = None

    def scan(self) -> LaserScan:
        if self._scan is None or self._scan.stamp != self.robot.t:
            p = self.robot.pose
            ranges = np.array([room_range(p.x, p.y, p.theta)], np.float32)
            self._scan = LaserScan(self.robot.t, 0.0, 0.0, 1.0, 0.0, 0.1, 0.05, 10.0, ranges,
                                   _NO_INTENSITIES)
        return self._scan


class KinematicRobot:
    """A RobotIO: a unicycle integrating the last command; never collides. Its laser sees the
    walls of a square room around the origin (``room_range``)."""

    def __init__(self, pose: Pose2D = Pose2D()) -> None:
        self.t = 0.0
        self.pose = pose
        self.cmd = Twist()
        self.base = _Base(self)
        self.laser = _Laser(self)

    def step_to(self, t: float) -> None:
        dt = t - self.t
        if dt > 0:
            p, c = self.pose, self.cmd
            th = p.theta + c.wz * dt
            self.pose = Pose2D(p.x + c.vx * math.cos(p.theta) * dt,
                               p.y + c.vx * math.sin(p.theta) * dt,
                               math.atan2(math.sin(th), math.cos(th)))
            self.t = t

    def true_pose(self) -> Pose2D:
        return self.pose

    def in_collision(self) -> bool:
        return False


def noop_components() -> dict:
    """The ``tree.setup`` components, all no-ops (see the module docstring)."""
    from executive.config import config_from_mapping
    return {
        "global_costmap": FakeCostmap(size_m=10.0, origin=-5.0),
        "local_costmap": FakeCostmap(size_m=10.0, origin=-5.0),
        "planners": {"GridBased": ScriptedPlanner(step=0.3)},
        "controllers": {"FollowPath": ScriptedController(max_vel_theta=1.5)},
        "localizer": None,
        "parameters": config_from_mapping({}, "<noop>").all_parameters(),
    }
