"""FollowPath: drive along the path with the controller (Nav2)."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from behaviors.base import FAILURE, INVALID, RUNNING, SUCCESS, Leaf, Port, PortInformation, Status
from navcore.controllers.progress import ProgressChecker
from navcore.controllers.result import ControlStatus
from navcore.error_codes import CONTROL_CODES, ControllerError
from behaviors.actions.recovery_action import OBSERVED_WITHIN
from navcore.controllers.rotation_shim import RotationShim, ShimParams, turn_toward_path
from navcore.motion.pursuit import swept_poses
from navcore.path_ops import TrackingFeedback, tracking_feedback
from navcore.types import Path, Pose2D, Twist

SHIM = ShimParams()  # Nav2's defaults
# looked up once: an Enum member is a slow class-attribute look-up, and update() runs every tick
_GOAL_REACHED, _NO_VALID = ControlStatus.GOAL_REACHED, ControllerError.NO_VALID_CONTROL


class FollowPath(Leaf):
    """Drive along ``path`` with the controller, one command per tick, until the goal is reached.

    * RUNNING while following; ``cmd_vel`` written every tick. A new ``path`` object is handed to
      the controller (``set_plan``) as it appears (so replanning takes effect at once).
    * SUCCESS when the controller reports the goal reached.
    * FAILURE with ``error_code_id``: INVALID_PATH (no path), INVALID_CONTROLLER,
      NO_VALID_CONTROL / PATIENCE_EXCEEDED (no valid command for longer than
      ``failure_tolerance`` s; within it the robot gets zero and the node keeps trying),
      FAILED_TO_MAKE_PROGRESS (moved less than ``required_movement_radius`` m in
      ``movement_time_allowance`` s; 0 disables, Nav2's SimpleProgressChecker).
    * ``rotate_to_heading``: Nav2's RotationShimController in front of the controller
      (navcore.controllers.rotation_shim): on each new path, while the path ahead
      (``forward_sampling_distance``) is more than ``angular_dist_threshold`` off the heading,
      turn on the spot at ``rotate_to_heading_angular_vel`` (``max_angular_accel``) instead of
      asking the controller, which could follow it backwards; a turn whose footprint hits the
      local costmap within ``simulate_ahead_time`` s counts as no valid command.
    * Whatever ``rotate_to_heading`` says, a command that drives backwards into space the
      sensors have not seen free within ``observed_within`` s (the ``observed_space`` memory,
      over ``simulate_ahead_time`` s of it; 0 = no check) is not sent: the robot turns toward
      the path ahead instead, or, if that is not off by more than the threshold (or blocked),
      gets no valid command. A local planner with ``min_vel_x`` < 0 may reverse only where the
      laser has looked.
    """

    INPUT_PORTS = {
        "path": PortInformation(Path, True, "path to follow"),
        "controller_id": PortInformation(str, False, "which controller (setup 'controllers' key)",
                                         "FollowPath"),
        "failure_tolerance": PortInformation(float, False,
                                             "s without a valid command before FAILURE; -1 never",
                                             0.0),
        "required_movement_radius": Port(float, False, "progress radius, m", 0.5, low=0.0),
        "movement_time_allowance": Port(float, False, "s to make progress; 0 = off",
                                                   10.0, low=0.0),
        "rotate_to_heading": PortInformation(bool, False, "turn to a new path's heading first "
                                                          "(RotationShimController)", False),
        "angular_dist_threshold": Port(float, False, "rad off the path ahead that makes it turn",
                                       SHIM.angular_dist_threshold, low=0.0, high=math.pi),
        "forward_sampling_distance": Port(float, False, "m along the path to aim at",
                                          SHIM.forward_sampling_distance, low=0.0),
        "rotate_to_heading_angular_vel": Port(float, False, "rad/s of the turn",
                                              SHIM.rotate_to_heading_angular_vel, low=0.0),
        "max_angular_accel": Port(float, False, "rad/s^2 of the turn", SHIM.max_angular_accel,
                                  low=0.0),
        "simulate_ahead_time": Port(float, False, "s of a turn or a reverse checked ahead",
                                    SHIM.simulate_ahead_time, low=0.0),
        "observed_within": Port(float, False, "s: reverse only into space the sensors saw free "
                                              "this recently (observed_space); 0 = no check",
                                OBSERVED_WITHIN, low=0.0),
    }
    OUTPUT_PORTS = {
        "cmd_vel": PortInformation(Twist, True, "velocity command for this tick"),
        "error_code_id": PortInformation(int, False, "a ControllerError; 0 on success"),
        "error_msg": PortInformation(str, False, "why following failed"),
        "tracking_feedback": PortInformation(TrackingFeedback, False,
                                             "tracking errors each tick (Nav2 main)"),
    }
    DEFAULT_KEYS = {"path": "path", "cmd_vel": "cmd_vel", "error_code_id": "follow_path_error_code",
                    "error_msg": "follow_path_error_msg"}
    _feedback_wired = False

    def setup(self, **kwargs: Any) -> None:
        self.clock = self.component(kwargs, "clock")
        self.robot = self.component(kwargs, "robot")
        self.controllers = self.component(kwargs, "controllers")
        self.local_costmap = kwargs.get("local_costmap")
        self.observed = kwargs.get("observed_space")
        self.control_period = float(kwargs.get("control_period") or 0.05)
        self._progress = ProgressChecker()
        self._shim = RotationShim()

    def wire(self, namespace: str, refs: dict[str, str] | None = None,
             literals: dict[str, Any] | None = None, private_tag: str | None = None) -> None:
        super().wire(namespace, refs, literals, private_tag)
        # tracking feedback costs a path search each tick: only when the tree reads it
        self._feedback_wired = "tracking_feedback" in (refs or {})

    def initialise(self) -> None:
        self._plan: Path | None = None
        self._controller = self.controllers.get(self.get_input("controller_id"))
        if self._controller is not None:
            self._controller.reset()
        now = self.clock.now()
        self._last_valid = now
        self._progress.reset(self.robot.pose(), now)

    def fail(self, code: ControllerError, msg: str) -> Status:
        self.write("cmd_vel", Twist.zero())
        self.write("error_code_id", int(code))
        self.write("error_msg", msg)
        self.say(msg)
        return FAILURE

    def update(self) -> Status:
        if self._controller is None:
            return self.fail(ControllerError.INVALID_CONTROLLER,
                             f"no controller '{self.get_input('controller_id')}'")
        path = self.read("path")
        if path is None or len(path) == 0:
            return self.fail(ControllerError.INVALID_PATH, "no path to follow")
        if path is not self._plan:
            self._controller.set_plan(path)
            self._plan = path
            self._plan_poses = np.asarray(path.poses, dtype=np.float64).reshape(-1, 3)
            self._shim.new_path()
        now, pose = self.clock.now(), self.robot.pose()
        if self.get_input("rotate_to_heading"):
            turn = self._rotate_to_heading(pose, now)
            if turn is not None:
                return turn
        result = self._controller.compute_velocity(pose, self.robot.velocity())
        if result.status == _GOAL_REACHED or self._controller.is_goal_reached():
            self.write("cmd_vel", Twist.zero())
            self.write("error_code_id", int(ControllerError.NONE))
            self.write("error_msg", "")
            self.say("goal reached")
            return SUCCESS
        code = CONTROL_CODES.get(result.status)
        if code is _NO_VALID:
            return self._no_valid(now, str(result.status))
        if code is not None:
            return self.fail(code, f"controller: {result.status}")
        if result.cmd.vx < 0.0 and self._reverses_blind(pose, result.cmd, now):
            return self._turn_instead(pose, now)
        self._last_valid = now
        if self._feedback_wired:
            self.write("tracking_feedback", tracking_feedback(path, pose,
                                                              self.robot.velocity().vx))
        if self._stalled(pose, now):
            return self.fail(ControllerError.FAILED_TO_MAKE_PROGRESS,
                             f"moved less than {self.get_input('required_movement_radius')} m in "
                             f"{self.get_input('movement_time_allowance')} s")
        self.write("cmd_vel", result.cmd)
        self.say("{}: vx {:.2f} wz {:.2f}", result.status, result.cmd.vx, result.cmd.wz)
        return RUNNING

    def _no_valid(self, now: float, why: str) -> Status:
        """No valid command this tick: zero and RUNNING within ``failure_tolerance``, then
        FAILURE (PATIENCE_EXCEEDED, or NO_VALID_CONTROL without a tolerance)."""
        tolerance = self.get_input("failure_tolerance")
        if tolerance >= 0.0 and now - self._last_valid >= tolerance:
            code = (ControllerError.PATIENCE_EXCEEDED if tolerance > 0.0
                    else ControllerError.NO_VALID_CONTROL)
            return self.fail(code, f"no valid command for {now - self._last_valid:.1f} s ({why})")
        self.write("cmd_vel", Twist.zero())
        self.say(f"no valid command ({why}), trying again")
        return RUNNING

    def _shim_params(self) -> ShimParams:
        get = self.get_input
        return ShimParams(angular_dist_threshold=get("angular_dist_threshold"),
                          forward_sampling_distance=get("forward_sampling_distance"),
                          rotate_to_heading_angular_vel=get("rotate_to_heading_angular_vel"),
                          max_angular_accel=get("max_angular_accel"),
                          simulate_ahead_time=get("simulate_ahead_time"))

    def _reverses_blind(self, pose: Pose2D, cmd: Twist, now: float) -> bool:
        within = self.get_input("observed_within")
        if self.observed is None or within <= 0.0:
            return False
        poses = swept_poses(pose, cmd.vx, cmd.wz, self.get_input("simulate_ahead_time"))
        return self.observed.first_unobserved(poses, pose, now - within) is not None

    def _turn_instead(self, pose: Pose2D, now: float) -> Status:
        """The controller would reverse blind: turn toward the path ahead instead."""
        cmd, hit = turn_toward_path(pose, self._plan_poses, self.robot.velocity().wz,
                                    self.control_period, self._shim_params(),
                                    self.local_costmap)
        if cmd is None:
            why = "turn blocked" if hit is not None else "path ahead"
            return self._no_valid(now, f"reverse into unobserved space; {why}")
        self._last_valid = now
        self.write("cmd_vel", cmd)
        self.say("not reversing blind: turning to the path, wz {:.2f}", cmd.wz)
        return RUNNING

    def _rotate_to_heading(self, pose: Pose2D, now: float) -> Status | None:
        """The shim's tick: RUNNING (turning, or blocked within ``failure_tolerance``), FAILURE
        (blocked for longer), None when the controller drives."""
        cmd, hit = self._shim.command(pose, self._plan_poses, self.robot.velocity().wz,
                                      self.control_period, self._shim_params(),
                                      self.local_costmap)
        if cmd is not None:
            self._last_valid = now
            self.write("cmd_vel", cmd)
            self.say("rotating to the path's heading: wz {:.2f}", cmd.wz)
            return RUNNING
        if hit is None:
            return None
        return self._no_valid(now, "turn to the path's heading blocked")

    def _stalled(self, pose: Pose2D, now: float) -> bool:
        allowance = self.get_input("movement_time_allowance")
        return allowance > 0.0 and self._progress.stalled(  # 0: no progress check
            pose, now, self.get_input("required_movement_radius"), allowance)

    def terminate(self, new_status: Status) -> None:
        if new_status is INVALID and self.status is RUNNING:
            self.write("cmd_vel", Twist.zero())
