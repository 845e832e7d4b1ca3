"""Recoveries: costmap clearing, Spin / BackUp / DriveOnHeading / Wait (Nav2 and rotate_recovery
semantics), and the guide's extra SMACH-style ones, TemporaryGoal and BackOffToPreviousPose.

Motion recoveries write ``cmd_vel`` one control period at a time, check the robot footprint on
the costmap (``footprint_cost``) along the motion ahead, and fail with COLLISION_AHEAD rather than
drive into a lethal cell or from free space into inscribed cost (a robot already in inscribed
cost may move through it to get out). They also move only into space the sensors saw free within
``observed_within`` seconds (the ``observed_space`` memory, which costmap clears do not erase):
a costmap just cleared says "free" for cells that were only forgotten, and a laser that cannot
see behind the robot never saw the way back. Without that component there is nothing to check.
Every exit (finished or interrupted) leaves a zero command.
"""

from __future__ import annotations

from enum import IntEnum
from typing import Any, Iterable

from behaviors.base import (FAILURE, INVALID, RUNNING, SUCCESS, Leaf, Port, PortInformation,
                            Recovery, Status)
from navcore.controllers.progress import ProgressChecker
from navcore.motion.collision import first_collision
from navcore.motion.pursuit import pure_pursuit, swept_poses
from navcore.types import Pose2D, Twist


COSTMAP_CHOICES = ("local", "global", "both")

# the "cost" ``pursue`` reports for a way not observed free recently (no costmap value)
UNOBSERVED = -2

# s: space seen free this recently counts as free for a motion recovery. Long enough for a
# recovery that follows a full-turn Spin (about 8 s) to use what the turn saw; short enough that
# a person or a cart is unlikely to have moved into the space since.
OBSERVED_WITHIN = 10.0

OBSERVED_IN = {
    "observed_within": Port(float, False, "s: move only into space the sensors saw free this "
                                          "recently (observed_space memory); 0 = no check",
                            OBSERVED_WITHIN, low=0.0),
    "allow_unknown": PortInformation(bool, False, "also move into space never seen (or seen "
                                                  "free long ago), never into space last seen "
                                                  "occupied: a last resort", False)}


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
        self.observed = kwargs.get("observed_space")
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

    def finish(self, code: IntEnum, msg: str = "") -> Status:
        """End the action: the zero command, ``code`` and ``msg`` reported; SUCCESS for code 0
        (NONE), else FAILURE."""
        self.stop_motion()
        self.report(code, msg)
        return SUCCESS if int(code) == 0 else FAILURE

    def first_collision(self, poses: Iterable[Pose2D], start: Pose2D | None = None
                        ) -> tuple[Pose2D, int] | None:
        """``navcore.motion.collision.first_collision`` on the collision map (None without
        one)."""
        handle = self.collision_map()
        return None if handle is None else first_collision(handle, poses, start)

    def first_unobserved(self, poses: Iterable[Pose2D], start: Pose2D
                         ) -> tuple[Pose2D, float] | None:
        """The first of ``poses`` whose footprint reaches space (outside the robot's footprint at
        ``start``) not observed free within ``observed_within`` s, and how far that is from
        ``start``; None when all of it was, or without the port, a memory or a window > 0."""
        if self.observed is None or "observed_within" not in self.INPUT_PORTS:
            return None
        within = self.get_input("observed_within")
        if within <= 0.0:
            return None
        poses = list(poses)
        found = self.observed.first_unobserved(poses, start, self.clock.now() - within,
                                               self.get_input("allow_unknown"))
        if found is None:
            return None
        p = poses[found[0]]
        return p, p.distance_to(start)

    def pursue(self, pose: Pose2D, trail: list[Pose2D], index: int, target: Pose2D,
               speed: float, lookahead: float, w_max: float
               ) -> tuple[Twist | None, int, tuple[Pose2D, int] | None]:
        """One pure-pursuit step (``navcore.motion.pursuit``): (the command, or None if
        blocked; the new trail index; the blocking pose and cost, where the cost is -2 when the
        way was not observed free within ``observed_within``). Checked over
        ``simulate_ahead_time`` unless ``disable_collision_checks``."""
        cmd, index = pure_pursuit(pose, trail, index, target, speed, lookahead, w_max,
                                  self.control_period)
        if not self.get_input("disable_collision_checks"):
            poses = swept_poses(pose, cmd.vx, cmd.wz, self.get_input("simulate_ahead_time"))
            hit = self.first_collision(poses, pose)
            if hit is not None:
                return None, index, hit
            blind = self.first_unobserved(poses, pose)
            if blind is not None:
                return None, index, (blind[0], UNOBSERVED)
        return cmd, index, None

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
