"""No-op components and a kinematic robot: the executive and trees without any real algorithm.

Used by ``bench/bench_executive.py`` to measure pure tree + executive overhead, and by tests that
check a tree's control flow without planners, controllers or a simulator. Each component does
the least that keeps the contract honest (a planner returns a straight line, a controller drives
toward the end of it), so trees run their real paths to success.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from hw.interfaces import BaseEvents
from navcore.costmap.costmap2d import Costmap2D
from navcore.types import LaserScan, Odometry, Path, Pose2D, Twist


@dataclass(slots=True)
class StraightPlan:
    ok: bool
    path: Path | None
    reason: str = ""


_STEPS = np.linspace(0.0, 1.0, 11)  # fractions of the way along a straight plan


class StraightLinePlanner:
    """A planner that returns the straight segment start -> goal (11 poses)."""

    def __init__(self) -> None:
        self.calls = 0

    def make_plan(self, start: Pose2D, goal: Pose2D) -> StraightPlan:
        self.calls += 1
        poses = np.empty((len(_STEPS), 3))
        poses[:, 0] = start.x + _STEPS * (goal.x - start.x)
        poses[:, 1] = start.y + _STEPS * (goal.y - start.y)
        poses[:, 2] = goal.theta
        return StraightPlan(True, Path(poses))


@dataclass(slots=True)
class Control:
    cmd: Twist
    status: str


class PursuitController:
    """Turns toward the last pose of the plan and drives; goal reached within 0.1 m."""

    def __init__(self) -> None:
        self.goal: Pose2D | None = None
        self._reached = False
        self.calls = 0

    def set_plan(self, path: Path) -> None:
        self.goal = path.pose(len(path) - 1) if len(path) else None

    def compute_velocity(self, pose: Pose2D, velocity: Twist, path: Path | None = None) -> Control:
        self.calls += 1
        if path is not None and len(path):
            self.set_plan(path)
        if self.goal is None:
            return Control(Twist(), "no_plan")
        if pose.distance_to(self.goal) < 0.1:
            self._reached = True
            return Control(Twist(), "goal_reached")
        err = math.atan2(self.goal.y - pose.y, self.goal.x - pose.x) - pose.theta
        err = math.atan2(math.sin(err), math.cos(err))
        return Control(Twist(0.5 if abs(err) < 0.4 else 0.0, 0.0, max(-1.5, min(1.5, 2 * err))),
                       "following")

    def is_goal_reached(self) -> bool:
        return self._reached

    def reset(self) -> None:
        self._reached = False


class FreeCostmap:
    """A CostmapHandle over an all-free grid; clearing does nothing."""

    def __init__(self, size: int = 200, resolution: float = 0.05) -> None:
        self.costmap = Costmap2D(size, size, resolution, -size * resolution / 2,
                                 -size * resolution / 2)

    def reset_layers(self) -> None:
        pass

    def clear_outside(self, x: float, y: float, reset_distance: float) -> None:
        pass

    def clear_inside(self, x: float, y: float, reset_distance: float) -> None:
        pass

    def footprint_cost(self, x: float, y: float, theta: float) -> int:
        return 0


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


class _Laser:
    mount = Pose2D()

    def __init__(self, robot: KinematicRobot) -> None:
        self.robot = robot
        self._ranges = np.full(5, 5.0, np.float32)
        self._scan: LaserScan | None = None

    def scan(self) -> LaserScan:
        if self._scan is None or self._scan.stamp != self.robot.t:
            self._scan = LaserScan(self.robot.t, -1.0, 1.0, 0.5, 0.0, 0.1, 0.05, 10.0,
                                   self._ranges, _NO_INTENSITIES)
        return self._scan


class KinematicRobot:
    """A RobotIO: a unicycle integrating the last command; never collides."""

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
        "global_costmap": FreeCostmap(),
        "local_costmap": FreeCostmap(),
        "planners": {"GridBased": StraightLinePlanner()},
        "controllers": {"FollowPath": PursuitController()},
        "localizer": None,
        "parameters": config_from_mapping({}, "<noop>").all_parameters(),
    }
