"""costmap_2d::ObstacleLayer: marking and ray-trace clearing from laser scans and point clouds.

Observations arrive already in the costmap's global frame: ``add_scan(scan, sensor_pose)`` with
the laser's pose in that frame, or ``add_points(points, origin)``. Each observation source keeps
an observation buffer (``observation_persistence``, ``expected_update_rate``) on the injected
clock. An update clears along every ray of the clearing sources first (Bresenham, limited to
``raytrace_range``), then marks the end points of the marking sources closer than
``obstacle_range``, then frees the robot footprint.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Mapping

import numpy as np
from numba import njit

from navcore.clock import Clock, SimClock
from navcore.costmap.cost_values import FREE_SPACE, LETHAL_OBSTACLE
from navcore.costmap.costmap2d import Costmap2D
from navcore.costmap.footprint import transform_footprint
from navcore.costmap.layer import CostmapLayer, combination_name, grow_bounds, touch
from navcore.params import Param, ParameterError, Parameters
from navcore.types import LaserScan, Pose2D

OBSTACLE_PARAMS = (
    Param("enabled", True, bool, "whether the layer contributes"),
    Param("footprint_clearing_enabled", True, bool, "free the cells under the robot footprint"),
    Param("max_obstacle_height", 2.0, float, "points higher than this (m) are not marked"),
    Param("combination_method", 1, int, "0 overwrite, 1 maximum, 99 nothing", min=0, max=99),
    Param("track_unknown_space", False, bool, "unseen cells are NO_INFORMATION, else FREE"),
    Param("observation_sources", "", str, "space-separated names of observation sources"),
    Param("obstacle_range", 2.5, float, "default marking range (m) of the sources", min=0.0),
    Param("raytrace_range", 3.0, float, "default clearing range (m) of the sources", min=0.0),
)

SOURCE_PARAMS = (
    Param("topic", "", str, "source topic (kept for config compatibility)"),
    Param("sensor_frame", "", str, "sensor frame (kept for config compatibility)"),
    Param("observation_persistence", 0.0, float, "seconds an observation is kept; 0: newest only",
          min=0.0),
    Param("expected_update_rate", 0.0, float, "max seconds between readings; 0: no check",
          min=0.0),
    Param("data_type", "PointCloud", str, "kind of data",
          choices=("LaserScan", "PointCloud", "PointCloud2")),
    Param("min_obstacle_height", 0.0, float, "points lower than this (m) are dropped"),
    Param("max_obstacle_height", 2.0, float, "points higher than this (m) are dropped"),
    Param("inf_is_valid", False, bool, "an inf range means free space up to range_max"),
    Param("clearing", False, bool, "ray-trace free space with this source"),
    Param("marking", True, bool, "mark obstacles with this source"),
    Param("obstacle_range", 2.5, float, "marking range (m)", min=0.0),
    Param("raytrace_range", 3.0, float, "clearing range (m)", min=0.0),
)


@dataclass(frozen=True, slots=True)
class Observation:
    """Points (N, 3) and the sensor origin (3,), both in the costmap's global frame."""

    points: np.ndarray
    origin: np.ndarray
    obstacle_range: float
    raytrace_range: float


class ObservationBuffer:
    """costmap_2d ObservationBuffer: the observations of one source, aged on the clock."""

    def __init__(self, name: str, params: Parameters, clock: Clock) -> None:
        self.name = name
        self.params = params
        self.clock = clock
        self._obs: list[tuple[float, Observation]] = []
        self._last_updated = clock.now()  # as costmap_2d: current until the first deadline

    def add(self, obs: Observation) -> None:
        now = self.clock.now()
        self._obs.append((now, obs))
        self._last_updated = now
        self._purge()

    def _purge(self) -> None:
        # ages count from the newest reading, not from now (costmap_2d): a sensor that stops
        # leaves its last observations in place; is_current() is what reports the silence
        keep = self.params.observation_persistence
        if keep == 0.0:
            self._obs = self._obs[-1:]
        else:
            self._obs = [(t, o) for t, o in self._obs if self._last_updated - t <= keep]

    def observations(self) -> list[Observation]:
        self._purge()
        return [o for _, o in self._obs]

    def is_current(self) -> bool:
        """False when readings stopped for longer than ``expected_update_rate``."""
        rate = self.params.expected_update_rate
        if rate == 0.0:
            return True
        return self.clock.now() - self._last_updated <= rate

    def clear(self) -> None:
        self._obs = []


def scan_to_points(scan: LaserScan, sensor_pose: Pose2D, sensor_z: float = 0.0,
                   inf_is_valid: bool = False) -> np.ndarray:
    """End points (N, 3) of the valid beams of a scan, in the frame of ``sensor_pose``.

    Invalid readings (NaN, outside [range_min, range_max]) are dropped; with ``inf_is_valid`` an
    inf reading becomes a point just short of range_max, which clears without marking when
    range_max exceeds the obstacle range (costmap_2d laserScanValidInfCallback).
    """
    return _scan_points(scan.ranges, float(scan.angle_min), float(scan.angle_increment),
                        float(scan.range_min), float(scan.range_max), bool(inf_is_valid),
                        float(sensor_pose.x), float(sensor_pose.y), float(sensor_pose.theta),
                        float(sensor_z))


@njit(cache=True, nogil=True)
def _scan_points(ranges: np.ndarray, angle_min: float, angle_increment: float,
                 range_min: float, range_max: float, inf_is_valid: bool, x: float, y: float,
                 theta: float, z: float) -> np.ndarray:
    """The kernel of ``scan_to_points``: beam i at angle_min + angle_increment * i (as
    LaserScan.angles), the valid ones in beam order."""
    pts = np.empty((ranges.shape[0], 3))
    n = 0
    for i in range(ranges.shape[0]):
        r = float(ranges[i])
        if inf_is_valid and math.isinf(r) and r > 0:
            r = range_max - 0.0001
        if not (math.isfinite(r) and r >= range_min and r < range_max):
            continue
        a = (angle_min + angle_increment * float(i)) + theta
        pts[n, 0] = x + r * math.cos(a)
        pts[n, 1] = y + r * math.sin(a)
        pts[n, 2] = z
        n += 1
    return pts[:n]


@njit(cache=True, nogil=True)
def _kept_points(pts: np.ndarray, min_height: float, max_height: float) -> np.ndarray:
    """The rows of ``pts`` (N, 3) that are finite with min_height <= z <= max_height, in order,
    as a new C-contiguous array."""
    keep = np.empty(pts.shape[0], dtype=np.bool_)
    n = 0
    for i in range(pts.shape[0]):
        px, py, pz = pts[i, 0], pts[i, 1], pts[i, 2]
        keep[i] = (math.isfinite(px) and math.isfinite(py) and math.isfinite(pz)
                   and pz >= min_height and pz <= max_height)
        n += keep[i]
    out = np.empty((n, 3))
    k = 0
    for i in range(pts.shape[0]):
        if keep[i]:
            out[k, 0] = pts[i, 0]
            out[k, 1] = pts[i, 1]
            out[k, 2] = pts[i, 2]
            k += 1
    return out


@njit(cache=True, nogil=True)
def raytrace_line(costs: np.ndarray, x0: int, y0: int, x1: int, y1: int, max_length: int,
                  value: np.uint8) -> None:
    """costmap_2d raytraceLine: Bresenham from (x0, y0) toward (x1, y1), at most ``max_length``
    cells along the dominant axis, setting ``value``; the last cell reached is set too."""
    dx = x1 - x0
    dy = y1 - y0
    adx = abs(dx)
    ady = abs(dy)
    sx = 1 if dx > 0 else (-1 if dx < 0 else 0)
    sy = 1 if dy > 0 else (-1 if dy < 0 else 0)
    dist = math.sqrt(dx * dx + dy * dy)
    scale = 1.0 if dist == 0.0 else min(1.0, max_length / dist)
    x = x0
    y = y0
    if adx >= ady:
        err = adx // 2
        end = min(int(scale * adx), adx)
        for _ in range(end):
            costs[y, x] = value
            x += sx
            err += ady
            if err >= adx:
                y += sy
                err -= adx
    else:
        err = ady // 2
        end = min(int(scale * ady), ady)
        for _ in range(end):
            costs[y, x] = value
            y += sy
            err += adx
            if err >= ady:
                x += sx
                err -= ady
    costs[y, x] = value


@njit(cache=True, nogil=True)
def grow_bounds_to_ray_end(bounds: np.ndarray, ox: float, oy: float, wx: float, wy: float,
                           raytrace_range: float) -> None:
    """Grow ``bounds`` to the end of the clearing ray (ox, oy) -> (wx, wy) limited to
    ``raytrace_range`` (2-D), as raytraceFreespace's updateRaytraceBounds."""
    dx = wx - ox
    dy = wy - oy
    full = math.sqrt(dx * dx + dy * dy)
    scale = 1.0 if full == 0.0 else min(1.0, raytrace_range / full)
    grow_bounds(bounds, ox + dx * scale, oy + dy * scale)


@njit(cache=True, nogil=True)
def _raytrace_freespace(costs: np.ndarray, origin_x: float, origin_y: float, resolution: float,
                        ox: float, oy: float, points: np.ndarray, raytrace_range: float,
                        bounds: np.ndarray) -> bool:
    """Clear from the sensor origin to every point (clipped to the map), growing ``bounds``.
    False if the origin is off the map (nothing cleared)."""
    size_y, size_x = costs.shape
    if ox < origin_x or oy < origin_y:
        return False
    x0 = int((ox - origin_x) / resolution)
    y0 = int((oy - origin_y) / resolution)
    if x0 >= size_x or y0 >= size_y:
        return False
    end_x = origin_x + size_x * resolution
    end_y = origin_y + size_y * resolution
    cell_range = max(0, int(math.ceil(raytrace_range / resolution)))
    grow_bounds(bounds, ox, oy)
    for i in range(points.shape[0]):
        wx = points[i, 0]
        wy = points[i, 1]
        a = wx - ox
        bb = wy - oy
        # clip the end point to the map, moving along the ray
        if wx < origin_x:
            t = (origin_x - ox) / a
            wx = origin_x
            wy = oy + bb * t
        if wy < origin_y:
            t = (origin_y - oy) / bb
            wx = ox + a * t
            wy = origin_y
        if wx > end_x:
            t = (end_x - ox) / a
            wx = end_x - 0.001
            wy = oy + bb * t
        if wy > end_y:
            t = (end_y - oy) / bb
            wx = ox + a * t
            wy = end_y - 0.001
        if wx < origin_x or wy < origin_y:
            continue
        x1 = int((wx - origin_x) / resolution)
        y1 = int((wy - origin_y) / resolution)
        if x1 >= size_x or y1 >= size_y:
            continue
        raytrace_line(costs, x0, y0, x1, y1, cell_range, np.uint8(FREE_SPACE))
        grow_bounds_to_ray_end(bounds, ox, oy, wx, wy, raytrace_range)
    return True


@njit(cache=True, nogil=True)
def _mark(costs: np.ndarray, origin_x: float, origin_y: float, resolution: float,
          origin: np.ndarray, points: np.ndarray, obstacle_range: float, max_height: float,
          bounds: np.ndarray) -> None:
    """Mark LETHAL every point not higher than ``max_height`` and closer than ``obstacle_range``
    (3-D distance to the sensor origin), growing ``bounds``."""
    size_y, size_x = costs.shape
    sq = obstacle_range * obstacle_range
    for i in range(points.shape[0]):
        px = points[i, 0]
        py = points[i, 1]
        pz = points[i, 2]
        if pz > max_height:
            continue
        d2 = (px - origin[0]) ** 2 + (py - origin[1]) ** 2 + (pz - origin[2]) ** 2
        if d2 >= sq:
            continue
        if px < origin_x or py < origin_y:
            continue
        mx = int((px - origin_x) / resolution)
        my = int((py - origin_y) / resolution)
        if mx >= size_x or my >= size_y:
            continue
        costs[my, mx] = LETHAL_OBSTACLE
        grow_bounds(bounds, px, py)


def split_sources(name: str, params: Mapping[str, Any], specs: tuple[Param, ...]
                  ) -> tuple[dict, dict[str, dict]]:
    """Separate a layer namespace into its own parameters and its observation source namespaces.

    Sources are the names in ``observation_sources``; a source named there without a namespace,
    or a namespace not named there, is a ParameterError.
    """
    own = dict(params)
    raw = own.get("observation_sources", "")
    if isinstance(raw, (list, tuple)):
        own["observation_sources"] = " ".join(str(s) for s in raw)
        raw = own["observation_sources"]
    if not isinstance(raw, str):
        raise ParameterError(f"{name}: parameter 'observation_sources' must be a string of names, "
                             f"got {raw!r}")
    names = raw.split()
    sources: dict[str, dict] = {}
    for src in names:
        ns = own.pop(src, None)
        if ns is None:
            raise ParameterError(f"{name}: observation source '{src}' has no namespace "
                                 f"'{name}/{src}' (data_type, marking, clearing, ...)")
        if not isinstance(ns, Mapping):
            raise ParameterError(f"{name}/{src}: must be a mapping of parameters, got {ns!r}")
        sources[src] = dict(ns)
    known = {s.name for s in specs}
    for key, value in own.items():
        if key not in known and isinstance(value, Mapping):
            raise ParameterError(f"{name}: namespace '{key}' is not listed in observation_sources "
                                 f"{names!r}")
    return own, sources


class ObstacleLayer(CostmapLayer):
    """costmap_2d::ObstacleLayer. Feed it with ``add_scan`` / ``add_points``.

    ``inherited`` carries the values found further up the namespace (the costmap's
    ``obstacle_range``, ``raytrace_range``, ``track_unknown_space``) used as defaults. With no
    ``observation_sources`` configured, one implicit source named "default" marks and clears
    (so a bare ``plugins: [obstacle_layer]`` config is useful).
    """

    kind = "obstacle"
    clearable = True
    PARAMS = OBSTACLE_PARAMS

    def __init__(self, name: str, params: Mapping[str, Any] | None = None,
                 clock: Clock | None = None, inherited: Mapping[str, Any] | None = None,
                 extra_specs: tuple[Param, ...] = ()) -> None:
        inherited = dict(inherited or {})
        specs = self.PARAMS + extra_specs
        own, sources = split_sources(name, params or {}, specs)
        layer_defaults = {k: v for k, v in inherited.items()
                          if k in ("obstacle_range", "raytrace_range", "track_unknown_space")}
        self.params = Parameters(specs, {**layer_defaults, **own}, where=name)
        super().__init__(name, self.params.track_unknown_space)
        self.clock = clock if clock is not None else SimClock()
        self.footprint: np.ndarray | None = None
        self.buffers: dict[str, ObservationBuffer] = {}
        if not sources:
            sources = {"default": {"clearing": True, "marking": True}}
        for src, ns in sources.items():
            defaults = {"obstacle_range": self.params.obstacle_range,
                        "raytrace_range": self.params.raytrace_range}
            p = Parameters(SOURCE_PARAMS, {**defaults, **ns}, where=f"{name}/{src}")
            self.buffers[src] = ObservationBuffer(src, p, self.clock)
        self._robot = (0.0, 0.0, 0.0)

    # ------------------------------------------------------------ feeding

    def _buffer(self, source: str | None, kind: str) -> list[ObservationBuffer]:
        if source is not None:
            if source not in self.buffers:
                raise KeyError(f"{self.name}: no observation source '{source}' "
                               f"(have {sorted(self.buffers)})")
            return [self.buffers[source]]
        want = ("LaserScan",) if kind == "scan" else ("PointCloud", "PointCloud2")
        chosen = [b for b in self.buffers.values() if b.params.data_type in want]
        if not chosen and "default" in self.buffers:
            chosen = [self.buffers["default"]]
        if not chosen:
            chosen = list(self.buffers.values())[:1]
        return chosen

    def add_scan(self, scan: LaserScan, sensor_pose: Pose2D, sensor_z: float = 0.0,
                 source: str | None = None) -> None:
        """A laser scan taken at ``sensor_pose`` (the laser in the costmap's global frame).

        Goes to ``source``, else to every LaserScan source (else the implicit one)."""
        for buf in self._buffer(source, "scan"):
            pts = scan_to_points(scan, sensor_pose, sensor_z, buf.params.inf_is_valid)
            self._add(buf, pts, np.array([sensor_pose.x, sensor_pose.y, sensor_z]))

    def add_points(self, points: np.ndarray, origin, source: str | None = None) -> None:
        """Points (N, 3) in the global frame seen from the sensor ``origin`` (x, y, z)."""
        pts = np.asarray(points, dtype=np.float64)
        if pts.ndim != 2 or pts.shape[1] != 3:
            raise ValueError(f"{self.name}.add_points: points must be (N, 3), got {pts.shape}")
        org = np.asarray(origin, dtype=np.float64).reshape(-1)
        if org.shape != (3,):
            raise ValueError(f"{self.name}.add_points: origin must be (x, y, z), got {origin!r}")
        for buf in self._buffer(source, "points"):
            self._add(buf, pts, org)

    def _add(self, buf: ObservationBuffer, pts: np.ndarray, origin: np.ndarray) -> None:
        """Store an observation; non-finite points are dropped (they would index anywhere)."""
        if not np.all(np.isfinite(origin)):
            raise ValueError(f"{self.name}: sensor origin {origin!r} is not finite")
        p = buf.params
        pts = _kept_points(pts, float(p.min_obstacle_height), float(p.max_obstacle_height))
        buf.add(Observation(pts, origin.astype(np.float64), p.obstacle_range, p.raytrace_range))

    def is_current(self) -> bool:
        return all(b.is_current() for b in self.buffers.values())

    # ------------------------------------------------------------ update

    def reset(self) -> None:
        super().reset()
        for b in self.buffers.values():
            b.clear()

    def update_bounds(self, robot_x: float, robot_y: float, robot_yaw: float,
                      bounds: list[float]) -> None:
        if not self.enabled:
            return
        if self.rolling:
            g = self.grid
            self.update_origin(robot_x - g.size_x * g.resolution / 2,
                               robot_y - g.size_y * g.resolution / 2)
        self.use_extra_bounds(bounds)
        self.current = self.is_current()
        b = np.array(bounds, dtype=np.float64)
        self._raytrace_and_mark(b)
        bounds[:] = list(b)
        self._robot = (robot_x, robot_y, robot_yaw)
        if self.params.footprint_clearing_enabled and self.footprint is not None:
            for px, py in transform_footprint(self.footprint, robot_x, robot_y, robot_yaw):
                touch(bounds, float(px), float(py))

    def _raytrace_and_mark(self, b: np.ndarray) -> None:
        g = self.grid
        for buf in self.buffers.values():
            if buf.params.clearing:
                for o in buf.observations():
                    _raytrace_freespace(g.costs, g.origin_x, g.origin_y, g.resolution,
                                        float(o.origin[0]), float(o.origin[1]), o.points,
                                        o.raytrace_range, b)
        for buf in self.buffers.values():
            if buf.params.marking:
                for o in buf.observations():
                    _mark(g.costs, g.origin_x, g.origin_y, g.resolution, o.origin, o.points,
                          o.obstacle_range, self.params.max_obstacle_height, b)

    def update_costs(self, master: Costmap2D, x0: int, y0: int, xn: int, yn: int) -> None:
        if not self.enabled:
            return
        if self.params.footprint_clearing_enabled and self.footprint is not None:
            self.grid.set_convex_polygon_cost(transform_footprint(self.footprint, *self._robot),
                                              FREE_SPACE)
        method = combination_name(self.params.combination_method)
        if method is not None:
            self.combine(method, master, x0, y0, xn, yn)
