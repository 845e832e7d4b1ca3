"""PlanResult: what every global planner's ``make_plan`` returns: a path, or why there is none."""

from __future__ import annotations

from dataclasses import dataclass
from enum import StrEnum

import numpy as np

from navcore.types import Path

class PlanReason(StrEnum):
    """Why ``make_plan`` gave no path (``NONE`` when it gave one); compares equal to its text.
    Each maps to a Nav2 ComputePathToPose code in ``navcore.error_codes.PLAN_CODES``."""

    NONE = ""
    INVALID_POSE = "invalid_pose"            # start or goal not finite
    START_OUTSIDE_MAP = "start_outside_map"
    GOAL_OUTSIDE_MAP = "goal_outside_map"
    START_OCCUPIED = "start_occupied"
    GOAL_OCCUPIED = "goal_occupied"
    NO_PATH = "no_path"


@dataclass
class PlanResult:
    """Either a ``path`` (``ok`` True, ``reason`` NONE) or the ``reason`` there is none.

    ``potential`` is the planner's navigation function, shape (size_y, size_x) float32, cells never
    reached hold 1e10. It is the planner's own buffer (no copy), valid until its next ``make_plan``,
    and only set when the planner's ``visualize_potential`` (navfn) or ``publish_potential``
    (global_planner) parameter is true.
    """

    ok: bool
    path: Path | None
    reason: PlanReason
    potential: np.ndarray | None = None

    @staticmethod
    def failure(reason: PlanReason, potential: np.ndarray | None = None) -> PlanResult:
        return PlanResult(False, None, reason, potential)
