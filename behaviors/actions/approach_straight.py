"""ApproachStraight: drive straight and slowly into a tight goal from where the robot lined up."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from behaviors.actions.recovery_action import CMD_VEL_OUT, ERROR_CODE_OUT
from behaviors.base import FAILURE, INVALID, RUNNING, SUCCESS, Leaf, Port, PortInformation, Status
from navcore.error_codes import DriveOnHeadingError
from navcore.motion.line_up import entry_blocked, line_offsets
from navcore.motion.pursuit import pure_pursuit, swept_poses
from navcore.types import Pose2D, Twist

# spacing of the poses of the straight line pursued, m
LINE_STEP = 0.05
# what is left to go along the line when driving stops and the final turn begins, m
ARRIVED = 0.01


class ApproachStraight(Leaf):
    """Drive along ``goal``'s heading line into the goal at ``entry_speed`` m/s, then turn on
    the spot to its heading: the slow, straight entry into a bay after lining up in front of it
    (``ComputePrePose``). Pure pursuit on the line (``lookahead`` m) takes out what is left of a
    lateral offset; the footprint is checked on the local costmap over ``simulate_ahead_time``
    s of the motion: inscribed cost is what a narrow space is made of and is allowed, the
    robot's body (the footprint without padding) may not overlap a lethal cell
    (``navcore.motion.line_up.entry_blocked``).

    RUNNING while driving or turning. SUCCESS within ``xy_goal_tolerance`` m and
    ``yaw_goal_tolerance`` rad of the goal. FAILURE (DriveOnHeading's codes): INVALID_INPUT
    when the robot does not start lined up (more than ``max_lateral_offset`` m beside the line,
    ``max_heading_error`` rad off it, or past the goal) or there is no goal, COLLISION_AHEAD,
    TIMEOUT after ``time_allowance`` s, UNKNOWN when it stops farther than the tolerance. Every
    exit leaves a zero command. Not a recovery: a way of arriving.
    """

    INPUT_PORTS = {
        "goal": PortInformation(Pose2D, True, "goal pose in map"),
        "entry_speed": Port(float, False, "m/s along the line", 0.1, low=0.0),
        "lookahead": Port(float, False, "pursuit look-ahead on the line, m", 0.3, low=0.01),
        "max_rotational_vel": Port(float, False, "rad/s", 0.6, low=0.0),
        "xy_goal_tolerance": Port(float, False, "m", 0.05, low=0.0),
        "yaw_goal_tolerance": Port(float, False, "rad", 0.05, low=0.0),
        "max_lateral_offset": Port(float, False, "m beside the line the start may be", 0.3,
                                   low=0.0),
        "max_heading_error": Port(float, False, "rad off the line the start may be", 0.6,
                                  low=0.0),
        "time_allowance": Port(float, False, "s before giving up", 60.0, low=0.0),
        "simulate_ahead_time": Port(float, False, "collision look-ahead, s", 1.0, low=0.0),
        "disable_collision_checks": PortInformation(bool, False, "skip footprint checks", False),
    }
    OUTPUT_PORTS = {**CMD_VEL_OUT, **ERROR_CODE_OUT}
    DEFAULT_KEYS = {"goal": "goal", "cmd_vel": "cmd_vel",
                    "error_code_id": "approach_straight_error_code"}

    def setup(self, **kwargs: Any) -> None:
        self.clock = self.component(kwargs, "clock")
        self.robot = self.component(kwargs, "robot")
        self.collision = kwargs.get("local_costmap") or kwargs.get("global_costmap")
        self.control_period = float(kwargs.get("control_period") or 0.05)

    def initialise(self) -> None:
        self._start = self.clock.now()
        self._checked = False
        self._turning = False

    def _fail(self, code: DriveOnHeadingError, msg: str) -> Status:
        self.write("cmd_vel", Twist.zero())
        self.write("error_code_id", int(code))
        self.write("error_msg", msg)
        self.say(msg)
        return FAILURE

    def _blocked(self, pose: Pose2D, cmd: Twist, horizon: float) -> Pose2D | None:
        if self.get_input("disable_collision_checks") or self.collision is None:
            return None
        way = swept_poses(pose, cmd.vx, cmd.wz, horizon)
        i = entry_blocked(self.collision, np.array([[p.x, p.y, p.theta] for p in way]))
        return None if i is None else way[i]

    def update(self) -> Status:
        goal = self.read("goal")
        if goal is None:
            return self._fail(DriveOnHeadingError.INVALID_INPUT, "no goal")
        pose = self.robot.pose()
        to_go, lateral, heading = line_offsets(goal, pose)
        if not self._checked:
            self._checked = True
            if (to_go < -self.get_input("xy_goal_tolerance")
                    or abs(lateral) > self.get_input("max_lateral_offset")
                    or abs(heading) > self.get_input("max_heading_error")):
                return self._fail(DriveOnHeadingError.INVALID_INPUT,
                                  f"not lined up: {to_go:.2f} m to go, {lateral:.2f} m beside, "
                                  f"{heading:.2f} rad off")
        if self.clock.now() - self._start > self.get_input("time_allowance"):
            return self._fail(DriveOnHeadingError.TIMEOUT, f"time out {to_go:.2f} m short")
        self._turning = self._turning or to_go <= ARRIVED
        if self._turning:
            return self._turn(goal, pose, heading)
        # the line from the robot's foot on it to the goal, pursued forwards
        n = max(1, int(math.ceil(to_go / LINE_STEP)))
        line = [goal.compose(Pose2D(-to_go * (1.0 - k / n), 0.0, 0.0)) for k in range(n + 1)]
        cmd, _ = pure_pursuit(pose, line, 0, goal, self.get_input("entry_speed"),
                              min(self.get_input("lookahead"), max(to_go, ARRIVED)),
                              self.get_input("max_rotational_vel"), self.control_period)
        cmd = Twist(max(cmd.vx, 0.0), 0.0, cmd.wz)   # never backwards into unseen space
        # the way still to go, not past the goal
        hit = self._blocked(pose, cmd, min(self.get_input("simulate_ahead_time"),
                                           to_go / max(cmd.vx, 1e-6)))
        if hit is not None:
            return self._fail(DriveOnHeadingError.COLLISION_AHEAD,
                              f"blocked: lethal {hit.distance_to(pose):.2f} m ahead")
        self.write("cmd_vel", cmd)
        self.say("{:.2f} m to go, {:.3f} m beside the line", to_go, lateral)
        return RUNNING

    def _turn(self, goal: Pose2D, pose: Pose2D, heading: float) -> Status:
        if abs(heading) <= self.get_input("yaw_goal_tolerance"):
            off = pose.distance_to(goal)
            if off > self.get_input("xy_goal_tolerance"):
                return self._fail(DriveOnHeadingError.UNKNOWN,
                                  f"stopped {off:.3f} m from the goal")
            self.write("cmd_vel", Twist.zero())
            self.write("error_code_id", int(DriveOnHeadingError.NONE))
            self.write("error_msg", "")
            self.say("in, {:.3f} m and {:.3f} rad off", off, heading)
            return SUCCESS
        w_max = self.get_input("max_rotational_vel")
        w = max(-w_max, min(w_max, -heading / max(self.control_period, 1e-3)))
        cmd = Twist(0.0, 0.0, w)
        # the turn still needed, not a whole look-ahead of it
        hit = self._blocked(pose, cmd, min(self.get_input("simulate_ahead_time"),
                                           abs(heading) / max(abs(w), 1e-6)))
        if hit is not None:
            return self._fail(DriveOnHeadingError.COLLISION_AHEAD,
                              "turn blocked: lethal")
        self.write("cmd_vel", cmd)
        self.say("turning, {:.3f} rad off", heading)
        return RUNNING

    def terminate(self, new_status: Status) -> None:
        if self.status is RUNNING or new_status is not INVALID:
            self.write("cmd_vel", Twist.zero())
