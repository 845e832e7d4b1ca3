"""What a behaviour may assume about the components it is handed.

The executive calls ``tree.setup(**components)`` with the keyword arguments below (the py_trees
idiom); each behaviour's ``setup(self, **kwargs)`` picks what it needs. These Protocols are the
contract between ``behaviors`` and whoever builds the components (the executive, or a test with
scripted fakes). Behaviours never send velocities to the base: they write ``cmd_vel`` on the
blackboard, and the executive passes it through the safety gate; a tick in which no behaviour
wrote ``cmd_vel`` sends zero.

Keyword arguments of ``setup``:

=================== ======================================================================
``clock``           navcore.clock.Clock: the only source of time.
``robot``           RobotState: pose in ``map``, body velocity, battery, contact events.
``global_costmap``  CostmapHandle of the global (static-size) costmap.
``local_costmap``   CostmapHandle of the local (rolling-window) costmap.
``planners``        dict of planner id -> Planner (``"GridBased"`` is the default id).
``controllers``     dict of controller id -> Controller (``"FollowPath"`` is the default id).
``localizer``       Localizer or None.
``parameters``      dict of ROS namespace -> navcore.params.Parameters (for SetParameters).
``control_period``  float seconds, 1 / controller_frequency.
``route_graph``     navcore.route.RouteGraph or None (route_server.graph_filepath).
``route_path_density`` float m between poses of a route's path (route_server.path_density).
``observed_space``  navcore.costmap.observed_space.ObservedSpace or None: when each cell near
                    the robot was last seen free / occupied (independent of costmap clears).
=================== ======================================================================
"""

from __future__ import annotations

from typing import Any, Protocol

import numpy as np

from navcore.costmap.costmap2d import Costmap2D
from navcore.types import BaseEvents, BatteryState, Path, Pose2D, Twist


class RobotState(Protocol):
    def pose(self) -> Pose2D:
        """Current pose in ``map`` (localisation or ground truth)."""
        ...

    def velocity(self) -> Twist:
        """Current body velocity (from odometry)."""
        ...

    def battery(self) -> BatteryState | None:
        ...

    def events(self) -> BaseEvents:
        ...


class CostmapHandle(Protocol):
    costmap: Costmap2D  # the master grid

    def reset_layers(self) -> None:
        """Clear every layer (clear_costmap: everything)."""
        ...

    def clear_outside(self, x: float, y: float, reset_distance: float) -> None:
        """clear_costmap_recovery: reset clearable layers outside a square of side
        ``reset_distance`` centred on (x, y)."""
        ...

    def clear_inside(self, x: float, y: float, reset_distance: float) -> None:
        """Reset clearable layers inside that square (ClearCostmapAroundRobot)."""
        ...

    def footprint_cost(self, x: float, y: float, theta: float) -> int:
        """Max cost under the robot footprint at that pose; -1 if any of it is off the map."""
        ...


class PlanResultLike(Protocol):
    ok: bool
    path: Path | None
    reason: str  # navcore.planners.result.PlanReason (or its text): "" when ok, "no_path", ...


class Planner(Protocol):
    def make_plan(self, start: Pose2D, goal: Pose2D) -> PlanResultLike:
        ...


class ControlResultLike(Protocol):
    cmd: Twist
    status: str  # navcore.controllers.result.ControlStatus (or its text): "following", ...


class Controller(Protocol):
    def set_plan(self, path: Path) -> None:
        ...

    def compute_velocity(self, pose: Pose2D, velocity: Twist, path: Path | None = None
                         ) -> ControlResultLike:
        ...

    def is_goal_reached(self) -> bool:
        ...

    def reset(self) -> None:
        """Forget latched goal tolerance and oscillation flags (a new goal or a recovery)."""
        ...


class Localizer(Protocol):
    def covariance(self) -> np.ndarray:
        """3x3 (x, y, theta) covariance of the pose estimate."""
        ...

    def global_localization(self) -> None:
        """Spread particles over all free space."""
        ...

    def request_nomotion_update(self) -> None:
        ...


Components = dict[str, Any]
