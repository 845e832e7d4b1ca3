"""StartEscape: get the footprint out of inflated space by the straightest free motion."""

from __future__ import annotations

import math
from typing import Any

from behaviors.actions.recovery_action import (CMD_VEL_OUT, ERROR_CODE_OUT, OBSERVED_IN,
                                              RecoveryAction)
from behaviors.base import RUNNING, Port, PortInformation, Status
from navcore.costmap.cost_values import INSCRIBED_INFLATED_OBSTACLE, LETHAL_OBSTACLE
from navcore.error_codes import RecoveryError
from navcore.motion.pursuit import CHECK_STEP
from navcore.motion.start_escape import motion_poses, nearer_than, start_gap, straightest_escape
from navcore.types import Pose2D, Twist

# searches per run: a motion that no longer frees the footprint (the costmap changed) is
# replaced by a new one from where the robot stands
SEARCHES = 3
# m of travel past the planned distance before searching again
OVERSHOOT = 0.05


class StartEscape(RecoveryAction):
    """Get the robot's footprint out of inscribed or lethal cost (a start pressed against a
    wall, a planner's START_OCCUPIED) by the straightest free motion: straight forwards or
    backwards, or else a short arc, whichever frees it (below the inscribed cost) in the least
    travel, at most ``max_distance`` m, the body never nearer a lethal cell than where it
    started (``navcore.motion.start_escape``), driven at ``speed`` m/s and checked so over
    ``simulate_ahead_time`` s of it each tick.

    SUCCESS once the footprint is free (at once, without moving, when it already is).
    RUNNING while moving. FAILURE: NO_FREE_POSE (no such motion), COLLISION_AHEAD (the costmap
    changed under the motion), UNOBSERVED_SPACE (the motion would enter space not seen free
    within ``observed_within`` s), TIMEOUT (``time_allowance``). Every exit leaves a zero command.
    """

    INPUT_PORTS = {
        "max_distance": Port(float, False, "m of travel searched", 1.0, low=0.0, high=10.0),
        "speed": Port(float, False, "m/s", 0.1, low=0.0),
        "costmap": PortInformation(str, False, "costmap the motion is searched on (it is "
                                   "checked on the local one)", "local"),
        "time_allowance": Port(float, False, "s before giving up", 20.0, low=0.0),
        "simulate_ahead_time": Port(float, False, "collision look-ahead, s", 1.0, low=0.0),
        "disable_collision_checks": PortInformation(bool, False, "skip footprint checks", False),
        **OBSERVED_IN,
    }
    OUTPUT_PORTS = {**CMD_VEL_OUT, **ERROR_CODE_OUT}
    DEFAULT_KEYS = {"cmd_vel": "cmd_vel", "error_code_id": "start_escape_error_code"}
    CHOICES = {"costmap": ("local", "global")}

    def initialise(self) -> None:
        self._start = self.clock.now()
        self._motion = None
        self._from: Pose2D | None = None
        self._gap: float | None = None
        self._searches = 0

    def _handle(self) -> Any:
        return self.costmaps.get(self.get_input("costmap")) or self.collision_map()

    def update(self) -> Status:
        pose = self.robot.pose()
        handle = self._handle()
        if handle is None:
            return self.finish(RecoveryError.INVALID_INPUT, "no costmap")
        cost = int(handle.footprint_cost(pose.x, pose.y, pose.theta))
        if 0 <= cost < INSCRIBED_INFLATED_OBSTACLE:
            moved = 0.0 if self._from is None else pose.distance_to(self._from)
            return self.finish(RecoveryError.NONE,
                               f"footprint free (cost {cost}) after {moved:.2f} m")
        if self.clock.now() - self._start > self.get_input("time_allowance"):
            return self.finish(RecoveryError.TIMEOUT, "time out, footprint still in inflated space")
        m = self._motion
        if m is not None and pose.distance_to(self._from) > m.distance + OVERSHOOT:
            m = None            # gone the whole way and still not free: the costmap changed
        if m is None:
            if self._searches >= SEARCHES:
                return self.finish(RecoveryError.NO_FREE_POSE, f"still in cost {cost} after "
                                                               f"{self._searches} motions")
            self._searches += 1
            m = straightest_escape(handle, pose, self.get_input("max_distance"))
            if m is None:
                return self.finish(RecoveryError.NO_FREE_POSE,
                                   f"no straight or arc motion frees the footprint within "
                                   f"{self.get_input('max_distance'):.2f} m")
            self._motion, self._from, self._gap = m, pose, start_gap(handle, pose)
        speed = self.get_input("speed")
        left = max(m.distance - pose.distance_to(self._from), 0.0) + OVERSHOOT
        v = m.direction * speed
        if not self.get_input("disable_collision_checks"):
            ahead = min(left, speed * self.get_input("simulate_ahead_time"))
            n = max(1, int(math.ceil(ahead / CHECK_STEP)))
            way = [Pose2D(*p) for p in motion_poses(pose, m.direction, m.curvature, ahead / n, n)]
            hit = self.first_collision(way, pose)
            near = nearer_than(handle, way, self._gap) if hit is None else None
            if near is not None:
                hit = (way[near], LETHAL_OBSTACLE)
            if hit is not None:
                return self.finish(RecoveryError.COLLISION_AHEAD,
                                   f"blocked: cost {hit[1]} {hit[0].distance_to(pose):.2f} m on")
            blind = self.first_unobserved(way, pose)
            if blind is not None:
                return self.finish(RecoveryError.UNOBSERVED_SPACE,
                                   f"not observed free within "
                                   f"{self.get_input('observed_within')} s: {blind[1]:.2f} m on")
        self.write("cmd_vel", Twist(v, 0.0, v * m.curvature))
        kind = "straight" if m.curvature == 0.0 else f"arc of radius {1.0 / abs(m.curvature):.1f} m"
        self.say("{} {}, {:.2f} of {:.2f} m", kind,
                 "forwards" if m.direction > 0 else "backwards",
                 pose.distance_to(self._from), m.distance)
        return RUNNING
