"""The map-only route: what the global planner would plan if every sensed obstacle were gone.

A plan much longer than the route on the static map alone is a detour round something the
sensors put in the costmap (a person who has left, a door that was closed); a goal with no
route even on the static map cannot be reached by any recovery. ``MapOnlyRoute`` composes the
global costmap's static layers and its inflation (no obstacle or voxel layers) into a costmap of
its own and plans on it with a planner of the same kind and parameters as the real one.
"""

from __future__ import annotations

from typing import Any

from navcore.costmap.cost_values import FREE_SPACE, NO_INFORMATION
from navcore.costmap.costmap2d import Costmap2D
from navcore.costmap.inflation import InflationLayer, inflate
from navcore.costmap.static_layer import StaticLayer
from navcore.planners.global_planner import GlobalPlanner
from navcore.planners.navfn import NavFn
from navcore.planners.result import PlanResult
from navcore.types import Path, Pose2D


def map_only_costmap(layered: Any) -> Costmap2D:
    """The master of ``layered`` (a LayeredCostmap) as its static layers and inflation alone
    make it: sensor layers left out, same size, origin and resolution."""
    m = layered.costmap
    default = NO_INFORMATION if layered.params.track_unknown_space else FREE_SPACE
    out = Costmap2D(m.size_x, m.size_y, m.resolution, m.origin_x, m.origin_y, default)
    for layer in layered.layers:
        if not layer.enabled:
            continue
        if isinstance(layer, StaticLayer):
            layer.update_costs(out, 0, 0, out.size_x, out.size_y)
        elif isinstance(layer, InflationLayer):
            # the layer's own table; inflate() itself, so the layer's window state is untouched
            inflate(out.costs, layer.table(), 0, 0, out.size_x, out.size_y,
                    layer.params.inflate_unknown)
    return out


def is_detour(path_length: float, map_length: float, ratio: float, min_extra: float) -> bool:
    """True when ``path_length`` is at least ``ratio`` times ``map_length`` AND at least
    ``min_extra`` metres longer (the second keeps short routes from counting: 0.5 m against 0.2
    m is not a detour worth a recovery)."""
    return path_length >= ratio * map_length and path_length - map_length >= min_extra


class MapOnlyRoute:
    """Plans on ``map_only_costmap(layered)`` with a planner like ``planner`` (navfn or
    global_planner, same parameters; anything else gets navfn's defaults). The map-only costmap
    is rebuilt only when the layered costmap moved, changed size or got a new static map."""

    def __init__(self, layered: Any, planner: Any = None) -> None:
        self.layered = layered
        self.template = planner
        self._key: tuple | None = None
        self._planner: Any = None

    @property
    def same_kind(self) -> bool:
        """True when the map-only plan is made by the real planner's kind (navfn or
        global_planner); otherwise it is navfn's, whose reasons may not be the real one's."""
        return isinstance(self.template, (NavFn, GlobalPlanner))

    @property
    def available(self) -> bool:
        """False for a costmap without layers (nothing to tell the static map apart by)."""
        return hasattr(self.layered, "layers") and hasattr(self.layered, "costmap")

    def _state_key(self) -> tuple:
        m = self.layered.costmap
        maps = tuple(id(getattr(l, "map", None)) for l in self.layered.layers
                     if isinstance(l, StaticLayer))
        infl = tuple(l.table().tobytes() for l in self.layered.layers
                     if isinstance(l, InflationLayer) and l.enabled)
        return (m.size_x, m.size_y, m.resolution, m.origin_x, m.origin_y, maps, infl)

    def planner(self) -> Any:
        key = self._state_key()
        if self._planner is None or key != self._key:
            cm = map_only_costmap(self.layered)
            t = self.template
            if isinstance(t, (NavFn, GlobalPlanner)):
                self._planner = type(t)(cm, t.params.as_dict())
            else:
                self._planner = NavFn(cm)
            self._key = key
        return self._planner

    def plan(self, start: Pose2D, goal: Pose2D) -> PlanResult:
        """The map-only plan from ``start`` to ``goal`` (or why there is none)."""
        return self.planner().make_plan(start, goal)

    def length(self, start: Pose2D, goal: Pose2D) -> float | None:
        """Length in metres of the map-only plan; None when there is none."""
        r = self.plan(start, goal)
        if not r.ok or r.path is None or len(r.path) == 0:
            return None
        return Path.length(r.path)
