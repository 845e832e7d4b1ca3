"""Recoveries: costmap clearing, Spin / BackUp / DriveOnHeading / Wait (Nav2 and rotate_recovery
semantics), and the guide's extra SMACH-style ones, TemporaryGoal and BackOffToPreviousPose.

Motion recoveries write ``cmd_vel`` one control period at a time, check the robot footprint on
the costmap (``footprint_cost``) along the motion ahead, and fail with COLLISION_AHEAD rather than
drive into a lethal cell or from free space into inscribed cost (a robot already in inscribed
cost may move through it to get out). Every exit (finished or interrupted) leaves a zero command.
"""

from __future__ import annotations

import math
from enum import IntEnum
from typing import Any, ClassVar, Iterable

from behaviors.base import INVALID, RUNNING, Leaf, PortInformation, Recovery, Status
from behaviors.clearance import clearances
from navcore.costmap.cost_values import INSCRIBED_INFLATED_OBSTACLE, LETHAL_OBSTACLE, NO_INFORMATION
from navcore.controllers.progress import ProgressChecker
from navcore.types import Pose2D, Twist


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
        self._progress = ProgressChecker()

    def costmap_handles(self, which: str) -> list[Any]:
        names = ("local", "global") if which == "both" else (which,)
        return [self.costmaps[n] for n in names if self.costmaps.get(n) is not None]

    def collision_map(self) -> Any:
        """The costmap motion is checked on: the local one, else the global one."""
        return self.costmaps.get("local") or self.costmaps.get("global")

    def report(self, code: IntEnum, msg: str = "") -> None:
        outputs = self.output_ports()
        if "error_code_id" in outputs:
            self.write("error_code_id", int(code))
        if "error_msg" in outputs:  # Nav2 Kilted+: the reason as text, "" on success
            self.write("error_msg", "" if code == 0 else msg)
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
        self._progress.reset(pose, self.clock.now())

    def no_progress(self, pose: Pose2D) -> bool:
        """True when the robot stayed within ``required_movement_radius`` for longer than
        ``movement_time_allowance`` seconds (0 disables); a stuck robot gives up early."""
        allowance = self.get_input("movement_time_allowance")
        return allowance > 0.0 and self._progress.stalled(
            pose, self.clock.now(), self.get_input("required_movement_radius"), allowance)

    def stop_motion(self) -> None:
        if "cmd_vel" in self.output_ports():
            self.write("cmd_vel", Twist.zero())

    def terminate(self, new_status: Status) -> None:
        if self.status is RUNNING or new_status is not INVALID:
            self.stop_motion()


ERROR_CODE_OUT = {"error_code_id": PortInformation(int, False, "the action's Nav2 error code "
                                                              "(navcore.error_codes); 0 on success"),
                  "error_msg": PortInformation(str, False, "why it failed; empty on success")}


CMD_VEL_OUT = {"cmd_vel": PortInformation(Twist, True, "velocity command for this tick")}
