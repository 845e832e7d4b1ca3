"""ComputePathThroughPoses: plan through goals in order (Nav2)."""

from __future__ import annotations

import numpy as np

from behaviors.actions.planning import PlanningAction, PLAN_IN, PLAN_OUT
from behaviors.base import PortInformation, Status
from navcore.error_codes import PlannerError
from navcore.types import Path


class ComputePathThroughPoses(PlanningAction):
    """Plan through ``goals`` in order (one planner call per leg, all in one tick) and join the
    legs into one ``path``. FAILURE with the failing leg's code, or NO_VIAPOINTS_GIVEN."""

    INPUT_PORTS = {"goals": PortInformation(list, True, "list of Pose2D, in order"), **PLAN_IN}
    OUTPUT_PORTS = dict(PLAN_OUT)
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
                return self.fail(self.code(reason), f"leg {i} failed: {reason}")
            legs.append(leg.poses if i == 0 else leg.poses[1:])
            start = goal
        return self.succeed(Path(np.concatenate(legs, axis=0)))
