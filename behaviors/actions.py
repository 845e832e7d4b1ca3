"""Navigation actions: plan (ComputePathToPose, ComputePathThroughPoses), follow (FollowPath),
the NavigateToPose subtree, and RecordPoseHistory (the trail BackOffToPreviousPose drives back on).

Each action writes ``error_code_id``/``error_msg`` on every exit so that recoveries are chosen by
cause (Nav2's error-code ports); codes are in ``behaviors.error_codes``.
"""

from __future__ import annotations

import math
from typing import Any

from behaviors.base import FAILURE, INVALID, RUNNING, SUCCESS, Leaf, PortInformation, Status
from behaviors.error_codes import ControllerError, PlannerError, planner_code
from navcore.types import Path, Pose2D, Twist

import numpy as np


class PlanningAction(Leaf):
    """Base of the planning actions: picks the planner by id and reports errors."""

    INPUT_PORTS: dict[str, PortInformation]
    OUTPUT_PORTS: dict[str, PortInformation]

    def setup(self, **kwargs: Any) -> None:
        self.robot = self.component(kwargs, "robot")
        self.planners = self.component(kwargs, "planners")

    def fail(self, code: PlannerError, msg: str) -> Status:
        self.write("error_code_id", int(code))
        self.write("error_msg", msg)
        self.say(msg)
        return FAILURE

    def planner(self) -> Any:
        return self.planners.get(self.get_input("planner_id"))

    def no_planner(self) -> Status:
        return self.fail(PlannerError.INVALID_PLANNER, f"no planner '{self.get_input('planner_id')}'")

    @staticmethod
    def plan(planner: Any, start: Pose2D, goal: Pose2D) -> tuple[Path | None, str]:
        """The planner's non-empty path, or None and the planner's reason."""
        result = planner.make_plan(start, goal)
        if not result.ok or result.path is None or len(result.path) == 0:
            return None, result.reason or "no_path"
        return result.path, ""

    def succeed(self, path: Path) -> Status:
        self.write("path", path)
        self.write("error_code_id", int(PlannerError.NONE))
        self.write("error_msg", "")
        return SUCCESS

    def start(self) -> Pose2D:
        if self.get_input("use_start"):
            start = self.read("start")
            if start is not None:
                return start
        return self.robot.pose()


_PLAN_OUT = {
    "path": PortInformation(Path, True, "the plan, in map"),
    "error_code_id": PortInformation(int, False, "a PlannerError; 0 on success"),
    "error_msg": PortInformation(str, False, "why planning failed"),
}
_PLAN_IN = {
    "start": PortInformation(Pose2D, False, "start pose (used when use_start)"),
    "use_start": PortInformation(bool, False, "plan from 'start' instead of the robot pose", False),
    "planner_id": PortInformation(str, False, "which planner (setup 'planners' key)", "GridBased"),
}


class ComputePathToPose(PlanningAction):
    """Plan from the robot (or ``start``) to ``goal`` in one tick.

    SUCCESS with ``path`` written. FAILURE with ``error_code_id`` (START_OCCUPIED, GOAL_OCCUPIED,
    NO_VALID_PATH, INVALID_PLANNER, ...) when the planner cannot, or when there is no goal.
    """

    INPUT_PORTS = {"goal": PortInformation(Pose2D, True, "goal pose in map"), **_PLAN_IN}
    OUTPUT_PORTS = dict(_PLAN_OUT)
    DEFAULT_KEYS = {"goal": "goal", "path": "path", "error_code_id": "compute_path_error_code",
                    "error_msg": "compute_path_error_msg"}

    def update(self) -> Status:
        planner = self.planner()
        if planner is None:
            return self.no_planner()
        goal = self.read("goal")
        if goal is None:
            return self.fail(PlannerError.INVALID_GOAL, "no goal on the blackboard")
        path, reason = self.plan(planner, self.start(), goal)
        if path is None:
            return self.fail(planner_code(reason), f"planning failed: {reason}")
        self.say(f"path of {len(path)} poses, {path.length():.2f} m")
        return self.succeed(path)


class ComputePathThroughPoses(PlanningAction):
    """Plan through ``goals`` in order (one planner call per leg, all in one tick) and join the
    legs into one ``path``. FAILURE with the failing leg's code, or NO_VIAPOINTS_GIVEN."""

    INPUT_PORTS = {"goals": PortInformation(list, True, "list of Pose2D, in order"), **_PLAN_IN}
    OUTPUT_PORTS = dict(_PLAN_OUT)
    DEFAULT_KEYS = {"goals": "goals", "path": "path", "error_code_id": "compute_path_error_code",
                    "error_msg": "compute_path_error_msg"}

    def update(self) -> Status:
        planner = self.planner()
        if planner is None:
            return self.no_planner()
        goals = self.read("goals")
        if not goals:
            return self.fail(PlannerError.NO_VIAPOINTS_GIVEN, "no goals on the blackboard")
        legs, start = [], self.start()
        for i, goal in enumerate(goals):
            leg, reason = self.plan(planner, start, goal)
            if leg is None:
                return self.fail(planner_code(reason), f"leg {i} failed: {reason}")
            legs.append(leg.poses if i == 0 else leg.poses[1:])
            start = goal
        return self.succeed(Path(np.concatenate(legs, axis=0)))


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
    """

    INPUT_PORTS = {
        "path": PortInformation(Path, True, "path to follow"),
        "controller_id": PortInformation(str, False, "which controller (setup 'controllers' key)",
                                         "FollowPath"),
        "failure_tolerance": PortInformation(float, False,
                                             "s without a valid command before FAILURE; -1 never",
                                             0.0),
        "required_movement_radius": PortInformation(float, False, "progress radius, m", 0.5),
        "movement_time_allowance": PortInformation(float, False, "s to make progress; 0 = off",
                                                   10.0),
    }
    OUTPUT_PORTS = {
        "cmd_vel": PortInformation(Twist, True, "velocity command for this tick"),
        "error_code_id": PortInformation(int, False, "a ControllerError; 0 on success"),
        "error_msg": PortInformation(str, False, "why following failed"),
    }
    DEFAULT_KEYS = {"path": "path", "cmd_vel": "cmd_vel", "error_code_id": "follow_path_error_code",
                    "error_msg": "follow_path_error_msg"}

    def setup(self, **kwargs: Any) -> None:
        self.clock = self.component(kwargs, "clock")
        self.robot = self.component(kwargs, "robot")
        self.controllers = self.component(kwargs, "controllers")

    def initialise(self) -> None:
        self._plan: Path | None = None
        self._controller = self.controllers.get(self.get_input("controller_id"))
        if self._controller is not None:
            self._controller.reset()
        now = self.clock.now()
        self._last_valid = now
        self._progress_anchor, self._progress_since = self.robot.pose(), now

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
        now, pose = self.clock.now(), self.robot.pose()
        result = self._controller.compute_velocity(pose, self.robot.velocity())
        if result.status == "goal_reached" or self._controller.is_goal_reached():
            self.write("cmd_vel", Twist.zero())
            self.write("error_code_id", int(ControllerError.NONE))
            self.write("error_msg", "")
            self.say("goal reached")
            return SUCCESS
        if result.status.startswith("no_valid"):
            tolerance = self.get_input("failure_tolerance")
            if tolerance >= 0.0 and now - self._last_valid >= tolerance:
                code = (ControllerError.PATIENCE_EXCEEDED if tolerance > 0.0
                        else ControllerError.NO_VALID_CONTROL)
                return self.fail(code, f"no valid command for {now - self._last_valid:.1f} s "
                                       f"({result.status})")
            self.write("cmd_vel", Twist.zero())
            self.say(f"no valid command ({result.status}), trying again")
            return RUNNING
        self._last_valid = now
        if self._stalled(pose, now):
            return self.fail(ControllerError.FAILED_TO_MAKE_PROGRESS,
                             f"moved less than {self.get_input('required_movement_radius')} m in "
                             f"{self.get_input('movement_time_allowance')} s")
        self.write("cmd_vel", result.cmd)
        self.say("{}: vx {:.2f} wz {:.2f}", result.status, result.cmd.vx, result.cmd.wz)
        return RUNNING

    def _stalled(self, pose: Pose2D, now: float) -> bool:
        allowance = self.get_input("movement_time_allowance")
        if allowance <= 0.0:
            return False
        if pose.distance_to(self._progress_anchor) >= self.get_input("required_movement_radius"):
            self._progress_anchor, self._progress_since = pose, now
            return False
        return now - self._progress_since > allowance

    def terminate(self, new_status: Status) -> None:
        if new_status is INVALID and self.status is RUNNING:
            self.write("cmd_vel", Twist.zero())


class RecordPoseHistory(Leaf):
    """Append the robot pose to ``pose_history`` whenever it moved ``spacing`` metres; keep the
    last ``max_length`` metres of trail. Always SUCCESS; put it first in the navigation
    pipeline so the trail grows while the robot drives. The history survives recoveries."""

    INPUT_PORTS = {
        "spacing": PortInformation(float, False, "distance between stored poses, m", 0.05),
        "max_length": PortInformation(float, False, "trail length kept, m", 5.0),
    }
    OUTPUT_PORTS = {"pose_history": PortInformation(list, True, "Pose2D, oldest first")}
    DEFAULT_KEYS = {"pose_history": "pose_history"}

    def setup(self, **kwargs: Any) -> None:
        self.robot = self.component(kwargs, "robot")
        self._trail: list[Pose2D] = []
        self._length = 0.0

    def update(self) -> Status:
        pose = self.robot.pose()
        trail = self._trail
        if trail:
            step = pose.distance_to(trail[-1])
            if step < self.get_input("spacing"):
                return SUCCESS
            self._length += step
        trail.append(pose)
        max_length = self.get_input("max_length")
        while len(trail) > 2:
            first = trail[0].distance_to(trail[1])
            if not self._length - first >= max_length:  # (NaN-safe as the loop condition was)
                break
            self._length -= first
            trail.pop(0)
        self.write("pose_history", list(self._trail))
        return SUCCESS


def trail_length(poses: list[Pose2D]) -> float:
    """Sum of the distances between consecutive poses, m."""
    return sum(a.distance_to(b) for a, b in zip(poses, poses[1:]))


def heading_to(a: Pose2D, b: Pose2D) -> float:
    """Direction from a to b, rad."""
    return math.atan2(b.y - a.y, b.x - a.x)


class _Selector(Leaf):
    """Write the requested component id (or the default) to the selected-id output. SUCCESS."""

    INPUT_PORTS: dict[str, PortInformation]
    OUTPUT_PORTS: dict[str, PortInformation]
    DEFAULT_PORT = ""
    OUTPUT_PORT = ""

    def update(self) -> Status:
        chosen = self.read("requested") or self.get_input(self.DEFAULT_PORT)
        self.write(self.OUTPUT_PORT, chosen)
        self.say(f"selected '{chosen}'")
        return SUCCESS


class PlannerSelector(_Selector):
    """Choose the planner id for ComputePathToPose: ``requested`` if someone wrote it, else
    ``default_planner`` (Nav2 ``PlannerSelector``; the topic becomes the blackboard key
    ``planner_selection``)."""

    INPUT_PORTS = {
        "default_planner": PortInformation(str, False, "planner id when none is requested",
                                           "GridBased"),
        "requested": PortInformation(str, False, "planner id asked for at run time"),
        "topic_name": PortInformation(str, False, "Nav2's topic; unused here", "planner_selector"),
    }
    OUTPUT_PORTS = {"selected_planner": PortInformation(str, True, "the planner id to use")}
    DEFAULT_KEYS = {"requested": "planner_selection", "selected_planner": "selected_planner"}
    DEFAULT_PORT, OUTPUT_PORT = "default_planner", "selected_planner"


class ControllerSelector(_Selector):
    """Choose the controller id for FollowPath: ``requested`` if someone wrote it, else
    ``default_controller`` (Nav2 ``ControllerSelector``; the topic becomes the blackboard key
    ``controller_selection``)."""

    INPUT_PORTS = {
        "default_controller": PortInformation(str, False, "controller id when none is requested",
                                              "FollowPath"),
        "requested": PortInformation(str, False, "controller id asked for at run time"),
        "topic_name": PortInformation(str, False, "Nav2's topic; unused here",
                                      "controller_selector"),
    }
    OUTPUT_PORTS = {"selected_controller": PortInformation(str, True, "the controller id to use")}
    DEFAULT_KEYS = {"requested": "controller_selection",
                    "selected_controller": "selected_controller"}
    DEFAULT_PORT, OUTPUT_PORT = "default_controller", "selected_controller"
