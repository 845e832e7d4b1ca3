"""Perception: the estimate and perceive phases of the control cycle (docs/architecture.md).

``Localisation`` turns odometry and the newest scan into a ``map`` pose with AMCL (which gates
its own filter updates by ``update_min_d`` / ``update_min_a``). ``CostmapSchedule`` says when
each costmap is due at its ``update_frequency``. ``Perception`` feeds each new scan to both
costmaps (``LayeredCostmap.queue_scan``: converted only when a costmap reads it), updates the
costmaps that are due, and paints a scenario's phantom obstacles once after the first update.
The observed-space memory (navcore.costmap.observed_space), when given, follows the robot every
cycle: its body and each new scan are stamped into it, whatever the costmaps clear.
"""

from __future__ import annotations

import math
from typing import Any

from navcore.types import LaserScan, Odometry, Pose2D

from executive.world import Shape

# s: a deadline this close to a tick counts as reached. The clock and the deadlines are sums of
# float periods; their rounding drifts apart by ~1e-9 s per half hour simulated, 1 us by far later.
SCHEDULE_SLACK = 1e-6


class Localisation:
    """AMCL as the executive's estimator: map pose = map->odom (+) odom.

    ``amcl`` is the stack's localiser (navcore.localization.amcl.Amcl); ``mount`` is where the
    laser sits on the base."""

    def __init__(self, amcl: Any, mount: Pose2D) -> None:
        self.amcl = amcl
        self.mount = mount

    def estimate(self, odom: Odometry | None, scan: LaserScan | None) -> Pose2D | None:
        """The robot in ``map`` after feeding the filter this cycle's odometry and scan."""
        if odom is None:
            return None
        self.amcl.update(odom.pose, scan, self.mount)
        return self.amcl.map_to_odom().compose(odom.pose)


class CostmapSchedule:
    """When each costmap is due: a fixed rate at its ``update_frequency``, like ros::Rate."""

    def __init__(self, costmaps: list[Any]) -> None:
        self.periods = [_update_period(cm) for cm in costmaps]
        self.due = [-math.inf] * len(costmaps)

    def take(self, i: int, now: float) -> bool:
        """Whether costmap ``i`` is due at ``now``; if so its next deadline is set.

        The next deadline is one period after this one (now + period would let float sums push
        it one control tick late each time); after a stall longer than a period the schedule
        restarts from now."""
        if now < self.due[i] - SCHEDULE_SLACK:
            return False
        nxt = self.due[i] + self.periods[i]
        self.due[i] = nxt if nxt > now else now + self.periods[i]
        return True


def _update_period(cm: Any) -> float:
    f = float(getattr(cm.params, "update_frequency", 0.0))
    return 1.0 / f if f > 0 else 0.0


class Perception:
    """The estimate and perceive phases: localisation, the costmaps' schedule and their scans.

    ``costmaps`` in update order (local, then global); ``mount``: the laser on the base;
    ``localisation`` None means the pose comes from the robot I/O (simulator ground truth or
    odometry); ``phantoms``: (shape, costmap name) pairs painted after the first update;
    ``observed``: the observed-space memory (an ObservedSpace) or None."""

    def __init__(self, costmaps: dict[str, Any], mount: Pose2D,
                 localisation: Localisation | None = None,
                 phantoms: list[tuple[Shape, str]] | None = None,
                 observed: Any = None) -> None:
        self.costmaps = costmaps
        self._ordered = list(costmaps.values())
        self.mount = mount
        self.localisation = localisation
        self.schedule = CostmapSchedule(self._ordered)
        self._phantoms = list(phantoms or [])
        self._last_scan: LaserScan | None = None
        self.observed = observed

    def estimate(self, odom: Odometry | None, scan: LaserScan | None) -> Pose2D | None:
        """The localiser's pose, or None when there is none (the executive falls back)."""
        if self.localisation is None:
            return None
        return self.localisation.estimate(odom, scan)

    def perceive(self, pose: Pose2D, scan: LaserScan | None, now: float) -> None:
        """Give a new scan to every costmap and the observed-space memory, and update the
        costmaps that are due."""
        new_scan = scan is not None and scan is not self._last_scan
        laser_pose = pose.compose(self.mount)
        if new_scan:
            self._last_scan = scan
            for cm in self._ordered:
                cm.queue_scan(scan, laser_pose)
        if self.observed is not None:
            self.observed.update(pose, scan if new_scan else None, laser_pose, now)
        for i, cm in enumerate(self._ordered):
            if self.schedule.take(i, now):
                cm.update_map(pose)
        if self._phantoms:
            self._paint_phantoms(pose)

    def _paint_phantoms(self, pose: Pose2D) -> None:
        # after the first update, so the rolling window is already around the robot
        names = {"global": ["global"], "local": ["local"], "both": ["global", "local"]}
        for shape, which in self._phantoms:
            for name in names[which]:
                paint_phantom(self.costmaps[name], shape)
        self._phantoms.clear()
        for cm in self._ordered:
            cm.update_map(pose)


def paint_phantom(cm: Any, shape: Shape) -> int:
    """Mark a shape LETHAL in every clearable (obstacle) layer of a costmap; returns the cells.

    The cells persist like any stale observation: until a clear recovery resets the layer or a
    laser ray passes through them (ray-trace clearing), exactly as a ghost obstacle would."""
    from navcore.costmap.cost_values import LETHAL_OBSTACLE
    x0, y0, x1, y1 = shape.bbox()
    n = 0
    for layer in [l for l in cm.layers if getattr(l, "clearable", False)]:
        g = layer.grid
        for my in range(max(0, int((y0 - g.origin_y) / g.resolution)),
                        min(g.size_y, int(math.ceil((y1 - g.origin_y) / g.resolution)))):
            for mx in range(max(0, int((x0 - g.origin_x) / g.resolution)),
                            min(g.size_x, int(math.ceil((x1 - g.origin_x) / g.resolution)))):
                wx, wy = g.map_to_world(mx, my)
                if shape.kind == "circle" and math.hypot(wx - shape.values[0],
                                                         wy - shape.values[1]) > shape.values[2]:
                    continue
                g.costs[my, mx] = LETHAL_OBSTACLE
                n += 1
        layer.add_extra_bounds(x0, y0, x1, y1)
    return n
