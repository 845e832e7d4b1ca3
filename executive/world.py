"""What a simulated world holds beyond the map: shapes, moving obstacles, phantoms, faults.

Scenarios describe these and the mission wiring puts them into the simulator; both import them
from here, so neither imports the other. ``World`` is the public one (``executive.World``); the
simulator builds its own ``hw.sim.SimWorld`` (map plus solid objects) from it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from navcore.maps import OccupancyGrid
from navcore.types import Pose2D


@dataclass
class Shape:
    """A box ``[x0, y0, x1, y1]`` or a circle ``[x, y, r]`` in map coordinates (m)."""

    kind: str
    values: tuple[float, ...]
    name: str = ""          # events refer to a shape by name (remove, move a phantom)

    def contains(self, x: float, y: float) -> bool:
        """Whether the point (x, y) is inside (or on the edge of) the shape."""
        if self.kind == "circle":
            cx, cy, r = self.values
            return (x - cx) ** 2 + (y - cy) ** 2 <= r * r
        x0, y0, x1, y1 = self.values
        return x0 <= x <= x1 and y0 <= y <= y1

    def polygon(self, n: int = 16) -> list[tuple[float, float]]:
        if self.kind == "box":
            x0, y0, x1, y1 = self.values
            return [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]
        x, y, r = self.values
        return [(x + r * math.cos(2 * math.pi * i / n), y + r * math.sin(2 * math.pi * i / n))
                for i in range(n)]

    def bbox(self) -> tuple[float, float, float, float]:
        """``(x0, y0, x1, y1)`` around the shape."""
        if self.kind == "box":
            return self.values  # type: ignore[return-value]
        x, y, r = self.values
        return x - r, y - r, x + r, y + r


@dataclass
class MovingObstacle:
    """A circle of ``radius`` that waits at ``waypoints[0]`` until ``start_time``, then moves
    through the waypoints at ``speed`` (and stays at the last one, or loops)."""

    radius: float
    waypoints: list[tuple[float, float]]
    speed: float
    start_time: float = 0.0
    loop: bool = False

    def position(self, t: float) -> tuple[float, float]:
        pts = self.waypoints
        if t <= self.start_time or len(pts) == 1 or self.speed <= 0:
            return pts[0]
        s = (t - self.start_time) * self.speed
        seg = [math.hypot(b[0] - a[0], b[1] - a[1]) for a, b in zip(pts, pts[1:])]
        total = sum(seg)
        if total <= 0:
            return pts[0]
        if self.loop:
            s = s % total
        for (a, b), d in zip(zip(pts, pts[1:]), seg):
            if s <= d and d > 0:
                f = s / d
                return a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1])
            s -= d
        return pts[-1]


@dataclass
class World:
    """What the simulated world holds beyond the map (from a scenario).

    ``phantoms``: (shape, "global" | "local" | "both") painted into the costmaps but absent from
    the world; ``faults``: the simulator's fault mappings (hw.sim.faults)."""

    objects: list[Shape] = field(default_factory=list)
    moving: list[MovingObstacle] = field(default_factory=list)
    phantoms: list[tuple[Shape, str]] = field(default_factory=list)
    faults: list[dict[str, Any]] = field(default_factory=list)
    unknown_solid: bool = False     # unknown map cells are solid in the simulated world


def free_start(grid: OccupancyGrid) -> Pose2D:
    """A default start: the free cell with the most clearance (the most open spot)."""
    from navcore.raycast import distance_field
    occ = (grid.data != 0)
    d = np.asarray(distance_field(occ.astype(np.uint8)), float)
    my, mx = np.unravel_index(int(np.argmax(d)), d.shape)
    x, y = grid.map_to_world(mx + 0.5, my + 0.5)
    return Pose2D(x, y, 0.0)
