"""ComputePathToPose: plan from the robot to the goal (Nav2)."""

from __future__ import annotations

from behaviors.actions.planning import PlanningAction, PLAN_IN, PLAN_OUT
from behaviors.base import PortInformation, Status
from navcore.error_codes import PlannerError
from navcore.types import Pose2D


class ComputePathToPose(PlanningAction):
    """Plan from the robot (or ``start``) to ``goal`` in one tick.

    SUCCESS with ``path`` written. FAILURE with ``error_code_id`` (START_OCCUPIED, GOAL_OCCUPIED,
    NO_VALID_PATH, INVALID_PLANNER, ...) when the planner cannot, or when there is no goal.
    """

    INPUT_PORTS = {"goal": PortInformation(Pose2D, True, "goal pose in map"), **PLAN_IN}
    OUTPUT_PORTS = dict(PLAN_OUT)
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
            return self.fail(self.code(reason), f"planning failed: {reason}")
        self.say(f"path of {len(path)} poses, {path.length():.2f} m")
        return self.succeed(path)
