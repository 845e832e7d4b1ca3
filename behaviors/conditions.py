"""Condition nodes: answer a question in one tick, SUCCESS = yes, FAILURE = no. Never RUNNING.

State that spans ticks (a reference pose, a start time) is re-armed when the node is fresh
(status INVALID): that is, when its parent starts a new run or halted it.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numba import njit

from behaviors.base import FAILURE, INVALID, SUCCESS, Leaf, PortInformation, Status
from behaviors.error_codes import CONTROLLER_RECOVERABLE, PLANNER_RECOVERABLE
from navcore.costmap.cost_values import INSCRIBED_INFLATED_OBSTACLE, NO_INFORMATION
from navcore.types import Path, Pose2D


def _yes(flag: bool) -> Status:
    return SUCCESS if flag else FAILURE


class Condition(Leaf):
    """Base: a condition with access to the clock and the robot."""

    CATEGORY = "Condition"
    INPUT_PORTS: dict[str, PortInformation]
    OUTPUT_PORTS: dict[str, PortInformation]

    def setup(self, **kwargs: Any) -> None:
        self.clock = self.component(kwargs, "clock")
        self.robot = self.component(kwargs, "robot", optional=True)
        self.control_period = float(kwargs.get("control_period") or 0.05)

    def pose(self) -> Pose2D:
        if self.robot is None:
            raise RuntimeError(f"{type(self).__name__} '{self.name}': setup() got no 'robot'")
        return self.robot.pose()


class GoalReached(Condition):
    """SUCCESS when the robot is within ``goal_reached_tol`` metres of ``goal``."""

    INPUT_PORTS = {
        "goal": PortInformation(Pose2D, True, "goal pose in map"),
        "goal_reached_tol": PortInformation(float, False, "distance tolerance, m", 0.25),
    }
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    DEFAULT_KEYS = {"goal": "goal"}

    def update(self) -> Status:
        goal = self.read("goal")
        if goal is None:
            self.say("no goal")
            return FAILURE
        d = self.pose().distance_to(goal)
        self.say("{:.2f} m from the goal", d)
        return _yes(d <= self.get_input("goal_reached_tol"))


class GoalUpdated(Condition):
    """SUCCESS on the tick in which ``goal`` differs from the goal seen on the previous tick.

    The first tick of a run only remembers the goal (FAILURE). (Nav2 ``GoalUpdated``.)
    """

    INPUT_PORTS = {"goal": PortInformation(Pose2D, True, "goal pose in map")}
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    DEFAULT_KEYS = {"goal": "goal"}

    def update(self) -> Status:
        goal = self.read("goal")
        if self.status is INVALID:
            self._seen = goal
            return FAILURE
        changed = goal != self._seen
        self._seen = goal
        if changed:
            self.say("goal changed")
        return _yes(changed)


class IsPathValid(Condition):
    """SUCCESS when no pose of ``path`` lies on a lethal or inscribed cell of the global costmap.

    FAILURE also when there is no path. (Nav2 Humble ``IsPathValid``.)
    """

    INPUT_PORTS = {
        "path": PortInformation(Path, True, "path to check"),
        "max_cost": PortInformation(int, False, "highest acceptable cell cost",
                                    INSCRIBED_INFLATED_OBSTACLE - 1),
        "consider_unknown_as_obstacle": PortInformation(bool, False, "unknown cells block", False),
    }
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    DEFAULT_KEYS = {"path": "path"}

    def setup(self, **kwargs: Any) -> None:
        super().setup(**kwargs)
        self.costmap = self.component(kwargs, "global_costmap")

    def update(self) -> Status:
        path = self.read("path")
        if path is None or len(path) == 0:
            self.say("no path")
            return FAILURE
        grid = self.costmap.costmap
        max_cost = self.get_input("max_cost")
        unknown_blocks = self.get_input("consider_unknown_as_obstacle")
        for x, y, _ in path.poses:
            cell = grid.world_to_map(float(x), float(y))
            if cell is None:
                continue
            cost = int(grid.costs[cell[1], cell[0]])
            if cost == NO_INFORMATION and not unknown_blocks:
                continue
            if cost > max_cost:
                self.say(f"path blocked at ({x:.2f}, {y:.2f}), cost {cost}")
                return FAILURE
        return SUCCESS


class _ProgressWindow:
    """Has the robot moved ``radius`` metres within the last ``window`` seconds?"""

    def __init__(self) -> None:
        self.anchor: Pose2D | None = None
        self.since = 0.0

    def reset(self, pose: Pose2D, now: float) -> None:
        self.anchor, self.since = pose, now

    def stalled(self, pose: Pose2D, now: float, radius: float, window: float) -> bool:
        if self.anchor is None or pose.distance_to(self.anchor) >= radius:
            self.reset(pose, now)
            return False
        return now - self.since > window


class IsStuck(Condition):
    """SUCCESS when the robot has not moved ``required_movement_radius`` metres within the last
    ``movement_time_allowance`` seconds (real progress checking, like Nav2's
    SimpleProgressChecker, rather than Nav2's deceleration-only ``IsStuck``)."""

    INPUT_PORTS = {
        "required_movement_radius": PortInformation(float, False, "progress radius, m", 0.5),
        "movement_time_allowance": PortInformation(float, False, "time to make progress, s", 10.0),
    }
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def update(self) -> Status:
        now, pose = self.clock.now(), self.pose()
        if self.status is INVALID:
            self._window = _ProgressWindow()
            self._window.reset(pose, now)
        stuck = self._window.stalled(pose, now, self.get_input("required_movement_radius"),
                                     self.get_input("movement_time_allowance"))
        if stuck:
            self.say("no progress for {:.1f} s", now - self._window.since)
        return _yes(stuck)


class IsOscillating(Condition):
    """move_base's oscillation check: SUCCESS when the robot has not moved
    ``oscillation_distance`` metres within ``oscillation_timeout`` seconds (0 = never).

    The timer restarts when the goal changes, and, like move_base after a recovery, when the
    node was not ticked for more than two control periods.
    """

    INPUT_PORTS = {
        "oscillation_timeout": PortInformation(float, False, "s; 0 disables the check", 0.0),
        "oscillation_distance": PortInformation(float, False, "m the robot must move", 0.5),
        "goal": PortInformation(Pose2D, False, "the timer restarts when this changes"),
    }
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    DEFAULT_KEYS = {"goal": "goal"}

    def setup(self, **kwargs: Any) -> None:
        super().setup(**kwargs)
        self._window = _ProgressWindow()
        self._last_tick = -math.inf
        self._goal: Pose2D | None = None

    def update(self) -> Status:
        now, pose, goal = self.clock.now(), self.pose(), self.read("goal")
        if goal != self._goal or now - self._last_tick > 2.0 * self.control_period:
            self._window.reset(pose, now)
            self._goal = goal
        self._last_tick = now
        timeout = self.get_input("oscillation_timeout")
        if timeout <= 0.0:
            return FAILURE
        osc = self._window.stalled(pose, now, self.get_input("oscillation_distance"), timeout)
        if osc:
            self.say(f"oscillating: moved < {self.get_input('oscillation_distance')} m "
                     f"in {timeout} s")
        return _yes(osc)


class IsLocalized(Condition):
    """SUCCESS when the localiser's standard deviations are within bounds.

    Without a localiser (ground truth), SUCCESS.
    """

    INPUT_PORTS = {
        "max_xy_std": PortInformation(float, False, "largest x or y std deviation, m", 0.25),
        "max_yaw_std": PortInformation(float, False, "largest yaw std deviation, rad", 0.25),
    }
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def setup(self, **kwargs: Any) -> None:
        super().setup(**kwargs)
        self.localizer = kwargs.get("localizer")

    def update(self) -> Status:
        if self.localizer is None:
            self.say("no localiser: ground truth")
            return SUCCESS
        cov = np.asarray(self.localizer.covariance(), dtype=float)
        sx, sy, st = (math.sqrt(max(0.0, float(cov[i, i]))) for i in range(3))
        self.say("std x {:.2f} y {:.2f} yaw {:.2f}", sx, sy, st)
        return _yes(max(sx, sy) <= self.get_input("max_xy_std")
                    and st <= self.get_input("max_yaw_std"))


class IsBatteryLow(Condition):
    """SUCCESS when the battery is at or below ``min_battery`` (fraction 0..1, or volts when
    ``is_voltage``). FAILURE when no battery state is known. (Nav2 ``IsBatteryLow``.)"""

    INPUT_PORTS = {
        "min_battery": PortInformation(float, False, "threshold, fraction 0..1 or V", 0.2),
        "is_voltage": PortInformation(bool, False, "compare volts instead of charge", False),
    }
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def update(self) -> Status:
        state = self.robot.battery() if self.robot is not None else None
        if state is None:
            self.say("no battery state")
            return FAILURE
        value = state.voltage if self.get_input("is_voltage") else state.percentage
        return _yes(value <= self.get_input("min_battery"))


class TimeExpired(Condition):
    """SUCCESS each time ``seconds`` have passed since the run started or it last fired."""

    INPUT_PORTS = {"seconds": PortInformation(float, False, "period, s", 1.0)}
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def update(self) -> Status:
        now = self.clock.now()
        if self.status is INVALID:
            self._start = now
            return FAILURE
        if now - self._start >= self.get_input("seconds") - 1e-9:  # float sums of periods
            self._start = now
            return SUCCESS
        return FAILURE


class DistanceTraveled(Condition):
    """SUCCESS each time the robot has moved ``distance`` metres since the run started or it
    last fired (straight-line)."""

    INPUT_PORTS = {"distance": PortInformation(float, False, "m", 1.0)}
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def update(self) -> Status:
        pose = self.pose()
        if self.status is INVALID:
            self._anchor = pose
            return FAILURE
        if pose.distance_to(self._anchor) >= self.get_input("distance"):
            self._anchor = pose
            return SUCCESS
        return FAILURE


def length_to_go(poses: np.ndarray) -> np.ndarray:
    """For each pose of an (N, 3) path, the path length from it to the end, m."""
    if len(poses) < 2:
        return np.zeros(1)
    return _length_to_go(poses)


@njit(cache=True)
def _length_to_go(poses: np.ndarray) -> np.ndarray:
    """Suffix sums of the step lengths, added from the end as a cumulative sum of the reversed
    steps does (so the same floats)."""
    n = poses.shape[0]
    out = np.empty(n)
    out[n - 1] = 0.0
    total = 0.0
    for i in range(n - 2, -1, -1):
        step = math.hypot(poses[i + 1, 0] - poses[i, 0], poses[i + 1, 1] - poses[i, 1])
        total = step if i == n - 2 else total + step
        out[i] = total
    return out


def remaining_length(path: Path, pose: Pose2D, to_go: np.ndarray | None = None) -> float:
    """Length of ``path`` from the pose closest to ``pose`` to its end, m (``to_go`` is
    ``length_to_go(path.poses)`` when the caller keeps it)."""
    if len(path) == 0:
        return 0.0
    if to_go is None:
        to_go = length_to_go(path.poses)
    return float(_closest_remaining(path.poses, float(pose.x), float(pose.y), to_go))


@njit(cache=True)
def _closest_remaining(poses: np.ndarray, x: float, y: float, to_go: np.ndarray) -> float:
    """Distance to the closest pose plus ``to_go`` from it (the first closest, as np.argmin;
    a NaN distance wins, as there). Checked every tick, so one pass without temporaries."""
    best, best_d = 0, math.inf
    for i in range(poses.shape[0]):
        d = math.hypot(poses[i, 0] - x, poses[i, 1] - y)
        if d != d:
            return d + to_go[i]
        if d < best_d:
            best, best_d = i, d
    if best_d == math.inf:  # every distance infinite: np.argmin takes the first
        best = 0
        best_d = math.hypot(poses[0, 0] - x, poses[0, 1] - y)
    return best_d + to_go[best]


class IsGoalNearby(Condition):
    """SUCCESS when what is left of ``path`` (from the robot) is shorter than
    ``proximity_threshold`` metres (Nav2 ``IsGoalNearby``)."""

    INPUT_PORTS = {
        "path": PortInformation(Path, True, "current global path"),
        "proximity_threshold": PortInformation(float, False, "remaining path length, m", 1.0),
    }
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    DEFAULT_KEYS = {"path": "path"}

    def update(self) -> Status:
        path = self.read("path")
        if path is None:
            return FAILURE
        if path is not getattr(self, "_path", None):  # a new plan: sum its lengths once
            self._path, self._to_go = path, length_to_go(path.poses)
        left = remaining_length(path, self.pose(), self._to_go)
        self.say("{:.2f} m of path left", left)
        return _yes(left < self.get_input("proximity_threshold"))


class _WouldRecoveryHelp(Condition):
    INPUT_PORTS: dict[str, PortInformation]
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def update(self) -> Status:
        code = self.read("error_code")
        if code is None:
            self.say("no error code yet")
            return FAILURE
        helps = int(code) in self.get_input("error_codes_to_check")
        self.say(f"error code {code}: a recovery {'may' if helps else 'would not'} help")
        return _yes(helps)


class AreErrorCodesPresent(Condition):
    """SUCCESS when ``error_code`` is one of ``error_codes_to_check`` (Nav2)."""

    INPUT_PORTS = {
        "error_code": PortInformation(int, True, "an error code key"),
        "error_codes_to_check": PortInformation(list, True, "codes to look for"),
    }
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def update(self) -> Status:
        code = self.read("error_code")
        return _yes(code is not None and int(code) in self.get_input("error_codes_to_check"))


class WouldAPlannerRecoveryHelp(_WouldRecoveryHelp):
    """SUCCESS when the last planning error code is one a recovery can fix (Nav2 defaults:
    UNKNOWN, NO_VALID_PATH, TIMEOUT)."""

    INPUT_PORTS = {
        "error_code": PortInformation(int, True, "ComputePathToPose error code"),
        "error_codes_to_check": PortInformation(list, False, "codes a recovery may fix",
                                                PLANNER_RECOVERABLE),
    }
    DEFAULT_KEYS = {"error_code": "compute_path_error_code"}


class WouldAControllerRecoveryHelp(_WouldRecoveryHelp):
    """SUCCESS when the last FollowPath error code is one a recovery can fix (Nav2 defaults:
    UNKNOWN, PATIENCE_EXCEEDED, FAILED_TO_MAKE_PROGRESS, NO_VALID_CONTROL)."""

    INPUT_PORTS = {
        "error_code": PortInformation(int, True, "FollowPath error code"),
        "error_codes_to_check": PortInformation(list, False, "codes a recovery may fix",
                                                CONTROLLER_RECOVERABLE),
    }
    DEFAULT_KEYS = {"error_code": "follow_path_error_code"}


class AlwaysSuccess(Leaf):
    """SUCCESS, every tick (BT.CPP built-in)."""

    INPUT_PORTS: dict[str, PortInformation] = {}
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def update(self) -> Status:
        return SUCCESS


class AlwaysFailure(Leaf):
    """FAILURE, every tick (BT.CPP built-in)."""

    INPUT_PORTS: dict[str, PortInformation] = {}
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def update(self) -> Status:
        return FAILURE
