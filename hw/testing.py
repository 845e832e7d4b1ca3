"""The robot I/O test double: a ``hw.interfaces.RobotIO`` without a simulator.

``KinematicRobot`` is a unicycle that integrates the last command between control cycles and
never collides, with a laser whose ranges change as it moves (the safety gate stops a robot
whose laser repeats itself while it moves). By default the laser is one beam straight ahead at
the walls of a square room around the origin (``room_ranges``); a test gives its own geometry
with ``ranges`` and the scan's angles and limits, or none with ``ranges=None`` (a robot without
a laser). ``sent`` keeps every command the base got.

It lives in hw because RobotIO is hw's interface (hw may import navcore only, and this needs
nothing else); the tree's component doubles are in behaviors/testing.py. Its messages are built
once per cycle and share read-only arrays: the executive benchmark steps it thousands of times.
"""

from __future__ import annotations

import math
from typing import Callable, Sequence

import numpy as np

from navcore.types import BaseEvents, LaserScan, Odometry, Pose2D, Twist

ROOM_HALF_WIDTH = 5.0  # m: the walls the default laser sees, the square of the no-op costmaps

# Odometry is frozen and these are never written: one read-only pair serves every message.
_ZERO_COVARIANCE = np.zeros((3, 3))
_ZERO_COVARIANCE.flags.writeable = False
_NO_EVENTS = BaseEvents()
_NO_INTENSITIES = np.zeros(0, np.float32)
_NO_INTENSITIES.flags.writeable = False


def room_ranges(pose: Pose2D) -> list[float]:
    """The default laser: one beam straight ahead, its distance to the walls of the square room
    of half-width ROOM_HALF_WIDTH around the origin (within the scan's 0.05-10 m)."""
    c, s = math.cos(pose.theta), math.sin(pose.theta)
    t = 10.0
    if c != 0.0:
        t = min(t, ((ROOM_HALF_WIDTH if c > 0.0 else -ROOM_HALF_WIDTH) - pose.x) / c)
    if s != 0.0:
        t = min(t, ((ROOM_HALF_WIDTH if s > 0.0 else -ROOM_HALF_WIDTH) - pose.y) / s)
    return [max(t, 0.05)]


class _Base:
    def __init__(self, robot: KinematicRobot) -> None:
        self.robot = robot

    def send(self, cmd: Twist) -> None:
        self.robot.cmd = cmd
        self.robot.sent.append(cmd)

    def odometry(self) -> Odometry:
        return Odometry(self.robot.t, self.robot.pose, self.robot.cmd, _ZERO_COVARIANCE,
                        _ZERO_COVARIANCE)

    def battery(self) -> None:
        return None

    def events(self) -> BaseEvents:
        return _NO_EVENTS


class _Laser:
    mount = Pose2D()

    def __init__(self, robot: KinematicRobot, ranges: Callable[[Pose2D], Sequence[float]],
                 angles: tuple[float, float, float], limits: tuple[float, float]) -> None:
        self.robot = robot
        self.ranges = ranges
        # the scan's fields between stamp and ranges: angles, time_increment, scan_time, limits
        self._fields = (*angles, 0.0, 0.1, *limits)
        self._scan: LaserScan | None = None
        self._scan_pose: Pose2D | None = None

    def scan(self) -> LaserScan:
        # one scan per pose (step_to makes a new one each cycle): read again in the same cycle
        # it is the same message
        robot = self.robot
        if self._scan_pose is not robot.pose:
            self._scan_pose = robot.pose
            self._scan = LaserScan(robot.t, *self._fields,
                                   np.array(self.ranges(robot.pose), np.float32), _NO_INTENSITIES)
        return self._scan


class KinematicRobot:
    """A RobotIO: a unicycle integrating the last command; never collides.

    ``ranges(pose)`` gives the laser's ranges at a pose, beam i at ``angle_min + i *
    angle_increment`` (default: ``room_ranges``, one beam ahead at the square room's walls);
    ``ranges=None``: no laser.
    """

    def __init__(self, pose: Pose2D = Pose2D(), *,
                 ranges: Callable[[Pose2D], Sequence[float]] | None = room_ranges,
                 angle_min: float = 0.0, angle_max: float = 0.0, angle_increment: float = 1.0,
                 range_min: float = 0.05, range_max: float = 10.0) -> None:
        self.t = 0.0
        self.pose = pose
        self.cmd = Twist()
        self.sent: list[Twist] = []
        self.base = _Base(self)
        self.laser = None if ranges is None else _Laser(
            self, ranges, (angle_min, angle_max, angle_increment), (range_min, range_max))

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


__all__ = ["KinematicRobot", "ROOM_HALF_WIDTH", "room_ranges"]
