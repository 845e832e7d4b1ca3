"""Spin: turn in place, footprint-checked (Nav2, rotate_recovery)."""

from __future__ import annotations

import math

from behaviors.actions.recovery_action import (RecoveryAction, CMD_VEL_OUT, ERROR_CODE_OUT,
                                              OBSERVED_IN)
from behaviors.base import RUNNING, Port, PortInformation, Status
from navcore.error_codes import SpinError
from navcore.types import Pose2D, Twist, angle_diff


class Spin(RecoveryAction):
    """Turn in place by ``spin_dist`` radians (sign = direction), then stop (rotate_recovery).

    Speed = clamp(sqrt(2 acc remaining), min_rotational_vel, max_rotational_vel), ramped by at
    most ``rotational_acc_lim`` per second. RUNNING while turning; SUCCESS when the turned angle
    is within ``yaw_goal_tolerance`` of the target; FAILURE (``error_code_id``) when
    ``time_allowance`` runs out (TIMEOUT) or the footprint would touch a lethal cell (or enter
    inscribed cost) within the next ``simulate_ahead_time`` seconds of turning
    (COLLISION_AHEAD), or when the footprint would sweep (outside where it stands: the corners of a
    non-round robot) into space last seen occupied (UNOBSERVED_SPACE; with ``allow_unknown:
    false`` also into space not observed free within ``observed_within`` s). A new run counts
    from zero.
    """

    INPUT_PORTS = {
        "spin_dist": PortInformation(float, False, "angle to turn, rad; sign gives direction", 1.57),
        "time_allowance": Port(float, False, "s before giving up", 10.0, low=0.0),
        "max_rotational_vel": Port(float, False, "rad/s", 1.0, low=0.0),
        "min_rotational_vel": Port(float, False, "rad/s", 0.4, low=0.0),
        "rotational_acc_lim": Port(float, False, "rad/s^2", 3.2, low=0.0),
        "yaw_goal_tolerance": Port(float, False, "rad", 0.1, low=0.0),
        "simulate_ahead_time": Port(float, False, "collision look-ahead, s", 2.0, low=0.0),
        "sim_granularity": Port(float, False, "collision check step, rad", 0.017, low=0.001),
        "disable_collision_checks": PortInformation(bool, False, "skip footprint checks", False),
        **OBSERVED_IN,
        # a turn sweeps only a band around the body (a rectangle's corners), and turning is how
        # a robot looks behind itself: never-seen space will do, space last seen occupied not
        "allow_unknown": PortInformation(bool, False, "also sweep space never seen (or seen "
                                                      "free long ago), never space last seen "
                                                      "occupied", True),
    }
    OUTPUT_PORTS = {**CMD_VEL_OUT, **ERROR_CODE_OUT}
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
            return self.finish(SpinError.NONE, f"turned {self._turned:.2f} rad")
        if self.clock.now() - self._start > self.get_input("time_allowance"):
            return self.finish(SpinError.TIMEOUT, f"time out after {self._turned:.2f} of "
                                                      f"{abs(target):.2f} rad")
        acc = self.get_input("rotational_acc_lim")
        w = math.sqrt(2.0 * acc * remaining)
        w = min(max(w, self.get_input("min_rotational_vel")), self.get_input("max_rotational_vel"))
        w = min(w, abs(self._w) + acc * self.control_period)
        if not self.get_input("disable_collision_checks"):
            ahead = min(remaining, w * self.get_input("simulate_ahead_time"))
            step = max(self.get_input("sim_granularity"), ahead / 20.0)
            n = max(1, int(math.ceil(ahead / step)))
            poses = [Pose2D(pose.x, pose.y, pose.theta + sign * ahead * k / n)
                     for k in range(1, n + 1)]
            hit = self.first_collision(poses, pose)
            if hit is not None:
                return self.finish(SpinError.COLLISION_AHEAD,
                                   f"blocked: cost {hit[1]} at yaw {hit[0].theta:.2f}")
            blind = self.first_unobserved(poses, pose)
            if blind is not None:
                return self.finish(SpinError.UNOBSERVED_SPACE,
                                   f"sweep not observed free within "
                                   f"{self.get_input('observed_within')} s "
                                   f"at yaw {blind[0].theta:.2f}")
        self._w = sign * w
        self.write("cmd_vel", Twist(0.0, 0.0, self._w))
        self.say("turned {:.2f} of {:.2f} rad", self._turned, abs(target))
        return RUNNING
