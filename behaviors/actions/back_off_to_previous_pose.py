"""BackOffToPreviousPose: drive back along the recorded trail."""

from __future__ import annotations

from behaviors.actions.recovery_action import (RecoveryAction, CMD_VEL_OUT, ERROR_CODE_OUT,
                                              OBSERVED_IN, UNOBSERVED)
from behaviors.base import FAILURE, RUNNING, Port, PortInformation, Status
from navcore.error_codes import RecoveryError
from navcore.motion.geometry import heading_to
from navcore.motion.trail import back_off_trail
from navcore.types import Pose2D


class BackOffToPreviousPose(RecoveryAction):
    """Drive back along the trail the robot came by to the pose visited ``distance`` metres ago.

    The trail is ``pose_history`` (RecordPoseHistory). It starts at the stored pose nearest the
    robot, so repeated back-offs go further back. If the pose ``distance`` back still has its
    footprint in inscribed cost (half-way out of a dead end, say), the target moves further
    back along the trail to the first free pose, at most ``max_distance`` metres back. The
    robot pursues the trail in reverse (pure pursuit with negative speed, ``lookahead`` m),
    footprint-checked ahead (leaving inscribed cost is allowed) and only into space observed free
    within ``observed_within`` s. SUCCESS within ``xy_goal_tolerance`` of the target; FAILURE:
    NO_POSE_HISTORY, COLLISION_AHEAD, UNOBSERVED_SPACE, TIMEOUT (``time_allowance`` spent, or no
    progress as in TemporaryGoal).
    """

    INPUT_PORTS = {
        "distance": Port(float, False, "how far back along the trail, m", 0.5, low=0.0),
        "max_distance": Port(float, False,
                                        "how far back at most to reach a pose free of "
                                        "inscribed cost, m", 2.0, low=0.0),
        "speed": PortInformation(float, False, "m/s", 0.1),
        "max_rotational_vel": Port(float, False, "rad/s", 1.0, low=0.0),
        "lookahead": Port(float, False, "pure-pursuit look-ahead, m", 0.25, low=0.0),
        "xy_goal_tolerance": Port(float, False, "m", 0.08, low=0.0),
        "time_allowance": Port(float, False, "s before giving up", 20.0, low=0.0),
        "simulate_ahead_time": Port(float, False, "collision look-ahead, s", 1.0, low=0.0),
        "disable_collision_checks": PortInformation(bool, False, "skip footprint checks", False),
        **OBSERVED_IN,
        "pose_history": PortInformation(list, False, "Pose2D trail, oldest first"),
        "required_movement_radius": Port(float, False, "progress radius, m", 0.1, low=0.0),
        "movement_time_allowance": Port(float, False, "s to make progress; 0 = off",
                                                   5.0, low=0.0),
    }
    OUTPUT_PORTS = {**CMD_VEL_OUT, **ERROR_CODE_OUT}
    DEFAULT_KEYS = {"cmd_vel": "cmd_vel", "error_code_id": "back_off_error_code",
                    "pose_history": "pose_history"}

    def initialise(self) -> None:
        self._start = self.clock.now()
        self._trail = back_off_trail(self.read("pose_history") or [], self.robot.pose(),
                                     self.get_input("distance"), self.get_input("max_distance"),
                                     self.collision_map())
        self._i = 0
        self.start_progress_check(self.robot.pose())

    def update(self) -> Status:
        pose = self.robot.pose()
        if not self._trail:
            return self.finish(RecoveryError.NO_POSE_HISTORY, "no trail to back off along")
        target = self._trail[-1]
        if pose.distance_to(target) <= self.get_input("xy_goal_tolerance"):
            return self.finish(RecoveryError.NONE, "back at the previous pose")
        if self.clock.now() - self._start > self.get_input("time_allowance") \
                or self.no_progress(pose):
            return self.finish(RecoveryError.TIMEOUT, "time out or no progress")
        cmd, self._i, hit = self.pursue(pose, self._trail, self._i, target,
                                        self.get_input("speed"), self.get_input("lookahead"),
                                        self.get_input("max_rotational_vel"))
        if cmd is None:
            assert hit is not None
            self.stop_motion()
            if hit[1] == UNOBSERVED:
                self.report(RecoveryError.UNOBSERVED_SPACE,
                            f"not observed free within {self.get_input('observed_within')} s: "
                            f"{hit[0].distance_to(pose):.2f} m away")
            else:
                self.report(RecoveryError.COLLISION_AHEAD,
                            f"blocked: cost {hit[1]} {hit[0].distance_to(pose):.2f} m away")
            return FAILURE
        self.write("cmd_vel", cmd)
        self.say("{:.2f} m to the previous pose (heading {:.2f})", pose.distance_to(target),
                 heading_to(pose, target))
        return RUNNING
