"""The Stack: the navigation components of one mission, built from a robot config.

This is the one place that knows how each component is constructed from its ROS namespace: the
global and local costmaps (navcore.costmap), the global planner (navcore.planners), the local
planner (navcore.controllers) and, when asked, AMCL (navcore.localization). The tree sees them
through ``components()``, the keyword arguments of ``tree.setup`` (behaviors/components.py).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from navcore.clock import Clock
from navcore.maps import OccupancyGrid
from navcore.params import Parameters
from navcore.types import Pose2D

from executive.config import RobotConfig
from executive.config_costmaps import make_costmap
from executive.errors import WiringError


def build_costmaps(config: RobotConfig, grid: OccupancyGrid, clock: Clock) -> tuple[Any, Any]:
    """The global and the local (rolling window) costmap, both with the robot's footprint."""
    fp = [list(p) for p in config.footprint()]
    g = config.ns("global_costmap")
    g.setdefault("footprint", fp)
    local = config.ns("local_costmap")
    local.setdefault("footprint", fp)
    local.setdefault("rolling_window", True)
    return (make_costmap(g, grid, "global_costmap", clock),
            make_costmap(local, grid, "local_costmap", clock))


def build_planner(config: RobotConfig, global_cm: Any) -> Any:
    """move_base's ``base_global_planner`` over the global costmap."""
    from navcore.planners import make_planner
    ns = config.global_planner_namespace()
    return make_planner(config.move_base.base_global_planner, global_cm.costmap, config.ns(ns),
                        global_cm.footprint_cost)


def build_controller(config: RobotConfig, local_cm: Any) -> Any:
    """move_base's ``base_local_planner`` over the local costmap."""
    from navcore.controllers import make_controller
    ns = config.local_planner_namespace()
    params = config.ns(ns)
    # as in ROS, the local planner's sim_period follows move_base's controller_frequency
    params.setdefault("controller_frequency", config.move_base.controller_frequency)
    # the costmap's padded footprint, as move_base hands the local planner the costmap's one
    return make_controller(config.move_base.base_local_planner, local_cm.costmap,
                           np.asarray(local_cm.footprint, np.float64), params)


def build_amcl(config: RobotConfig, grid: OccupancyGrid, start: Pose2D | None,
               rng: np.random.Generator) -> Any:
    """AMCL on ``grid``, starting at ``start`` unless the config gives ``initial_pose_*``."""
    from navcore.localization.amcl import Amcl
    params = config.ns("amcl")
    if start is not None:
        params.setdefault("initial_pose_x", start.x)
        params.setdefault("initial_pose_y", start.y)
        params.setdefault("initial_pose_a", start.theta)
    return Amcl(grid, params, rng)


def build_observed_space(config: RobotConfig, local_cm: Any) -> Any:
    """The short-term memory of observed space (navcore.costmap.observed_space): a window twice
    the local costmap's width and height at its resolution; motions are checked with the
    robot's own footprint, the body frees the local costmap's (padded) one."""
    from navcore.costmap.observed_space import ObservedSpace
    grid = local_cm.costmap
    res = grid.resolution
    return ObservedSpace.around(res, 2.0 * grid.size_x * res, 2.0 * grid.size_y * res,
                                config.footprint(), local_cm.footprint)


def build_route_graph(config: RobotConfig) -> Any:
    """The route graph of ``route_server.graph_filepath`` (None when not configured). A
    relative path is looked up beside the config file, then among the bundled maps."""
    import os
    from pathlib import Path as FsPath

    from navcore.route import RouteError, load_route_graph
    path = str(config.ns("route_server").get("graph_filepath") or "")
    if not path:
        return None
    candidates = [path] if os.path.isabs(path) else [
        os.path.join(os.path.dirname(str(config.source)), path),
        str(FsPath(__file__).resolve().parent / "data" / "maps" / path)]
    found = next((c for c in candidates if os.path.isfile(c)), None)
    if found is None:
        raise WiringError(f"{config.source}: route_server: graph_filepath '{path}' not found "
                          f"(looked in {', '.join(candidates)})")
    try:
        return load_route_graph(found)
    except RouteError as e:
        raise WiringError(str(e)) from None


@dataclass
class Stack:
    """The components one mission's tree calls; ``localizer`` is None on ground truth."""

    config: RobotConfig
    global_costmap: Any
    local_costmap: Any
    planner: Any
    controller: Any
    localizer: Any = None
    route_graph: Any = None  # navcore.route.RouteGraph when route_server.graph_filepath is set
    observed_space: Any = None  # navcore.costmap.observed_space.ObservedSpace

    @classmethod
    def from_config(cls, config: RobotConfig, grid: OccupancyGrid, clock: Clock) -> Stack:
        """Costmaps, planner and controller from ``config`` (a WiringError if one is missing)."""
        try:
            global_cm, local_cm = build_costmaps(config, grid, clock)
            planner = build_planner(config, global_cm)
            controller = build_controller(config, local_cm)
        except ImportError as e:
            raise WiringError(f"component not available: {e}") from None
        return cls(config, global_cm, local_cm, planner, controller,
                   route_graph=build_route_graph(config),
                   observed_space=build_observed_space(config, local_cm))

    def add_localizer(self, grid: OccupancyGrid, start: Pose2D | None,
                      rng: np.random.Generator) -> None:
        """AMCL from the config's ``amcl`` namespace. Built after the robot I/O, which draws
        from ``rng`` first: the order keeps every seed's run as it was."""
        self.localizer = build_amcl(self.config, grid, start, rng)

    def parameters(self) -> dict[str, Parameters]:
        """ROS namespace -> the live Parameters object each component reads (SetParameters's
        view). The components' own objects, not copies: a change takes effect at their next
        cycle."""
        config = self.config
        out: dict[str, Any] = dict(config.all_parameters())
        for cm in (self.global_costmap, self.local_costmap):
            out.update(cm.parameter_namespaces())
        if getattr(self.planner, "params", None) is not None:
            out[config.global_planner_namespace()] = self.planner.params
        if getattr(self.controller, "params", None) is not None:
            out[config.local_planner_namespace()] = self.controller.params
        if self.localizer is not None and getattr(self.localizer, "params", None) is not None:
            out["amcl"] = self.localizer.params
        return out

    def components(self) -> dict[str, Any]:
        """The keyword arguments of ``tree.setup`` (behaviors/components.py) for this stack."""
        return {
            "global_costmap": self.global_costmap,
            "local_costmap": self.local_costmap,
            "planners": {"GridBased": self.planner},
            "controllers": {"FollowPath": self.controller},
            "localizer": self.localizer,
            "parameters": self.parameters(),
            "route_graph": self.route_graph,
            "observed_space": self.observed_space,
            "route_path_density": float(self.config.ns("route_server").get("path_density",
                                                                             0.05)),
        }
