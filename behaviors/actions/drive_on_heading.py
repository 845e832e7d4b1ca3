"""DriveOnHeading and BackUp: drive straight, footprint-checked (Nav2)."""

from __future__ import annotations

import math

from behaviors.actions.recovery_action import (RecoveryAction, CMD_VEL_OUT, ERROR_CODE_OUT,
                                              OBSERVED_IN)
from behaviors.base import RUNNING, Port, PortInformation, Status
from navcore.error_codes import BackUpError, DriveOnHeadingError
from navcore.types import Pose2D, Twist


class DriveOnHeading(RecoveryAction):
    """Drive straight ``dist_to_travel`` metres at ``speed`` m/s along the current heading
    (negative values drive backwards), then stop (Nav2 ``DriveOnHeading``).

    RUNNING while driving; SUCCESS when the distance is covered; FAILURE on ``time_allowance``
    (TIMEOUT), on a lethal cell under the footprint (or newly inscribed cost) within
    ``simulate_ahead_time`` s of travel (COLLISION_AHEAD), on space there that the sensors have
    not seen free within ``observed_within`` s (UNOBSERVED_SPACE: behind the laser's field of
    view, say), or when distance and speed have different signs (INVALID_INPUT).
    """

    INPUT_PORTS = {
        "dist_to_travel": PortInformation(float, False, "m; negative = backwards", 0.15),
        "speed": PortInformation(float, False, "m/s; same sign as the distance", 0.025),
        "time_allowance": Port(float, False, "s before giving up", 10.0, low=0.0),
        "simulate_ahead_time": Port(float, False, "collision look-ahead, s", 2.0, low=0.0),
        "disable_collision_checks": PortInformation(bool, False, "skip footprint checks", False),
        **OBSERVED_IN,
    }
    OUTPUT_PORTS = {**CMD_VEL_OUT, **ERROR_CODE_OUT}
    DEFAULT_KEYS = {"cmd_vel": "cmd_vel", "error_code_id": "drive_on_heading_error_code"}
    ERRORS: type[DriveOnHeadingError] | type[BackUpError] = DriveOnHeadingError  # Nav2's numbers

    def distance_and_speed(self) -> tuple[float, float]:
        return self.get_input("dist_to_travel"), self.get_input("speed")

    def initialise(self) -> None:
        self._start_pose = self.robot.pose()
        self._start = self.clock.now()

    def update(self) -> Status:
        dist, speed = self.distance_and_speed()
        if dist * speed < 0.0 or speed == 0.0:
            return self.finish(self.ERRORS.INVALID_INPUT,
                               f"distance {dist} and speed {speed} must be non-zero with the "
                               f"same sign")
        pose = self.robot.pose()
        travelled = pose.distance_to(self._start_pose)
        remaining = abs(dist) - travelled
        if remaining <= 1e-3:
            return self.finish(self.ERRORS.NONE, f"drove {travelled:.2f} m")
        if self.clock.now() - self._start > self.get_input("time_allowance"):
            return self.finish(self.ERRORS.TIMEOUT, f"time out after {travelled:.2f} m")
        direction = 1.0 if dist > 0.0 else -1.0
        v = min(abs(speed), remaining / self.control_period)
        if not self.get_input("disable_collision_checks"):
            ahead = min(remaining, abs(speed) * self.get_input("simulate_ahead_time"))
            n = max(1, int(math.ceil(ahead / 0.05)))
            poses = [pose.compose(Pose2D(direction * ahead * k / n, 0.0, 0.0))
                     for k in range(1, n + 1)]
            hit = self.first_collision(poses, pose)
            if hit is not None:
                return self.finish(self.ERRORS.COLLISION_AHEAD,
                                   f"blocked: cost {hit[1]} {hit[0].distance_to(pose):.2f} m ahead")
            blind = self.first_unobserved(poses, pose)
            if blind is not None:
                return self.finish(self.ERRORS.UNOBSERVED_SPACE,
                                   f"not observed free within "
                                   f"{self.get_input('observed_within')} s: {blind[1]:.2f} m ahead")
        self.write("cmd_vel", Twist(direction * v, 0.0, 0.0))
        self.say("drove {:.2f} of {:.2f} m", travelled, abs(dist))
        return RUNNING


class BackUp(DriveOnHeading):
    """Drive straight backwards ``backup_dist`` metres at ``backup_speed`` m/s (both positive),
    collision-checked like DriveOnHeading (Nav2 ``BackUp``)."""

    INPUT_PORTS = {
        "backup_dist": PortInformation(float, False, "m to back up", 0.15),
        "backup_speed": Port(float, False, "m/s", 0.025, low=0.0),
        "time_allowance": Port(float, False, "s before giving up", 10.0, low=0.0),
        "simulate_ahead_time": Port(float, False, "collision look-ahead, s", 2.0, low=0.0),
        "disable_collision_checks": PortInformation(bool, False, "skip footprint checks", False),
        **OBSERVED_IN,
    }
    DEFAULT_KEYS = {"cmd_vel": "cmd_vel", "error_code_id": "backup_error_code"}
    ERRORS = BackUpError

    def distance_and_speed(self) -> tuple[float, float]:
        return -abs(self.get_input("backup_dist")), -abs(self.get_input("backup_speed"))
