"""Local planners with base_local_planner semantics: DWA and trajectory rollout.

``make_controller(kind, costmap, footprint, params)`` builds one by its ROS plugin name.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from navcore.costmap.costmap2d import Costmap2D
from navcore.controllers.dwa import DWAPlanner
from navcore.controllers.result import ControlResult
from navcore.controllers.trajectory_rollout import TrajectoryPlanner

KINDS = ("dwa_local_planner/DWAPlannerROS", "base_local_planner/TrajectoryPlannerROS")


def make_controller(kind: str, costmap: Costmap2D, footprint: np.ndarray,
                    params: dict[str, Any] | None = None) -> DWAPlanner | TrajectoryPlanner:
    """The local planner registered as ``kind`` (a ROS nav_core plugin name, or its class name
    alone); ``params`` is that planner's ROS namespace."""
    if kind in ("dwa_local_planner/DWAPlannerROS", "DWAPlannerROS"):
        return DWAPlanner(costmap, footprint, params)
    if kind in ("base_local_planner/TrajectoryPlannerROS", "TrajectoryPlannerROS"):
        return TrajectoryPlanner(costmap, footprint, params)
    raise ValueError(f"make_controller: unknown local planner '{kind}'; known: {', '.join(KINDS)}")


__all__ = ["ControlResult", "DWAPlanner", "KINDS", "TrajectoryPlanner", "make_controller"]
