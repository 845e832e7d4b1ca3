"""Recoveries: costmap clearing, Spin / BackUp / DriveOnHeading / Wait (Nav2 and rotate_recovery
semantics), and the guide's extra SMACH-style ones, TemporaryGoal and BackOffToPreviousPose.

Motion recoveries write ``cmd_vel`` one control period at a time, check the robot footprint on
the costmap (``footprint_cost``) along the motion ahead, and fail with COLLISION_AHEAD rather than
drive into a lethal cell or from free space into inscribed cost (a robot already in inscribed
cost may move through it to get out). Every exit (finished or interrupted) leaves a zero command.
"""

from __future__ import annotations

import math
from typing import Any, Iterable

import numpy as np

from behaviors.actions import heading_to
from behaviors.base import (FAILURE, INVALID, RUNNING, SUCCESS, Leaf, PortInformation, Recovery,
                            Status)
from behaviors.clearance import clearances
from behaviors.error_codes import BehaviorError
from navcore.costmap.cost_values import INSCRIBED_INFLATED_OBSTACLE, LETHAL_OBSTACLE, NO_INFORMATION
from navcore.types import Pose2D, Twist, angle_diff

COSTMAP_CHOICES = ("local", "global", "both")
# metres a tight-spot motion may close in on a lethal cell beyond the start (numerical slack)
CLEARANCE_TOLERANCE = 0.002


def is_collision(cost: int, start_cost: int = 0) -> bool:
    """A footprint cost that forbids the pose: off the map (-1), touching a lethal cell, or
    entering inscribed cost from a pose that was not already there. (A robot already in a
    tight spot may move through inscribed cells to get out; unknown cells do not block.)"""
    if cost < 0 or cost == LETHAL_OBSTACLE:
        return True
    return cost == INSCRIBED_INFLATED_OBSTACLE and start_cost < INSCRIBED_INFLATED_OBSTACLE


class RecoveryAction(Recovery, Leaf):
    """Base of the recovery actions: components, error reporting, the zero command on exit."""

    CATEGORY = "Action"
    INPUT_PORTS: dict[str, PortInformation]
    OUTPUT_PORTS: dict[str, PortInformation]
    CHOICES: dict[str, tuple] = {}
    NEEDS_ROBOT = True

    def setup(self, **kwargs: Any) -> None:
        self.clock = self.component(kwargs, "clock")
        self.robot = self.component(kwargs, "robot", optional=not self.NEEDS_ROBOT)
        self.costmaps = {"local": kwargs.get("local_costmap"), "global": kwargs.get("global_costmap")}
        self.control_period = float(kwargs.get("control_period") or 0.05)

    def costmap_handles(self, which: str) -> list[Any]:
        names = ("local", "global") if which == "both" else (which,)
        return [self.costmaps[n] for n in names if self.costmaps.get(n) is not None]

    def collision_map(self) -> Any:
        """The costmap motion is checked on: the local one, else the global one."""
        return self.costmaps.get("local") or self.costmaps.get("global")

    def report(self, code: BehaviorError, msg: str = "") -> None:
        if "error_code_id" in self.output_ports():
            self.write("error_code_id", int(code))
        self.say(msg)

    def first_collision(self, poses: Iterable[Pose2D], start: Pose2D | None = None
                        ) -> tuple[Pose2D, int] | None:
        """First pose whose footprint is in collision (see ``is_collision``; ``start`` is where
        the robot is now), with its cost; None if all are clear.

        From a tight spot (the footprint already in inscribed or lethal cost) the grid's
        conservative rasterisation cannot tell a near miss from contact, so a lethal cost is
        then judged geometrically: the footprint polygon may not overlap a lethal cell (as the
        square it is) more than it already does at ``start``."""
        handle = self.collision_map()
        if handle is None:
            return None
        start_cost = 0 if start is None else int(handle.footprint_cost(start.x, start.y,
                                                                        start.theta))
        if start_cost == NO_INFORMATION:
            start_cost = 0
        poses = list(poses)
        tight = start is not None and start_cost >= INSCRIBED_INFLATED_OBSTACLE
        gaps: Any = None
        for i, p in enumerate(poses):
            cost = int(handle.footprint_cost(p.x, p.y, p.theta))
            if not is_collision(cost, start_cost):
                continue
            if tight and cost == LETHAL_OBSTACLE:
                if gaps is None:
                    gaps = clearances(handle, [start] + poses)
                if gaps is not None and gaps[i + 1] >= min(0.0, gaps[0]) - CLEARANCE_TOLERANCE:
                    continue
            return p, cost
        return None

    def pursue(self, pose: Pose2D, trail: list[Pose2D], index: int, target: Pose2D,
               speed: float, lookahead: float, w_max: float
               ) -> tuple[Twist | None, int, tuple[Pose2D, int] | None]:
        """One pure-pursuit step along ``trail`` toward ``target``: forwards when the aim point
        is ahead, backwards when it is behind. Returns (command or None if blocked, the new
        trail index, the blocking pose and cost). Footprint-checked over
        ``simulate_ahead_time`` unless ``disable_collision_checks``."""
        while index < len(trail) - 1 and pose.distance_to(trail[index]) < lookahead:
            index += 1
        aim = trail[index].relative_to(pose)
        v = -speed if aim.x <= 0.0 else speed
        v = math.copysign(min(abs(v), pose.distance_to(target) / self.control_period), v)
        l2 = max(aim.x * aim.x + aim.y * aim.y, 1e-6)
        w = max(-w_max, min(w_max, v * 2.0 * aim.y / l2))
        if not self.get_input("disable_collision_checks"):
            horizon = self.get_input("simulate_ahead_time")
            n = max(1, int(math.ceil(abs(v) * horizon / 0.05)))
            dt = horizon / n
            poses, p = [], pose
            for _ in range(n):
                p = p.compose(Pose2D(v * dt, 0.0, w * dt))
                poses.append(p)
            hit = self.first_collision(poses, pose)
            if hit is not None:
                return None, index, hit
        return Twist(v, 0.0, w), index, None

    def start_progress_check(self, pose: Pose2D) -> None:
        self._anchor, self._anchor_t = pose, self.clock.now()

    def no_progress(self, pose: Pose2D) -> bool:
        """True when the robot stayed within ``required_movement_radius`` for longer than
        ``movement_time_allowance`` seconds (0 disables); a stuck robot gives up early."""
        allowance = self.get_input("movement_time_allowance")
        if allowance <= 0.0:
            return False
        if pose.distance_to(self._anchor) >= self.get_input("required_movement_radius"):
            self.start_progress_check(pose)
            return False
        return self.clock.now() - self._anchor_t > allowance

    def stop_motion(self) -> None:
        if "cmd_vel" in self.output_ports():
            self.write("cmd_vel", Twist.zero())

    def terminate(self, new_status: Status) -> None:
        if self.status is RUNNING or new_status is not INVALID:
            self.stop_motion()


_ERR = {"error_code_id": PortInformation(int, False, "a BehaviorError; 0 on success")}
_CMD = {"cmd_vel": PortInformation(Twist, True, "velocity command for this tick")}


class _Clear(RecoveryAction):
    INPUT_PORTS: dict[str, PortInformation]
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    CHOICES = {"costmap": COSTMAP_CHOICES}

    def clear(self, handle: Any, pose: Pose2D | None) -> None:
        raise NotImplementedError

    def update(self) -> Status:
        which = self.get_input("costmap")
        if which not in COSTMAP_CHOICES:
            self.say(f"costmap must be one of {COSTMAP_CHOICES}, got {which!r}")
            return FAILURE
        handles = self.costmap_handles(which)
        if not handles:
            self.say(f"no {which} costmap was set up")
            return FAILURE
        pose = self.robot.pose() if self.robot is not None else None
        for h in handles:
            self.clear(h, pose)
        self.say(f"cleared {which}")
        return SUCCESS


class ClearEntireCostmap(_Clear):
    """Reset every layer of the ``costmap`` (local, global or both) in one tick. SUCCESS."""

    INPUT_PORTS = {"costmap": PortInformation(str, False, "local, global or both", "both")}
    NEEDS_ROBOT = False

    def clear(self, handle: Any, pose: Pose2D | None) -> None:
        handle.reset_layers()


class ClearCostmapExceptRegion(_Clear):
    """clear_costmap_recovery: reset clearable layers outside a square of side
    ``reset_distance`` metres centred on the robot (move_base's conservative/aggressive reset).
    SUCCESS in one tick."""

    INPUT_PORTS = {
        "costmap": PortInformation(str, False, "local, global or both", "both"),
        "reset_distance": PortInformation(float, False, "side of the kept square, m", 1.0),
    }

    def clear(self, handle: Any, pose: Pose2D | None) -> None:
        if pose is None:
            raise RuntimeError(f"{self.name}: needs the robot pose")
        handle.clear_outside(pose.x, pose.y, self.get_input("reset_distance"))


class ClearCostmapAroundRobot(_Clear):
    """Reset clearable layers inside a square of side ``reset_distance`` metres centred on the
    robot. SUCCESS in one tick."""

    INPUT_PORTS = {
        "costmap": PortInformation(str, False, "local, global or both", "local"),
        "reset_distance": PortInformation(float, False, "side of the cleared square, m", 1.0),
    }

    def clear(self, handle: Any, pose: Pose2D | None) -> None:
        if pose is None:
            raise RuntimeError(f"{self.name}: needs the robot pose")
        handle.clear_inside(pose.x, pose.y, self.get_input("reset_distance"))


class Wait(RecoveryAction):
    """RUNNING for ``wait_duration`` seconds of the injected clock, then SUCCESS."""

    INPUT_PORTS = {"wait_duration": PortInformation(float, False, "s", 1.0)}
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    NEEDS_ROBOT = False

    def initialise(self) -> None:
        self._until = self.clock.now() + self.get_input("wait_duration")

    def update(self) -> Status:
        left = self._until - self.clock.now()
        if left <= 1e-9:
            return SUCCESS
        self.say("{:.1f} s left", left)
        return RUNNING


class ReinitializeGlobalLocalization(RecoveryAction):
    """Ask the localiser to spread its particles over all free space (amcl's
    global_localization service). SUCCESS in one tick; FAILURE without a localiser."""

    INPUT_PORTS: dict[str, PortInformation] = {}
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    NEEDS_ROBOT = False

    def setup(self, **kwargs: Any) -> None:
        super().setup(**kwargs)
        self.localizer = kwargs.get("localizer")

    def update(self) -> Status:
        if self.localizer is None:
            self.say("no localiser to reinitialise")
            return FAILURE
        self.localizer.global_localization()
        self.say("particles spread over the free space")
        return SUCCESS


class GlobalLocalization(ReinitializeGlobalLocalization):
    """navbt's plain name for ReinitializeGlobalLocalization (same node, same semantics)."""


class Spin(RecoveryAction):
    """Turn in place by ``spin_dist`` radians (sign = direction), then stop (rotate_recovery).

    Speed = clamp(sqrt(2 acc remaining), min_rotational_vel, max_rotational_vel), ramped by at
    most ``rotational_acc_lim`` per second. RUNNING while turning; SUCCESS when the turned angle
    is within ``yaw_goal_tolerance`` of the target; FAILURE (``error_code_id``) when
    ``time_allowance`` runs out (TIMEOUT) or the footprint would touch a lethal cell (or enter
    inscribed cost) within the next ``simulate_ahead_time`` seconds of turning
    (COLLISION_AHEAD). A new run counts from zero.
    """

    INPUT_PORTS = {
        "spin_dist": PortInformation(float, False, "angle to turn, rad; sign gives direction", 1.57),
        "time_allowance": PortInformation(float, False, "s before giving up", 10.0),
        "max_rotational_vel": PortInformation(float, False, "rad/s", 1.0),
        "min_rotational_vel": PortInformation(float, False, "rad/s", 0.4),
        "rotational_acc_lim": PortInformation(float, False, "rad/s^2", 3.2),
        "yaw_goal_tolerance": PortInformation(float, False, "rad", 0.1),
        "simulate_ahead_time": PortInformation(float, False, "collision look-ahead, s", 2.0),
        "sim_granularity": PortInformation(float, False, "collision check step, rad", 0.017),
        "disable_collision_checks": PortInformation(bool, False, "skip footprint checks", False),
    }
    OUTPUT_PORTS = {**_CMD, **_ERR}
    DEFAULT_KEYS = {"cmd_vel": "cmd_vel", "error_code_id": "spin_error_code"}

    def initialise(self) -> None:
        self._start = self.clock.now()
        self._prev = self.robot.pose().theta
        self._turned = 0.0
        self._w = 0.0

    def update(self) -> Status:
        target = self.get_input("spin_dist")
        sign = 1.0 if target >= 0.0 else -1.0
        pose = self.robot.pose()
        self._turned += sign * angle_diff(pose.theta, self._prev)
        self._prev = pose.theta
        remaining = abs(target) - self._turned
        if remaining <= self.get_input("yaw_goal_tolerance"):
            self.stop_motion()
            self.report(BehaviorError.NONE, f"turned {self._turned:.2f} rad")
            return SUCCESS
        if self.clock.now() - self._start > self.get_input("time_allowance"):
            self.stop_motion()
            self.report(BehaviorError.TIMEOUT, f"time out after {self._turned:.2f} of "
                                               f"{abs(target):.2f} rad")
            return FAILURE
        acc = self.get_input("rotational_acc_lim")
        w = math.sqrt(2.0 * acc * remaining)
        w = min(max(w, self.get_input("min_rotational_vel")), self.get_input("max_rotational_vel"))
        w = min(w, abs(self._w) + acc * self.control_period)
        if not self.get_input("disable_collision_checks"):
            ahead = min(remaining, w * self.get_input("simulate_ahead_time"))
            step = max(self.get_input("sim_granularity"), ahead / 20.0)
            n = max(1, int(math.ceil(ahead / step)))
            poses = (Pose2D(pose.x, pose.y, pose.theta + sign * ahead * k / n)
                     for k in range(1, n + 1))
            hit = self.first_collision(poses, pose)
            if hit is not None:
                self.stop_motion()
                self.report(BehaviorError.COLLISION_AHEAD,
                            f"blocked: cost {hit[1]} at yaw {hit[0].theta:.2f}")
                return FAILURE
        self._w = sign * w
        self.write("cmd_vel", Twist(0.0, 0.0, self._w))
        self.say("turned {:.2f} of {:.2f} rad", self._turned, abs(target))
        return RUNNING


class DriveOnHeading(RecoveryAction):
    """Drive straight ``dist_to_travel`` metres at ``speed`` m/s along the current heading
    (negative values drive backwards), then stop (Nav2 ``DriveOnHeading``).

    RUNNING while driving; SUCCESS when the distance is covered; FAILURE on ``time_allowance``
    (TIMEOUT), on a lethal cell under the footprint (or newly inscribed cost) within
    ``simulate_ahead_time`` s of travel (COLLISION_AHEAD), or when distance and speed have different signs (INVALID_INPUT).
    """

    INPUT_PORTS = {
        "dist_to_travel": PortInformation(float, False, "m; negative = backwards", 0.15),
        "speed": PortInformation(float, False, "m/s; same sign as the distance", 0.025),
        "time_allowance": PortInformation(float, False, "s before giving up", 10.0),
        "simulate_ahead_time": PortInformation(float, False, "collision look-ahead, s", 2.0),
        "disable_collision_checks": PortInformation(bool, False, "skip footprint checks", False),
    }
    OUTPUT_PORTS = {**_CMD, **_ERR}
    DEFAULT_KEYS = {"cmd_vel": "cmd_vel", "error_code_id": "drive_on_heading_error_code"}

    def distance_and_speed(self) -> tuple[float, float]:
        return self.get_input("dist_to_travel"), self.get_input("speed")

    def initialise(self) -> None:
        self._start_pose = self.robot.pose()
        self._start = self.clock.now()

    def update(self) -> Status:
        dist, speed = self.distance_and_speed()
        if dist * speed < 0.0 or speed == 0.0:
            self.stop_motion()
            self.report(BehaviorError.INVALID_INPUT, f"distance {dist} and speed {speed} must be "
                                                     f"non-zero with the same sign")
            return FAILURE
        pose = self.robot.pose()
        travelled = pose.distance_to(self._start_pose)
        remaining = abs(dist) - travelled
        if remaining <= 1e-3:
            self.stop_motion()
            self.report(BehaviorError.NONE, f"drove {travelled:.2f} m")
            return SUCCESS
        if self.clock.now() - self._start > self.get_input("time_allowance"):
            self.stop_motion()
            self.report(BehaviorError.TIMEOUT, f"time out after {travelled:.2f} m")
            return FAILURE
        direction = 1.0 if dist > 0.0 else -1.0
        v = min(abs(speed), remaining / self.control_period)
        if not self.get_input("disable_collision_checks"):
            ahead = min(remaining, abs(speed) * self.get_input("simulate_ahead_time"))
            n = max(1, int(math.ceil(ahead / 0.05)))
            poses = (pose.compose(Pose2D(direction * ahead * k / n, 0.0, 0.0))
                     for k in range(1, n + 1))
            hit = self.first_collision(poses, pose)
            if hit is not None:
                self.stop_motion()
                self.report(BehaviorError.COLLISION_AHEAD,
                            f"blocked: cost {hit[1]} {hit[0].distance_to(pose):.2f} m ahead")
                return FAILURE
        self.write("cmd_vel", Twist(direction * v, 0.0, 0.0))
        self.say("drove {:.2f} of {:.2f} m", travelled, abs(dist))
        return RUNNING


class BackUp(DriveOnHeading):
    """Drive straight backwards ``backup_dist`` metres at ``backup_speed`` m/s (both positive),
    collision-checked like DriveOnHeading (Nav2 ``BackUp``)."""

    INPUT_PORTS = {
        "backup_dist": PortInformation(float, False, "m to back up", 0.15),
        "backup_speed": PortInformation(float, False, "m/s", 0.025),
        "time_allowance": PortInformation(float, False, "s before giving up", 10.0),
        "simulate_ahead_time": PortInformation(float, False, "collision look-ahead, s", 2.0),
        "disable_collision_checks": PortInformation(bool, False, "skip footprint checks", False),
    }
    DEFAULT_KEYS = {"cmd_vel": "cmd_vel", "error_code_id": "backup_error_code"}

    def distance_and_speed(self) -> tuple[float, float]:
        return -abs(self.get_input("backup_dist")), -abs(self.get_input("backup_speed"))


def ring_candidates(center: Pose2D, min_distance: float, max_distance: float, radial_step: float,
                    angular_samples: int) -> list[Pose2D]:
    """Poses on rings around ``center``, each facing away from it."""
    out = []
    radii = np.arange(min_distance, max_distance + 1e-9, max(radial_step, 1e-3))
    for r in radii:
        for k in range(angular_samples):
            a = center.theta + 2.0 * math.pi * k / angular_samples
            out.append(Pose2D(center.x + r * math.cos(a), center.y + r * math.sin(a),
                              math.atan2(math.sin(a), math.cos(a))))
    return out


# spacing of the footprint checks along a candidate arc while searching, m
ARC_SEARCH_STEP = 0.03
# clear arcs compared for clearance, and the clearance (m) beyond which any arc will do
ARC_CHOICES = 8
# arc searches per run: a blocked arc is replaced by a new one from where the robot stands
ARC_SEARCHES = 3
ARC_GAP_ENOUGH = 0.1


def arc_poses(pose: Pose2D, x: float, y: float, step: float,
              max_turn: float = 0.5 * math.pi, end_only: bool = False) -> list[Pose2D] | None:
    """Poses every ``step`` metres along the circular arc a differential drive follows from
    ``pose`` to the point (x, y), forwards if the point is ahead, backwards if behind; the last
    one is at the point with the heading the arc ends with (``end_only``: just that one). None
    when the arc would turn by more than ``max_turn`` or the point is (nearly) abeam or at the
    robot."""
    rel = Pose2D(x, y, 0.0).relative_to(pose)
    d2 = rel.x * rel.x + rel.y * rel.y
    turn = 2.0 * math.atan2(abs(rel.y), abs(rel.x))
    if d2 < 1e-6 or turn > max_turn:
        return None
    k = 2.0 * rel.y / d2                                    # curvature: w = v * k either way
    length = turn / abs(k) if abs(k) > 1e-9 else abs(rel.x)
    direction = 1.0 if rel.x > 0.0 else -1.0
    n = max(1, int(math.ceil(length / step)))
    out = []
    for j in range(n if end_only else 1, n + 1):
        s = direction * length * j / n                      # signed distance along the arc
        a = k * s
        lx = math.sin(a) / k if abs(k) > 1e-9 else s
        ly = (1.0 - math.cos(a)) / k if abs(k) > 1e-9 else 0.0
        out.append(pose.compose(Pose2D(lx, ly, a)))
    return out


class TemporaryGoal(RecoveryAction):
    """Get out of a tight spot: find a free, reachable pose near the robot and drive there.

    Candidates lie on rings from ``min_distance`` to ``search_radius`` metres, facing away from
    the robot. Those whose footprint cost is below the inscribed cost are ranked by openness
    plus turn (cost/253 + turn/90 degrees, where a pose straight ahead or behind needs no turn)
    and tried in that order, at most ``max_plans_per_tick`` planner calls per tick, until one
    has a plan. The controller then follows the plan; if it finds no valid command (its
    footprint already in inflated cost, say), the node drives there itself by pure pursuit at
    ``escape_speed``, footprint-checked. SUCCESS when the goal is reported reached or the robot
    is within ``xy_goal_tolerance``. FAILURE: NO_FREE_POSE, COLLISION_AHEAD (no valid command
    and the own pursuit is blocked too), TIMEOUT (``time_allowance`` spent, or no progress of
    ``required_movement_radius`` within ``movement_time_allowance``). ``temporary_goal`` holds
    the chosen pose.
    """

    INPUT_PORTS = {
        "search_radius": PortInformation(float, False, "farthest candidate, m", 1.5),
        "min_distance": PortInformation(float, False, "nearest candidate, m", 0.4),
        "radial_step": PortInformation(float, False, "spacing of the rings, m", 0.2),
        "angular_samples": PortInformation(int, False, "candidates per ring", 16),
        "costmap": PortInformation(str, False, "costmap to score candidates on", "local"),
        "planner_id": PortInformation(str, False, "planner for the way there", "GridBased"),
        "controller_id": PortInformation(str, False, "controller for the way there", "FollowPath"),
        "max_plans_per_tick": PortInformation(int, False, "planner calls per tick", 4),
        "goal": PortInformation(Pose2D, False, "navigation goal: among equally open poses, "
                                               "those nearer to it come first"),
        "arc_first": PortInformation(bool, False,
                                     "first try poses one collision-free arc away, driven "
                                     "without the planner", True),
        "xy_goal_tolerance": PortInformation(float, False, "m", 0.15),
        "time_allowance": PortInformation(float, False, "s before giving up", 30.0),
        "escape_speed": PortInformation(float, False,
                                        "m/s of the own pursuit used when the controller finds "
                                        "no valid command (0 = never)", 0.1),
        "lookahead": PortInformation(float, False, "own pursuit look-ahead, m", 0.4),
        "max_rotational_vel": PortInformation(float, False, "own pursuit, rad/s", 1.0),
        "simulate_ahead_time": PortInformation(float, False, "collision look-ahead, s", 1.0),
        "disable_collision_checks": PortInformation(bool, False, "skip footprint checks", False),
        "required_movement_radius": PortInformation(float, False, "progress radius, m", 0.1),
        "movement_time_allowance": PortInformation(float, False, "s to make progress; 0 = off",
                                                   5.0),
    }
    OUTPUT_PORTS = {**_CMD, **_ERR,
                    "temporary_goal": PortInformation(Pose2D, False, "the pose chosen")}
    DEFAULT_KEYS = {"cmd_vel": "cmd_vel", "error_code_id": "temporary_goal_error_code",
                    "temporary_goal": "temporary_goal", "goal": "goal"}
    CHOICES = {"costmap": ("local", "global")}

    def setup(self, **kwargs: Any) -> None:
        super().setup(**kwargs)
        self.planners = self.component(kwargs, "planners")
        self.controllers = self.component(kwargs, "controllers")

    def initialise(self) -> None:
        self._start = self.clock.now()
        self._candidates: list[Pose2D] | None = None
        self._goal: Pose2D | None = None
        self._controller = None
        self._own = False
        self._arcs_tried = not self.get_input("arc_first") or self.get_input("escape_speed") <= 0
        self._arc_mode = False
        self._arc_searches = 0

    def _rank(self, pose: Pose2D) -> list[Pose2D]:
        handle = self.costmaps.get(self.get_input("costmap")) or self.collision_map()
        scored = []
        for c in ring_candidates(pose, self.get_input("min_distance"),
                                 self.get_input("search_radius"), self.get_input("radial_step"),
                                 self.get_input("angular_samples")):
            cost = int(handle.footprint_cost(c.x, c.y, c.theta)) if handle is not None else 0
            if 0 <= cost < INSCRIBED_INFLATED_OBSTACLE:
                # A differential drive reaches poses ahead or behind with gentle arcs, while a
                # pose abeam needs a sharp turn that sweeps a corner into whatever is beside it.
                bearing = abs(angle_diff(heading_to(pose, c), pose.theta))
                turn = min(bearing, math.pi - bearing)
                score = cost / INSCRIBED_INFLATED_OBSTACLE + turn / (0.5 * math.pi)
                scored.append((round(score, 2), c.distance_to(pose), c))
        scored.sort(key=lambda t: t[:2])
        return [t[2] for t in scored]

    def _to_goal(self, pose: Pose2D) -> float:
        """Distance from ``pose`` to the navigation goal in tenths of a metre (0 without one)."""
        goal = self.read("goal")
        return round(pose.distance_to(goal), 1) if isinstance(goal, Pose2D) else 0.0

    def _arc_goal(self, pose: Pose2D) -> Pose2D | None:
        """The best pose one arc away (forwards or backwards, turning at most 90 degrees) whose
        footprint is free at the arc's end and clear all along it; None if there is none.
        Ranked by openness at the end (in tenths of the inscribed cost), then by the distance
        left to the navigation goal (tenths of a metre; when one is known), then arc length."""
        handle = self.costmaps.get(self.get_input("costmap")) or self.collision_map()
        ends = []
        for c in ring_candidates(pose, self.get_input("min_distance"),
                                 self.get_input("search_radius"), self.get_input("radial_step"),
                                 self.get_input("angular_samples")):
            last = arc_poses(pose, c.x, c.y, ARC_SEARCH_STEP, end_only=True)
            if last is None:
                continue
            end = last[0]
            cost = int(handle.footprint_cost(end.x, end.y, end.theta)) if handle else 0
            if 0 <= cost < INSCRIBED_INFLATED_OBSTACLE:
                half = 0.5 * abs(angle_diff(end.theta, pose.theta))   # arc from its chord
                length = pose.distance_to(end) * (half / math.sin(half) if half > 1e-9 else 1.0)
                ends.append((round(cost / INSCRIBED_INFLATED_OBSTACLE, 1), self._to_goal(end),
                             round(length, 3), end, c))
        ends.sort(key=lambda t: t[:3])
        if self.get_input("disable_collision_checks"):
            return ends[0][3] if ends else None
        # Of the first few clear arcs, take the one that keeps farthest from lethal cells
        # (the gentlest way out of a tight spot).
        best, best_gap, clear = None, -math.inf, 0
        for _, _, _, end, c in ends:
            arc = arc_poses(pose, c.x, c.y, ARC_SEARCH_STEP) or []
            if self.first_collision(arc, pose) is not None:
                continue
            gaps = clearances(handle, arc) if handle is not None else None
            gap = min(float(np.min(gaps)), ARC_GAP_ENOUGH) if gaps is not None else 0.0
            if gap > best_gap + 1e-3:
                best, best_gap = end, gap
            clear += 1
            if clear >= ARC_CHOICES or best_gap >= ARC_GAP_ENOUGH:
                break
        return best

    def update(self) -> Status:
        pose = self.robot.pose()
        if self.clock.now() - self._start > self.get_input("time_allowance"):
            self.stop_motion()
            self.report(BehaviorError.TIMEOUT, "time out")
            return FAILURE
        if self._goal is None:
            return self._search(pose)
        return self._drive(pose)

    def _chosen(self, pose: Pose2D, goal: Pose2D, how: str) -> None:
        self._goal = goal
        self.start_progress_check(pose)
        self.write("temporary_goal", goal)
        self.say(f"temporary goal ({goal.x:.2f}, {goal.y:.2f}) {how}")

    def _search(self, pose: Pose2D) -> Status:
        self.write("cmd_vel", Twist.zero())
        if not self._arcs_tried:
            self._arcs_tried = True
            goal = self._arc_goal(pose)
            self._arc_searches += 1
            if goal is not None:
                self._own = self._arc_mode = True  # one arc: our own checked motion, no planner
                self._chosen(pose, goal, "one arc away")
                return RUNNING
        if self._candidates is None:
            self._candidates = self._rank(pose)
        planner = self.planners.get(self.get_input("planner_id"))
        controller = self.controllers.get(self.get_input("controller_id"))
        if planner is None or controller is None:
            self.report(BehaviorError.INVALID_INPUT, "unknown planner or controller id")
            return FAILURE
        for _ in range(self.get_input("max_plans_per_tick")):
            if not self._candidates:
                self.stop_motion()
                self.report(BehaviorError.NO_FREE_POSE, "no reachable free pose nearby")
                return FAILURE
            cand = self._candidates.pop(0)
            result = planner.make_plan(pose, cand)
            if result.ok and result.path is not None and len(result.path) > 0:
                self._controller = controller
                controller.reset()
                controller.set_plan(result.path)
                self._chosen(pose, cand, "by plan")
                break
        return RUNNING

    def _drive(self, pose: Pose2D) -> Status:
        assert self._goal is not None
        reached = pose.distance_to(self._goal) <= self.get_input("xy_goal_tolerance")
        result = None
        if self._controller is not None and not self._own:
            result = self._controller.compute_velocity(pose, self.robot.velocity())
            reached = (reached or result.status == "goal_reached"
                       or self._controller.is_goal_reached())
        if reached:
            self.stop_motion()
            self.report(BehaviorError.NONE, "reached the temporary goal")
            return SUCCESS
        if self.no_progress(pose):
            self.stop_motion()
            self.report(BehaviorError.TIMEOUT, "no progress toward the temporary goal")
            return FAILURE
        if result is not None and not result.status.startswith("no_valid"):
            cmd = result.cmd
        else:
            # One arc chosen, or the controller refuses to move from here (its footprint
            # already touches inflated cost, say): drive with our own footprint-checked
            # pursuit, which may leave inscribed cost. Once chosen, keep it until the goal.
            speed = self.get_input("escape_speed")
            # Aim at the temporary goal itself: over these short distances the straight
            # pursuit arc is the gentlest way there (the plan may start with a sharp turn).
            own, _, hit = (self.pursue(pose, [self._goal], 0, self._goal, speed,
                                       self.get_input("lookahead"),
                                       self.get_input("max_rotational_vel"))
                           if speed > 0.0 else (None, 0, None))
            if own is None and self._arc_mode and self._arc_searches < ARC_SEARCHES:
                # the costmap changed under the arc (a new obstacle, sensor noise along a
                # wall): look for another arc from here
                self._goal, self._arcs_tried, self._arc_mode = None, False, False
                self.stop_motion()
                self.say("arc blocked; searching again")
                return RUNNING
            if own is None:
                self.stop_motion()
                why = f"blocked: cost {hit[1]}" if hit is not None else "no escape speed"
                status = result.status if result is not None else "one arc"
                self.report(BehaviorError.COLLISION_AHEAD, f"controller: {status}; {why}")
                return FAILURE
            self._own, cmd = True, own
        self.write("cmd_vel", cmd)
        self.say("{:.2f} m to the temporary goal" + (" (own pursuit)" if self._own else ""),
                 pose.distance_to(self._goal))
        return RUNNING

    def terminate(self, new_status: Status) -> None:
        super().terminate(new_status)
        if getattr(self, "_controller", None) is not None:
            self._controller.reset()  # the main FollowPath sets its own plan again
            self._controller = None


class BackOffToPreviousPose(RecoveryAction):
    """Drive back along the trail the robot came by to the pose visited ``distance`` metres ago.

    The trail is ``pose_history`` (RecordPoseHistory). It starts at the stored pose nearest the
    robot, so repeated back-offs go further back. If the pose ``distance`` back still has its
    footprint in inscribed cost (half-way out of a dead end, say), the target moves further
    back along the trail to the first free pose, at most ``max_distance`` metres back. The
    robot pursues the trail in reverse (pure pursuit with negative speed, ``lookahead`` m),
    footprint-checked ahead (leaving inscribed cost is allowed). SUCCESS within
    ``xy_goal_tolerance`` of the target; FAILURE: NO_POSE_HISTORY, COLLISION_AHEAD, TIMEOUT
    (``time_allowance`` spent, or no progress as in TemporaryGoal).
    """

    INPUT_PORTS = {
        "distance": PortInformation(float, False, "how far back along the trail, m", 0.5),
        "max_distance": PortInformation(float, False,
                                        "how far back at most to reach a pose free of "
                                        "inscribed cost, m", 2.0),
        "speed": PortInformation(float, False, "m/s", 0.1),
        "max_rotational_vel": PortInformation(float, False, "rad/s", 1.0),
        "lookahead": PortInformation(float, False, "pure-pursuit look-ahead, m", 0.25),
        "xy_goal_tolerance": PortInformation(float, False, "m", 0.08),
        "time_allowance": PortInformation(float, False, "s before giving up", 20.0),
        "simulate_ahead_time": PortInformation(float, False, "collision look-ahead, s", 1.0),
        "disable_collision_checks": PortInformation(bool, False, "skip footprint checks", False),
        "pose_history": PortInformation(list, False, "Pose2D trail, oldest first"),
        "required_movement_radius": PortInformation(float, False, "progress radius, m", 0.1),
        "movement_time_allowance": PortInformation(float, False, "s to make progress; 0 = off",
                                                   5.0),
    }
    OUTPUT_PORTS = {**_CMD, **_ERR}
    DEFAULT_KEYS = {"cmd_vel": "cmd_vel", "error_code_id": "back_off_error_code",
                    "pose_history": "pose_history"}

    def initialise(self) -> None:
        self._start = self.clock.now()
        self._trail = self._plan_trail(self.robot.pose(), self.read("pose_history") or [])
        self._i = 0
        self.start_progress_check(self.robot.pose())

    def _plan_trail(self, pose: Pose2D, history: list[Pose2D]) -> list[Pose2D]:
        """Poses from the one nearest the robot back ``distance`` metres (or on to the first
        pose free of inscribed cost, within ``max_distance``), newest first."""
        if not history:
            return []
        near = min(range(len(history)), key=lambda i: history[i].distance_to(pose))
        want = self.get_input("distance")
        limit = max(want, self.get_input("max_distance"))
        handle = self.collision_map()
        trail, travelled = [], 0.0
        prev = history[near]
        for p in reversed(history[:near + 1]):
            travelled += p.distance_to(prev)
            if travelled > limit + 1e-9:
                break
            trail.append(p)
            prev = p
            if travelled >= want and (handle is None or 0 <= int(handle.footprint_cost(
                    p.x, p.y, p.theta)) < INSCRIBED_INFLATED_OBSTACLE):
                break
        return trail if travelled > 0.0 else []

    def update(self) -> Status:
        pose = self.robot.pose()
        if not self._trail:
            self.stop_motion()
            self.report(BehaviorError.NO_POSE_HISTORY, "no trail to back off along")
            return FAILURE
        target = self._trail[-1]
        if pose.distance_to(target) <= self.get_input("xy_goal_tolerance"):
            self.stop_motion()
            self.report(BehaviorError.NONE, "back at the previous pose")
            return SUCCESS
        if self.clock.now() - self._start > self.get_input("time_allowance") \
                or self.no_progress(pose):
            self.stop_motion()
            self.report(BehaviorError.TIMEOUT, "time out or no progress")
            return FAILURE
        cmd, self._i, hit = self.pursue(pose, self._trail, self._i, target,
                                        self.get_input("speed"), self.get_input("lookahead"),
                                        self.get_input("max_rotational_vel"))
        if cmd is None:
            assert hit is not None
            self.stop_motion()
            self.report(BehaviorError.COLLISION_AHEAD,
                        f"blocked: cost {hit[1]} {hit[0].distance_to(pose):.2f} m away")
            return FAILURE
        self.write("cmd_vel", cmd)
        self.say("{:.2f} m to the previous pose (heading {:.2f})", pose.distance_to(target),
                 heading_to(pose, target))
        return RUNNING
