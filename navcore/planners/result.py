"""PlanResult: what every global planner's ``make_plan`` returns instead of raising."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from navcore.types import Path

#: Every reason a plan can fail with (``""`` when it succeeded).
REASONS = ("start_outside_map", "goal_outside_map", "start_occupied", "goal_occupied", "no_path",
           "invalid_pose")


@dataclass
class PlanResult:
    """Either a ``path`` (``ok`` True, ``reason`` "") or a ``reason`` why there is none.

    ``potential`` is the planner's navigation function, shape (size_y, size_x) float32, cells never
    reached hold 1e10. It is the planner's own buffer (no copy), valid until its next ``make_plan``,
    and only set when the planner's ``visualize_potential`` (navfn) or ``publish_potential``
    (global_planner) parameter is true.
    """

    ok: bool
    path: Path | None
    reason: str
    potential: np.ndarray | None = None

    @staticmethod
    def failure(reason: str, potential: np.ndarray | None = None) -> PlanResult:
        return PlanResult(False, None, reason, potential)
