"""TemporaryGoal: get out of a tight spot to a free pose nearby."""

from __future__ import annotations

from typing import Any

from behaviors.actions.recovery_action import (RecoveryAction, CMD_VEL_OUT, ERROR_CODE_OUT,
                                              OBSERVED_IN, UNOBSERVED)
from behaviors.base import RUNNING, Port, PortInformation, Status
from navcore.controllers.result import ControlStatus
from navcore.error_codes import RecoveryError
from navcore.motion.escape import arc_goal, rank_candidates
from navcore.motion.geometry import ring_candidates
from navcore.motion.pursuit import swept_poses
from navcore.types import Pose2D, Twist


# arc searches per run: a blocked arc is replaced by a new one from where the robot stands
ARC_SEARCHES = 3


class TemporaryGoal(RecoveryAction):
    """Get out of a tight spot: find a free, reachable pose near the robot and drive there.

    Candidates lie on rings from ``min_distance`` to ``search_radius`` metres, facing away from
    the robot. Those whose footprint cost is below the inscribed cost are ranked by openness
    plus turn (cost/253 + turn/90 degrees, where a pose straight ahead or behind needs no turn)
    and tried in that order, at most ``max_plans_per_tick`` planner calls per tick, until one
    has a plan. The controller then follows the plan; if it finds no valid command (its
    footprint already in inflated cost, say), the node drives there itself by pure pursuit at
    ``escape_speed``, footprint-checked. Arcs, the own pursuit and any backwards command of the
    controller keep to space observed free within ``observed_within`` s. SUCCESS when the goal
    is reported reached or the robot is within ``xy_goal_tolerance``. FAILURE: NO_FREE_POSE,
    COLLISION_AHEAD (no valid command and the own pursuit is blocked too), UNOBSERVED_SPACE
    (the way there was not observed free recently), TIMEOUT (``time_allowance`` spent, or no
    progress of ``required_movement_radius`` within ``movement_time_allowance``). ``temporary_goal`` holds
    the chosen pose.
    """

    INPUT_PORTS = {
        "search_radius": Port(float, False, "farthest candidate, m", 1.5, low=0.0, high=100.0),
        "min_distance": Port(float, False, "nearest candidate, m", 0.4, low=0.0),
        "radial_step": Port(float, False, "spacing of the rings, m", 0.2, low=0.01),
        "angular_samples": Port(int, False, "candidates per ring", 16, low=1, high=720),
        "costmap": PortInformation(str, False, "costmap to score candidates on", "local"),
        "planner_id": PortInformation(str, False, "planner for the way there", "GridBased"),
        "controller_id": PortInformation(str, False, "controller for the way there", "FollowPath"),
        "max_plans_per_tick": Port(int, False, "planner calls per tick", 4, low=1, high=100),
        "goal": PortInformation(Pose2D, False, "navigation goal: among equally open poses, "
                                               "those nearer to it come first"),
        "arc_first": PortInformation(bool, False,
                                     "first try poses one collision-free arc away, driven "
                                     "without the planner", True),
        "xy_goal_tolerance": Port(float, False, "m", 0.15, low=0.0),
        "time_allowance": Port(float, False, "s before giving up", 30.0, low=0.0),
        "escape_speed": Port(float, False,
                                        "m/s of the own pursuit used when the controller finds "
                                        "no valid command (0 = never)", 0.1, low=0.0),
        "lookahead": Port(float, False, "own pursuit look-ahead, m", 0.4, low=0.0),
        "max_rotational_vel": Port(float, False, "own pursuit, rad/s", 1.0, low=0.0),
        "simulate_ahead_time": Port(float, False, "collision look-ahead, s", 1.0, low=0.0),
        "disable_collision_checks": PortInformation(bool, False, "skip footprint checks", False),
        **OBSERVED_IN,
        "required_movement_radius": Port(float, False, "progress radius, m", 0.1, low=0.0),
        "movement_time_allowance": Port(float, False, "s to make progress; 0 = off",
                                                   5.0, low=0.0),
    }
    OUTPUT_PORTS = {**CMD_VEL_OUT, **ERROR_CODE_OUT,
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

    def _candidates_around(self, pose: Pose2D) -> list[Pose2D]:
        return ring_candidates(pose, self.get_input("min_distance"),
                               self.get_input("search_radius"), self.get_input("radial_step"),
                               self.get_input("angular_samples"))

    def _scoring_map(self) -> Any:
        return self.costmaps.get(self.get_input("costmap")) or self.collision_map()

    def _rank(self, pose: Pose2D) -> list[Pose2D]:
        return rank_candidates(self._scoring_map(), pose, self._candidates_around(pose))

    def _arc_goal(self, pose: Pose2D) -> Pose2D | None:
        goal = self.read("goal")
        within = self.get_input("observed_within")
        observed = self.observed if within > 0.0 else None
        return arc_goal(self._scoring_map(), self.collision_map(), pose,
                        self._candidates_around(pose), goal if isinstance(goal, Pose2D) else None,
                        not self.get_input("disable_collision_checks"), observed,
                        self.clock.now() - within, self.get_input("allow_unknown"))

    def update(self) -> Status:
        pose = self.robot.pose()
        if self.clock.now() - self._start > self.get_input("time_allowance"):
            return self.finish(RecoveryError.TIMEOUT, "time out")
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
            return self.finish(RecoveryError.INVALID_INPUT, "unknown planner or controller id")
        for _ in range(self.get_input("max_plans_per_tick")):
            if not self._candidates:
                return self.finish(RecoveryError.NO_FREE_POSE, "no reachable free pose nearby")
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
            reached = (reached or result.status == ControlStatus.GOAL_REACHED
                       or self._controller.is_goal_reached())
        if reached:
            return self.finish(RecoveryError.NONE, "reached the temporary goal")
        if self.no_progress(pose):
            return self.finish(RecoveryError.TIMEOUT, "no progress toward the temporary goal")
        if result is not None and result.status != ControlStatus.NO_VALID_TRAJECTORY:
            cmd = result.cmd
            if cmd.vx < 0.0 and not self.get_input("disable_collision_checks"):
                # the controller may reverse (min_vel_x < 0): only into space seen free
                blind = self.first_unobserved(
                    swept_poses(pose, cmd.vx, cmd.wz, self.get_input("simulate_ahead_time")), pose)
                if blind is not None:
                    return self.finish(RecoveryError.UNOBSERVED_SPACE,
                                       f"controller reverses into space not observed free: "
                                       f"{blind[1]:.2f} m away")
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
                status = result.status if result is not None else "one arc"
                if hit is not None and hit[1] == UNOBSERVED:
                    return self.finish(RecoveryError.UNOBSERVED_SPACE,
                                       f"controller: {status}; the way was not observed free")
                why = f"blocked: cost {hit[1]}" if hit is not None else "no escape speed"
                return self.finish(RecoveryError.COLLISION_AHEAD, f"controller: {status}; {why}")
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
