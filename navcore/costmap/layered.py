"""LayeredCostmap: the master grid composed from its layers in plugin order (costmap_2d semantics).

Built from a ROS costmap namespace (``costmap_common_params.yaml`` + ``global_costmap`` /
``local_costmap`` style) by ``LayeredCostmap.from_params``: ``plugins`` (names, or {name, type}
dicts), one namespace per layer, ``footprint`` / ``robot_radius``, ``rolling_window``, ``width``,
``height``, ``resolution``, ``track_unknown_space`` ... A namespace without ``plugins`` is read
the pre-Hydro way, as costmap_2d does: ``static_map`` adds a static layer, ``map_type: voxel``
picks the voxel layer, and the top-level obstacle and inflation parameters move into the layers.
"""

from __future__ import annotations

import math
from typing import Any, Iterable, Mapping

import numpy as np

from navcore.clock import Clock, SimClock
from navcore.costmap.cost_values import FREE_SPACE, NO_INFORMATION
from navcore.costmap.costmap2d import Costmap2D
from navcore.costmap.footprint import (circumscribed_radius, footprint_cost, footprint_costs,
                                       inscribed_radius, make_footprint)
from navcore.costmap.inflation import InflationLayer
from navcore.costmap.obstacle_layer import ObstacleLayer
from navcore.costmap.static_layer import StaticLayer
from navcore.costmap.voxel_layer import VoxelLayer
from navcore.maps import OccupancyGrid
from navcore.params import Param, ParameterError, Parameters
from navcore.types import LaserScan, Pose2D

COSTMAP_PARAMS = (
    Param("global_frame", "map", str, "frame of the costmap"),
    Param("robot_base_frame", "base_link", str, "frame of the robot base"),
    Param("transform_tolerance", 0.3, float, "seconds of transform delay tolerated", min=0.0),
    Param("update_frequency", 5.0, float, "Hz of map updates", min=0.0),
    Param("publish_frequency", 0.0, float, "Hz of map publication", min=0.0),
    Param("width", 10.0, float, "width (m), unless a static map sets it", min=0.0),
    Param("height", 10.0, float, "height (m), unless a static map sets it", min=0.0),
    Param("resolution", 0.05, float, "metres per cell, unless a static map sets it", min=1e-6),
    Param("origin_x", 0.0, float, "x (m) of the grid's corner"),
    Param("origin_y", 0.0, float, "y (m) of the grid's corner"),
    Param("robot_radius", 0.46, float, "radius (m) of a round robot when no footprint", min=0.0),
    Param("footprint_padding", 0.01, float, "metres added around the footprint"),
    Param("rolling_window", False, bool, "the grid follows the robot"),
    Param("track_unknown_space", False, bool, "unseen cells are NO_INFORMATION, else FREE"),
    Param("always_send_full_costmap", False, bool, "kept for config compatibility"),
    Param("footprint_topic", "footprint", str, "kept for config compatibility"),
    Param("use_sim_time", False, bool, "kept for config compatibility (time is the Clock's)"),
    # found here by the layers searching up the namespace
    Param("obstacle_range", 2.5, float, "default marking range (m) of obstacle sources", min=0.0),
    Param("raytrace_range", 3.0, float, "default clearing range (m) of obstacle sources",
          min=0.0),
)

# pre-Hydro (no ``plugins``) top-level names and the layer they move into (Costmap2DROS
# resetOldParameters)
_LEGACY_STATIC = ("map_topic", "unknown_cost_value", "lethal_cost_threshold")
_LEGACY_OBSTACLE = ("max_obstacle_height", "raytrace_range", "obstacle_range",
                    "observation_sources")
_LEGACY_VOXEL = ("origin_z", "z_resolution", "z_voxels", "mark_threshold", "unknown_threshold",
                 "publish_voxel_map")
_LEGACY_INFLATION = ("cost_scaling_factor", "inflation_radius")

_TYPES = {
    "static": StaticLayer, "obstacle": ObstacleLayer, "voxel": VoxelLayer,
    "inflation": InflationLayer,
}


def plugin_kind(name: str, type_name: str | None, where: str) -> str:
    """Layer kind of a plugin from its type ("costmap_2d::VoxelLayer", "nav2_costmap_2d::...")
    or, when only a name is given, from the name ("static_layer", "obstacles", "inflater")."""
    text = (type_name or name).lower()
    for key, kind in (("static", "static"), ("voxel", "voxel"), ("obstacle", "obstacle"),
                      ("inflat", "inflation")):
        if key in text:
            return kind
    what = f"type '{type_name}'" if type_name else f"name '{name}'"
    raise ParameterError(f"{where}: plugin {what} is not a known layer (static, obstacle, voxel "
                         f"or inflation); give it a type such as costmap_2d::ObstacleLayer")


def _legacy_plugins(params: dict) -> tuple[list[dict], dict]:
    """costmap_2d's pre-Hydro conversion: returns the plugin list and the rewritten namespace."""
    p = dict(params)
    plugins: list[dict] = []
    if p.pop("static_map", False):
        plugins.append({"name": "static_layer", "type": "costmap_2d::StaticLayer"})
        ns = dict(p.get("static_layer", {}))
        for k in _LEGACY_STATIC:
            if k in p:
                ns[k] = p.pop(k)
        if "track_unknown_space" in p:
            ns["track_unknown_space"] = p["track_unknown_space"]
        p["static_layer"] = ns
    voxel = p.pop("map_type", "costmap") == "voxel"
    plugins.append({"name": "obstacle_layer",
                    "type": "costmap_2d::VoxelLayer" if voxel else "costmap_2d::ObstacleLayer"})
    ns = dict(p.get("obstacle_layer", {}))
    for k in _LEGACY_OBSTACLE + (_LEGACY_VOXEL if voxel else ()):
        if k in p:
            ns[k] = p.pop(k)
    if "track_unknown_space" in p:
        ns["track_unknown_space"] = p["track_unknown_space"]
    sources = ns.get("observation_sources", "")
    for src in (sources.split() if isinstance(sources, str) else list(sources)):
        if src in p:
            ns[src] = p.pop(src)
    p["obstacle_layer"] = ns
    plugins.append({"name": "inflation_layer", "type": "costmap_2d::InflationLayer"})
    ns = dict(p.get("inflation_layer", {}))
    for k in _LEGACY_INFLATION:
        if k in p:
            ns[k] = p.pop(k)
    p["inflation_layer"] = ns
    return plugins, p


def _parse_plugins(raw: Any, where: str) -> list[dict]:
    if not isinstance(raw, (list, tuple)):
        raise ParameterError(f"{where}: parameter 'plugins' must be a list, got {raw!r}")
    out = []
    for i, item in enumerate(raw):
        if isinstance(item, str):
            out.append({"name": item, "type": None})
        elif isinstance(item, Mapping) and "name" in item:
            extra = set(item) - {"name", "type", "enabled"}
            if extra:
                raise ParameterError(f"{where}: plugins[{i}] has unknown key(s) {sorted(extra)}")
            out.append({"name": str(item["name"]), "type": item.get("type"),
                        "enabled": item.get("enabled")})
        else:
            raise ParameterError(f"{where}: plugins[{i}] must be a name or {{name, type}}, "
                                 f"got {item!r}")
    names = [p["name"] for p in out]
    if len(set(names)) != len(names):
        raise ParameterError(f"{where}: plugin names must be unique, got {names}")
    return out


class LayeredCostmap:
    """The master ``costmap`` composed from ``layers`` in plugin order (costmap_2d semantics).

    Implements behaviors.components.CostmapHandle. Feed sensor data with ``add_scan`` /
    ``add_points`` (forwarded to every obstacle and voxel layer), then call ``update_map`` with
    the robot pose in the costmap's global frame.
    """

    def __init__(self, params: Parameters, layers: list, footprint: np.ndarray,
                 static_map: OccupancyGrid | None = None, name: str = "costmap",
                 clock: Clock | None = None) -> None:
        self.name = name
        self.params = params
        self.layers = layers
        self.clock = clock if clock is not None else SimClock()
        self.rolling = bool(params.rolling_window)
        default = NO_INFORMATION if params.track_unknown_space else FREE_SPACE
        res = params.resolution
        self.costmap = Costmap2D(max(1, int(params.width / res)), max(1, int(params.height / res)),
                                 res, params.origin_x, params.origin_y, default)
        self.size_locked = False
        self.current = True
        self.last_error = ""  # why the last update_map did nothing, if it did nothing
        self.warnings: list[str] = []  # parameters accepted but without effect, as in ROS
        self._last_pose: Pose2D | None = None
        self.last_window: tuple[int, int, int, int] | None = None
        # queue_scan's scan not yet added to the layers (see there); False: add every scan at once
        self.defer_scans = True
        self._pending_scan: tuple[LaserScan, Pose2D] | None = None
        for layer in layers:
            layer.rolling = self.rolling
        self._match_size()
        if static_map is not None:
            self.set_static_map(static_map)
        elif any(isinstance(l, StaticLayer) for l in layers):
            raise ParameterError(f"{name}: a static layer needs a map (pass static_map)")
        self.set_footprint(footprint)
        # a kept scan is added with the parameters it arrived under (obstacle_range, heights,
        # persistence...), as it would have been at once
        for p in self.parameter_namespaces().values():
            p.before_change(self._add_pending_scan, weak=True)  # no cycle through them

    # ------------------------------------------------------------ construction

    @classmethod
    def from_params(cls, params: Mapping[str, Any], static_map: OccupancyGrid | None = None,
                    name: str = "global_costmap", clock: Clock | None = None) -> "LayeredCostmap":
        """Build from a ROS costmap namespace dict; unknown parameters are ParameterErrors."""
        if not isinstance(params, Mapping):
            raise ParameterError(f"{name}: expected a mapping of parameters, got {params!r}")
        raw = dict(params)
        warnings: list[str] = []
        if "plugins" in raw:
            plugins = _parse_plugins(raw.pop("plugins"), name)
            for k in ("static_map", "map_type") + _LEGACY_INFLATION:
                if k in raw:
                    warnings.append(f"{name}: '{k}' has no effect when 'plugins' is given "
                                    f"(as in costmap_2d); set it in the layer's namespace")
                    raw.pop(k)
            for k in ("max_obstacle_height", "observation_sources") + _LEGACY_VOXEL:
                if k in raw:
                    raise ParameterError(
                        f"{name}: parameter '{k}' belongs in an obstacle or voxel layer's "
                        f"namespace when 'plugins' is given (e.g. obstacle_layer: {{{k}: ...}})")
        else:
            plugins, raw = _legacy_plugins(raw)
        namespaces = {}
        for p in plugins:
            ns = raw.pop(p["name"], {})
            if ns is None:
                ns = {}
            if not isinstance(ns, Mapping):
                raise ParameterError(f"{name}/{p['name']}: must be a mapping of parameters, "
                                     f"got {ns!r}")
            ns = dict(ns)
            if p.get("enabled") is not None:
                ns.setdefault("enabled", p["enabled"])
            if "plugin" in ns:  # Nav2 puts the type inside the layer's namespace
                p["type"] = p["type"] or ns.pop("plugin")
            namespaces[p["name"]] = ns
        fp_raw = raw.pop("footprint", None)
        cp = Parameters(COSTMAP_PARAMS, raw, where=name)
        try:
            fp = make_footprint(fp_raw, cp.robot_radius, cp.footprint_padding)
        except ValueError as e:
            raise ParameterError(f"{name}: {e}") from None
        inherited = {"obstacle_range": cp.obstacle_range, "raytrace_range": cp.raytrace_range,
                     "track_unknown_space": cp.track_unknown_space}
        layers = []
        for p in plugins:
            kind = plugin_kind(p["name"], p["type"], name)
            lname = f"{name}/{p['name']}"
            ns = namespaces[p["name"]]
            if kind == "static":
                layer = StaticLayer(lname, ns)
            elif kind in ("obstacle", "voxel"):
                layer = _TYPES[kind](lname, ns, clock, inherited)
            else:
                layer = InflationLayer(lname, ns, resolution=cp.resolution)
            layer.plugin_name = p["name"]
            layers.append(layer)
        out = cls(cp, layers, fp, static_map, name, clock)
        out.warnings = warnings
        return out

    def _match_size(self) -> None:
        m = self.costmap
        for layer in self.layers:
            layer.match_size(m.size_x, m.size_y, m.resolution, m.origin_x, m.origin_y)

    def set_static_map(self, grid: OccupancyGrid) -> None:
        """Give the static layer(s) a map; a static-size costmap takes the map's geometry."""
        statics = [l for l in self.layers if isinstance(l, StaticLayer)]
        if not statics:
            raise ParameterError(f"{self.name}: a static map was given but no static layer is "
                                 f"configured in 'plugins'")
        for layer in statics:
            m = layer.set_map(grid)
        if not self.rolling:
            self.costmap.resize(m.size_x, m.size_y, m.resolution, m.origin_x, m.origin_y)
            self.size_locked = True
            self._match_size()

    def set_footprint(self, footprint: np.ndarray) -> None:
        """A new (padded) footprint polygon (N, 2); layers that depend on it are told."""
        self.footprint = np.ascontiguousarray(footprint, dtype=np.float64)
        self.inscribed_radius = inscribed_radius(self.footprint)
        self.circumscribed_radius = circumscribed_radius(self.footprint)
        for layer in self.layers:
            if hasattr(layer, "footprint"):
                layer.footprint = self.footprint
            layer.on_footprint_changed(self.inscribed_radius, self.circumscribed_radius)

    # ------------------------------------------------------------ sensing

    def obstacle_layers(self) -> list[ObstacleLayer]:
        return [l for l in self.layers if isinstance(l, ObstacleLayer)]

    def add_scan(self, scan: LaserScan, sensor_pose: Pose2D, sensor_z: float = 0.0,
                 source: str | None = None) -> None:
        """A scan taken with the laser at ``sensor_pose`` in this costmap's global frame; goes
        to every obstacle / voxel layer (to its LaserScan sources, see ObstacleLayer)."""
        for layer in self.obstacle_layers():
            if source is None or source in layer.buffers:
                layer.add_scan(scan, sensor_pose, sensor_z, source)

    def queue_scan(self, scan: LaserScan, sensor_pose: Pose2D) -> None:
        """``add_scan`` for a costmap fed every control cycle, done lazily when it can be.

        When every sensor buffer keeps only its newest reading and checks no reading rate
        (ROS's defaults: ``observation_persistence`` and ``expected_update_rate`` 0), only the
        last scan before the buffers are read matters: the scan is kept and added (converted to
        points) just before the next ``update_map``, clear or parameter change; a reset drops
        it, as it would have emptied the buffers. The map is exactly as with every scan added
        at once, at one conversion per update instead of one per scan. Scans are values:
        nobody changes one after publishing it."""
        if (self.defer_scans and math.isfinite(sensor_pose.x) and math.isfinite(sensor_pose.y)
                and self._newest_only()):  # (an unusable pose still fails at once)
            self._pending_scan = (scan, sensor_pose)
        else:
            self._add_pending_scan()
            self.add_scan(scan, sensor_pose)

    def _newest_only(self) -> bool:
        for layer in self.obstacle_layers():
            for buf in layer.buffers.values():
                p = buf.params
                if p.observation_persistence != 0.0 or p.expected_update_rate != 0.0:
                    return False
        return True

    def _add_pending_scan(self, _new_values: Any = None) -> None:
        item = self._pending_scan
        if item is not None:
            self._pending_scan = None
            self.add_scan(*item)

    def add_points(self, points: np.ndarray, origin, source: str | None = None) -> None:
        """Points (N, 3) in the global frame seen from ``origin`` (x, y, z)."""
        for layer in self.obstacle_layers():
            if source is None or source in layer.buffers:
                layer.add_points(points, origin, source)

    def is_current(self) -> bool:
        """False if a sensor source missed its ``expected_update_rate`` or the last update
        failed (see ``last_error``)."""
        return self.current and all(l.current for l in self.layers)

    # ------------------------------------------------------------ update

    def update_map(self, robot_pose: Pose2D) -> tuple[int, int, int, int] | None:
        """One costmap_2d updateMap: move a rolling window to the robot, collect the layers'
        bounds, reset that window of the master and let each layer write it in plugin order.

        Returns the cell window [x0, xn) x [y0, yn) that was recomposed, or None.
        """
        self._add_pending_scan()
        x, y, yaw = float(robot_pose.x), float(robot_pose.y), float(robot_pose.theta)
        if not (math.isfinite(x) and math.isfinite(y) and math.isfinite(yaw)):
            # called from the control loop: report, do not raise; the map stays as it was
            self.last_error = f"{self.name}: robot pose {robot_pose} is not finite; not updated"
            self.current = False
            return None
        self.last_error = ""
        self._last_pose = Pose2D(x, y, yaw)
        m = self.costmap
        if self.rolling:
            m.update_origin(x - m.size_x * m.resolution / 2, y - m.size_y * m.resolution / 2)
        bounds = [1e30, 1e30, -1e30, -1e30]
        for layer in self.layers:
            if layer.enabled:
                layer.update_bounds(x, y, yaw, bounds)
        x0, y0 = m.world_to_map_enforce_bounds(bounds[0], bounds[1])
        xn, yn = m.world_to_map_enforce_bounds(bounds[2], bounds[3])
        x0, y0 = max(0, x0), max(0, y0)
        xn, yn = min(m.size_x, xn + 1), min(m.size_y, yn + 1)
        self.current = all(l.current for l in self.layers)
        if xn < x0 or yn < y0:
            return None
        m.reset(x0, y0, xn, yn)
        for layer in self.layers:
            if layer.enabled:
                layer.update_costs(m, x0, y0, xn, yn)
        self.last_window = (x0, y0, xn, yn)
        return self.last_window

    def _recompose(self) -> None:
        """Redraw the whole master from the layers at the last pose (after a clear or reset)."""
        if self._last_pose is not None:
            self.update_map(self._last_pose)

    # ------------------------------------------------------------ clearing

    def reset_layers(self) -> None:
        """Clear every layer and the master (clear_costmap: everything); the static map and
        fresh sensor data come back on the next update."""
        self._pending_scan = None
        self.costmap.reset()
        for layer in self.layers:
            layer.reset()
        self._recompose()

    def _clearable(self, layer_names: Iterable[str] | None) -> list:
        if layer_names is None:
            return [l for l in self.layers if l.clearable]
        names = set(layer_names)
        return [l for l in self.layers if getattr(l, "plugin_name", l.name) in names
                and hasattr(l, "clear_area")]

    def _clear(self, x: float, y: float, reset_distance: float, invert: bool,
               layer_names: Iterable[str] | None) -> None:
        self._add_pending_scan()   # the clear must see every scan that came before it
        half = reset_distance / 2.0
        for layer in self._clearable(layer_names):
            g = layer.grid
            # worldToMapNoBounds truncates toward zero
            sx = int((x - half - g.origin_x) / g.resolution)
            sy = int((y - half - g.origin_y) / g.resolution)
            ex = int((x + half - g.origin_x) / g.resolution)
            ey = int((y + half - g.origin_y) / g.resolution)
            layer.clear_area(sx, sy, ex, ey, invert)
        self._recompose()

    def clear_outside(self, x: float, y: float, reset_distance: float,
                      layer_names: Iterable[str] | None = None) -> None:
        """clear_costmap_recovery: NO_INFORMATION in the clearable layers outside the square of
        side ``reset_distance`` centred on (x, y); the master is recomposed at once.

        ``layer_names`` picks layers by plugin name (ROS ``layer_names``); None means every
        obstacle and voxel layer (ROS's default ["obstacles"] only matches a layer so named).
        """
        self._clear(x, y, reset_distance, False, layer_names)

    def clear_inside(self, x: float, y: float, reset_distance: float,
                     layer_names: Iterable[str] | None = None) -> None:
        """The same inside the square (``invert_area_to_clear``, ClearCostmapAroundRobot)."""
        self._clear(x, y, reset_distance, True, layer_names)

    # ------------------------------------------------------------ parameters

    def parameter_namespaces(self) -> dict[str, Parameters]:
        """Every live Parameters object by its ROS namespace ("local_costmap",
        "local_costmap/inflation_layer", "local_costmap/obstacle_layer/scan", ...), for the
        executive's SetParameters. Changes take effect at the next ``update_map``."""
        out: dict[str, Parameters] = {self.name: self.params}
        for layer in self.layers:
            ns = f"{self.name}/{getattr(layer, 'plugin_name', layer.name)}"
            out[ns] = layer.params
            for src, buf in getattr(layer, "buffers", {}).items():
                out[f"{ns}/{src}"] = buf.params
        return out

    # ------------------------------------------------------------ queries

    def footprint_cost(self, x: float, y: float, theta: float) -> int:
        """Max master cost under the footprint at (x, y, theta); -1 if any of it is off the map."""
        m = self.costmap
        return int(footprint_cost(m.costs, m.origin_x, m.origin_y, m.resolution, self.footprint,
                                  float(x), float(y), float(theta)))

    def footprint_costs(self, poses: np.ndarray) -> np.ndarray:
        """``footprint_cost`` of each (x, y, theta) row of ``poses`` (N, 3), in one numba call."""
        p = np.ascontiguousarray(poses, dtype=np.float64).reshape(-1, 3)
        m = self.costmap
        return footprint_costs(m.costs, m.origin_x, m.origin_y, m.resolution, self.footprint, p)

    def layer(self, plugin_name: str):
        """The layer of that plugin name."""
        for l in self.layers:
            if getattr(l, "plugin_name", None) == plugin_name or l.name == plugin_name:
                return l
        raise KeyError(f"{self.name}: no layer '{plugin_name}' "
                       f"(have {[getattr(l, 'plugin_name', l.name) for l in self.layers]})")
