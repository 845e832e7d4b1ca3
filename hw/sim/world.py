"""The simulated world: a static occupancy grid plus objects the map does not know.

Objects are boxes, circles, thin poles and polygons, optionally present only between ``appear``
and ``disappear`` times, and moving obstacles that follow scripted waypoints at a speed with a
pause at each waypoint. For the numba kernels the world at time t reduces to two arrays: circles
(N, 3: cx, cy, r) and segments (M, 4: ax, ay, bx, by); boxes and polygons become their edges.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Iterable, Sequence, Union

import numpy as np

from navcore.maps import OccupancyGrid
from navcore.raycast import clearance_field
from hw.errors import HwError


class WorldError(HwError, ValueError):
    """An object or world description is malformed; the message names the object and field."""


def first_after(t: float, times: Iterable[float]) -> float:
    """The earliest of ``times`` strictly after t (inf if none): where a physics chunk must end
    so that a scheduled change (an object appearing, a fault starting or ending) is on time."""
    return min((s for s in times if s > t), default=math.inf)


def _finite(where: str, **values: float) -> None:
    for k, v in values.items():
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
            raise WorldError(f"{where}: {k} must be a finite number, got {v!r}")


@dataclass(frozen=True)
class Circle:
    """A round object of radius ``r`` centred at (x, y)."""

    x: float
    y: float
    r: float
    appear: float = -math.inf
    disappear: float = math.inf
    name: str = ""

    def __post_init__(self) -> None:
        _finite(f"Circle {self.name!r}", x=self.x, y=self.y, r=self.r)
        if self.r <= 0:
            raise WorldError(f"Circle {self.name!r}: radius must be > 0, got {self.r}")


def Pole(x: float, y: float, r: float = 0.02, appear: float = -math.inf,
         disappear: float = math.inf, name: str = "") -> Circle:
    """A thin pole (a table leg, a chair strut): a circle of a few centimetres, thinner than a
    map cell, so the static map could never hold it."""
    return Circle(x, y, r, appear, disappear, name)


@dataclass(frozen=True)
class Polygon:
    """A solid polygon with vertices ``points`` [(x, y), ...] (at least 2: two points = a thin
    wall of zero thickness)."""

    points: tuple[tuple[float, float], ...]
    appear: float = -math.inf
    disappear: float = math.inf
    name: str = ""

    def __post_init__(self) -> None:
        pts = tuple((float(p[0]), float(p[1])) for p in self.points)
        if len(pts) < 2:
            raise WorldError(f"Polygon {self.name!r}: needs at least 2 points, got {len(pts)}")
        for p in pts:
            _finite(f"Polygon {self.name!r}", x=p[0], y=p[1])
        object.__setattr__(self, "points", pts)

    def segments(self) -> np.ndarray:
        p = np.asarray(self.points, np.float64)
        if len(p) == 2:
            return np.array([[p[0, 0], p[0, 1], p[1, 0], p[1, 1]]])
        q = np.roll(p, -1, axis=0)
        return np.concatenate([p, q], axis=1)


def Box(x0: float, y0: float, x1: float, y1: float, appear: float = -math.inf,
        disappear: float = math.inf, name: str = "") -> Polygon:
    """An axis-aligned box between corners (x0, y0) and (x1, y1)."""
    _finite(f"Box {name!r}", x0=x0, y0=y0, x1=x1, y1=y1)
    xa, xb = sorted((float(x0), float(x1)))
    ya, yb = sorted((float(y0), float(y1)))
    if xa == xb or ya == yb:
        raise WorldError(f"Box {name!r}: zero width or height ({x0}, {y0}, {x1}, {y1})")
    return Polygon(((xa, ya), (xb, ya), (xb, yb), (xa, yb)), appear, disappear, name)


@dataclass(frozen=True)
class MovingObstacle:
    """A circle of ``radius`` (or an axis-aligned box of ``half_extents``) that waits at the first
    waypoint until ``start_time``, then travels waypoint to waypoint at ``speed`` m/s, pausing
    ``pauses[i]`` seconds on arriving at waypoint i. With ``loop`` it returns to the first
    waypoint and repeats; otherwise it stays at the last one."""

    waypoints: tuple[tuple[float, float], ...]
    speed: float = 0.5
    radius: float = 0.25
    half_extents: tuple[float, float] | None = None
    pauses: tuple[float, ...] = ()
    start_time: float = 0.0
    loop: bool = False
    appear: float = -math.inf
    disappear: float = math.inf
    name: str = ""
    _legs: np.ndarray = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        where = f"MovingObstacle {self.name!r}"
        pts = tuple((float(p[0]), float(p[1])) for p in self.waypoints)
        if not pts:
            raise WorldError(f"{where}: waypoints must not be empty")
        for p in pts:
            _finite(where, waypoint_x=p[0], waypoint_y=p[1])
        _finite(where, speed=self.speed, radius=self.radius, start_time=self.start_time)
        if self.speed <= 0:
            raise WorldError(f"{where}: speed must be > 0, got {self.speed}")
        if self.half_extents is None and self.radius <= 0:
            raise WorldError(f"{where}: radius must be > 0, got {self.radius}")
        if self.half_extents is not None and (len(self.half_extents) != 2
                                              or min(self.half_extents) <= 0):
            raise WorldError(f"{where}: half_extents must be two numbers > 0")
        pauses = tuple(float(p) for p in self.pauses)
        if pauses and len(pauses) != len(pts):
            raise WorldError(f"{where}: {len(pauses)} pauses for {len(pts)} waypoints")
        if any(p < 0 for p in pauses):
            raise WorldError(f"{where}: pauses must be >= 0")
        pauses = pauses or (0.0,) * len(pts)
        object.__setattr__(self, "waypoints", pts)
        object.__setattr__(self, "pauses", pauses)
        # legs: (start time offset, duration, from, to) including the pause on arrival
        route = list(pts) + ([pts[0]] if self.loop and len(pts) > 1 else [])
        legs = []
        t = 0.0
        for i in range(len(route) - 1):
            a, b = route[i], route[i + 1]
            d = math.hypot(b[0] - a[0], b[1] - a[1]) / self.speed
            legs.append((t, d, a[0], a[1], b[0], b[1]))
            t += d
            pause = pauses[(i + 1) % len(pts)]
            if pause > 0:
                legs.append((t, pause, b[0], b[1], b[0], b[1]))
                t += pause
        object.__setattr__(self, "_legs", np.array(legs, np.float64).reshape(-1, 6))

    def position(self, t: float) -> tuple[float, float]:
        """Centre of the obstacle at time t."""
        legs = self._legs
        if t <= self.start_time or len(legs) == 0:
            return self.waypoints[0]
        s = t - self.start_time
        period = legs[-1, 0] + legs[-1, 1]
        if self.loop:
            s = s % period if period > 0 else 0.0
        elif s >= period:
            return self.waypoints[-1]
        i = int(np.searchsorted(legs[:, 0], s, side="right")) - 1
        t0, d, ax, ay, bx, by = legs[max(i, 0)]
        f = 0.0 if d <= 0 else min(max((s - t0) / d, 0.0), 1.0)
        return ax + f * (bx - ax), ay + f * (by - ay)


WorldObject = Union[Circle, Polygon, MovingObstacle]


def _present(o: WorldObject, t: float) -> bool:
    return o.appear <= t < o.disappear


class SimWorld:
    """The simulator's physical world (what the robot collides with and the laser sees): an
    ``OccupancyGrid`` (cells >= ``occupied_value`` are solid; unknown cells are solid only
    with ``unknown_is_obstacle``) plus objects. ``shapes_at(t)`` gives the kernels' arrays."""

    def __init__(self, grid: OccupancyGrid, objects: Sequence[WorldObject] = (),
                 unknown_is_obstacle: bool = False, occupied_value: int = 65) -> None:
        if not isinstance(grid, OccupancyGrid):
            raise WorldError(f"SimWorld: grid must be an OccupancyGrid, got {type(grid).__name__}")
        if grid.origin.theta != 0.0:
            raise WorldError("SimWorld: maps with a rotated origin are not supported "
                             f"(origin yaw {grid.origin.theta})")
        self.grid = grid
        blocked = grid.data >= occupied_value
        if unknown_is_obstacle:
            blocked |= grid.data < 0
        self.blocked = np.ascontiguousarray(blocked, dtype=np.uint8)
        self.clearance = clearance_field(self.blocked)
        self.origin_x = float(grid.origin.x)
        self.origin_y = float(grid.origin.y)
        self.resolution = float(grid.resolution)
        self._objects: list[WorldObject] = []
        self._timed = False
        self._moving = False
        self._cache_key: tuple | None = None
        self._cache: tuple[np.ndarray, np.ndarray] = (np.zeros((0, 3)), np.zeros((0, 4)))
        for o in objects:
            self.add(o)

    @property
    def objects(self) -> tuple[WorldObject, ...]:
        return tuple(self._objects)

    def add(self, obj: WorldObject) -> WorldObject:
        """Put an object into the world (it still honours its own appear/disappear times)."""
        if not isinstance(obj, (Circle, Polygon, MovingObstacle)):
            raise WorldError("SimWorld.add: expected Circle, Polygon, Box, Pole or "
                             f"MovingObstacle, got {type(obj).__name__}")
        self._objects.append(obj)
        self._changed()
        return obj

    def remove(self, obj: WorldObject) -> None:
        """Take an object out of the world (ValueError if it is not there)."""
        self._objects.remove(obj)
        self._changed()

    def _changed(self) -> None:
        self._cache_key = None
        self._timed = any(math.isfinite(o.appear) or math.isfinite(o.disappear)
                          for o in self._objects)
        self._moving = any(isinstance(o, MovingObstacle) for o in self._objects)

    def next_change(self, t: float) -> float:
        """The first appear/disappear time after t (inf if none): the simulator ends a physics
        chunk there so that objects pop in and out on time."""
        if not self._timed:
            return math.inf
        return first_after(t, (s for o in self._objects for s in (o.appear, o.disappear)))

    @property
    def dynamic(self) -> bool:
        """Whether anything changes with time (moving, appearing or disappearing objects)."""
        return self._timed or self._moving

    def has_moving(self, t: float) -> bool:
        if not self._moving:
            return False
        return any(isinstance(o, MovingObstacle) and _present(o, t) for o in self._objects)

    def shapes_at(self, t: float) -> tuple[np.ndarray, np.ndarray]:
        """(circles (N, 3), segments (M, 4)) of every object present at time t."""
        if not self._timed and not self._moving and self._cache_key is not None:
            return self._cache  # a static world: the same arrays every time
        present = tuple(i for i, o in enumerate(self._objects) if _present(o, t))
        moving = any(isinstance(self._objects[i], MovingObstacle) for i in present)
        if not moving and self._cache_key == present:
            return self._cache
        circles: list[tuple[float, float, float]] = []
        segs: list[np.ndarray] = []
        for i in present:
            o = self._objects[i]
            if isinstance(o, Circle):
                circles.append((o.x, o.y, o.r))
            elif isinstance(o, Polygon):
                segs.append(o.segments())
            else:
                x, y = o.position(t)
                if o.half_extents is None:
                    circles.append((x, y, o.radius))
                else:
                    hx, hy = o.half_extents
                    segs.append(Box(x - hx, y - hy, x + hx, y + hy).segments())
        c = np.array(circles, np.float64).reshape(-1, 3)
        s = np.concatenate(segs, axis=0) if segs else np.zeros((0, 4), np.float64)
        out = (np.ascontiguousarray(c), np.ascontiguousarray(s))
        if not moving:
            self._cache_key, self._cache = present, out
        return out
