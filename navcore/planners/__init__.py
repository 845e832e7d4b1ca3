"""Global planners with ROS semantics: navfn, global_planner and carrot_planner.

Each has ``.params`` (ROS names and effective defaults) and ``make_plan(start, goal) ->
PlanResult`` (a path or the ``PlanReason`` there is none). ``make_planner`` builds one from the ROS
``base_global_planner`` string.
"""

from __future__ import annotations

from typing import Callable

from navcore.costmap.costmap2d import Costmap2D
from navcore.params import suggest
from navcore.planners.carrot_planner import CarrotPlanner, costmap_footprint_cost
from navcore.planners.global_planner import GlobalPlanner
from navcore.planners.navfn import NavFn
from navcore.planners.result import PlanReason, PlanResult

__all__ = ["CarrotPlanner", "GlobalPlanner", "NavFn", "PlanResult", "PlanReason", "PLANNER_KINDS",
           "costmap_footprint_cost", "make_planner"]

PLANNER_KINDS = ("navfn/NavfnROS", "global_planner/GlobalPlanner", "carrot_planner/CarrotPlanner")


def make_planner(kind: str, costmap: Costmap2D, params: dict | None = None,
                 footprint_cost: Callable[[float, float, float], int] | None = None
                 ) -> NavFn | GlobalPlanner | CarrotPlanner:
    """The planner named by a ROS ``base_global_planner`` value, with its parameter namespace.

    ``footprint_cost(x, y, theta) -> int`` is needed by (only) the carrot planner;
    ``costmap_footprint_cost(costmap, footprint)`` makes one.
    """
    if kind == "navfn/NavfnROS":
        return NavFn(costmap, params)
    if kind == "global_planner/GlobalPlanner":
        return GlobalPlanner(costmap, params)
    if kind == "carrot_planner/CarrotPlanner":
        if footprint_cost is None:
            raise ValueError("make_planner: carrot_planner/CarrotPlanner needs footprint_cost")
        return CarrotPlanner(costmap, footprint_cost, params)
    raise ValueError(f"make_planner: unknown base_global_planner {kind!r}"
                     f"{suggest(kind, PLANNER_KINDS)}; known: {', '.join(PLANNER_KINDS)}")
