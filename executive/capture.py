"""What a run's pictures and replay page need beyond the tick log, sampled while it runs.

``RunCapture`` is a Recorder sink (see ``recorder.Recorder``): after each tick it keeps the time
series (estimated and true pose, speed, distance to the goal, the active recovery) and, at
their own rates, laser scans, costmap snapshots and AMCL particles. Scans are also kept at every
recovery's start, so ``run.png`` can show what the robot saw when it got stuck. Everything is
sampled on the simulated clock, so the same seed gives the same capture.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from navcore.types import LaserScan, Pose2D


@dataclass(frozen=True)
class ScanSample:
    """One laser scan with the laser's pose in ``map`` when it was used."""

    tick: int
    t: float
    scan: LaserScan
    laser_pose: Pose2D

    def points(self, max_points: int = 720) -> np.ndarray:
        """Hit points in ``map``, shape (n, 2), float64, m (no-return beams left out)."""
        s = self.scan
        r = np.asarray(s.ranges, dtype=np.float64)
        a = s.angle_min + s.angle_increment * np.arange(len(r))
        ok = np.isfinite(r) & (r >= s.range_min) & (r < s.range_max)
        r, a = r[ok], a[ok]
        if len(r) > max_points:
            idx = np.linspace(0, len(r) - 1, max_points).round().astype(int)
            r, a = r[idx], a[idx]
        p = self.laser_pose
        ang = a + p.theta
        return np.column_stack([p.x + r * np.cos(ang), p.y + r * np.sin(ang)])


@dataclass(frozen=True)
class GridSample:
    """A copy of a costmap's cost array (row 0 = lowest y) and where it lies."""

    tick: int
    t: float
    costs: np.ndarray
    resolution: float
    origin_x: float
    origin_y: float


@dataclass
class RunCapture:
    """Recorder sink keeping time series and sampled scans, costmaps and particles.

    Rates are in simulated seconds; 0 keeps one sample per tick."""

    scan_every_s: float = 0.2
    local_costmap_every_s: float = 1.0
    global_costmap_every_s: float = 2.0
    max_global_costmaps: int = 32    # a long run keeps every other one and samples half as often
    particles_every_s: float = 0.5
    max_particles: int = 500
    header: dict[str, Any] = field(default_factory=dict)
    lines: list[dict[str, Any]] = field(default_factory=list)
    times: list[float] = field(default_factory=list)
    poses: list[tuple[float, float, float]] = field(default_factory=list)
    truth: list[tuple[float, float, float]] = field(default_factory=list)
    odom: list[tuple[float, float, float]] = field(default_factory=list)
    speed: list[float] = field(default_factory=list)
    goal_distance: list[float] = field(default_factory=list)
    active_recovery: list[int] = field(default_factory=list)  # index into recovery_names, -1
    recovery_names: list[str] = field(default_factory=list)
    scans: list[ScanSample] = field(default_factory=list)
    recovery_scans: list[ScanSample] = field(default_factory=list)
    local_costmaps: list[GridSample] = field(default_factory=list)
    global_costmaps: list[GridSample] = field(default_factory=list)
    particles: list[tuple[int, float, np.ndarray]] = field(default_factory=list)
    footer: dict[str, Any] | None = None
    laser_mount: Pose2D = field(default_factory=Pose2D)

    def __post_init__(self) -> None:
        self._next = {"scan": -math.inf, "local": -math.inf, "global": -math.inf,
                      "particles": -math.inf}
        self._recovery_nodes: dict[int, str] = {}
        self._status: dict[int, str] = {}
        self._running: list[str] = []    # the recovery running now (the last in tree order)
        self._goal: Any = None
        self._last_scan: LaserScan | None = None

    # ------------------------------------------------------------------ sink interface
    def start(self, header: dict[str, Any], executive: Any) -> None:
        from behaviors.base import Recovery

        from executive.recorder import walk
        self.header = header
        self._recovery_nodes = {i: node.name for i, (node, _) in
                                enumerate(walk(executive.tree.root))
                                if isinstance(node, Recovery)}
        io = getattr(executive, "io", None)
        mount = getattr(getattr(io, "laser", None), "mount", None)
        self.laser_mount = mount if isinstance(mount, Pose2D) else Pose2D()

    def tick(self, line: dict[str, Any], executive: Any) -> None:
        self.lines.append(line)
        t = float(line["t"])
        tick = int(line["tick"])
        robot = executive.robot
        est = robot.pose()
        truth = executive.io.true_pose()
        truth = truth if truth is not None else est
        self.times.append(t)
        self.poses.append((est.x, est.y, est.theta))
        self.truth.append((truth.x, truth.y, truth.theta))
        odom = executive.last_odom
        op = odom.pose if odom is not None else est
        self.odom.append((op.x, op.y, op.theta))
        v = robot.velocity()
        self.speed.append(math.hypot(v.vx, v.vy))
        bb = line.get("bb")
        if len(self.times) == 1 or (bb is not None and "goal" in bb):
            # the goal changes only with a blackboard write, which the line reports
            self._goal = executive.blackboard_get("goal")
        goal = self._goal
        self.goal_distance.append(math.hypot(goal.x - truth.x, goal.y - truth.y)
                                  if isinstance(goal, Pose2D) else math.nan)
        changes = line.get("status")
        if changes:
            for i, s in changes.items():
                self._status[int(i)] = s
            running = [name for i, name in self._recovery_nodes.items()
                       if self._status.get(i) == "RUNNING"]
            self._running = running[-1:]
        # the recovery running now, or one that fired and finished within this tick
        events = line.get("events", ())
        fired = [e["recovery"] for e in events if "recovery" in e]
        active = -1
        for name in fired + self._running:
            if name not in self.recovery_names:
                self.recovery_names.append(name)
            active = self.recovery_names.index(name)
        self.active_recovery.append(active)

        scan = executive.last_scan
        if scan is not None:
            sample = None
            if scan is not self._last_scan and t >= self._next["scan"] - 1e-9:
                sample = ScanSample(tick, t, scan, est.compose(self.laser_mount))
                self.scans.append(sample)
                self._last_scan = scan
                self._next["scan"] = t + self.scan_every_s
            if fired:
                self.recovery_scans.append(
                    sample or ScanSample(tick, t, scan, est.compose(self.laser_mount)))
        comps = executive.components
        if t >= self._next["local"] - 1e-9 and comps.get("local_costmap") is not None:
            self.local_costmaps.append(_grid_sample(comps["local_costmap"], tick, t))
            self._next["local"] = t + self.local_costmap_every_s
        if t >= self._next["global"] - 1e-9 and comps.get("global_costmap") is not None:
            g = _grid_sample(comps["global_costmap"], tick, t, copy=False)
            last = self.global_costmaps[-1] if self.global_costmaps else None
            if last is None or not np.array_equal(last.costs, g.costs):
                self.global_costmaps.append(_grid_sample(comps["global_costmap"], tick, t))
                if len(self.global_costmaps) > self.max_global_costmaps:
                    # a big map is megabytes a copy: thin out, first and newest kept
                    kept = self.global_costmaps
                    self.global_costmaps = kept[:-1:2] + [kept[-1]]
                    self.global_costmap_every_s *= 2.0
            self._next["global"] = t + self.global_costmap_every_s
        loc = comps.get("localizer")
        if loc is not None and t >= self._next["particles"] - 1e-9:
            parts = np.asarray(getattr(loc, "particles", np.zeros((0, 3))), dtype=np.float64)
            if len(parts) > self.max_particles:
                parts = parts[:: int(math.ceil(len(parts) / self.max_particles))]
            self.particles.append((tick, t, parts.copy()))
            self._next["particles"] = t + self.particles_every_s

    def finish(self, footer: dict[str, Any]) -> None:
        self.footer = footer

    # ------------------------------------------------------------------ queries
    @property
    def has_localisation(self) -> bool:
        """Whether the pose came from an estimator (poses differ from ground truth)."""
        return any(abs(a[0] - b[0]) > 1e-9 or abs(a[1] - b[1]) > 1e-9
                   for a, b in zip(self.poses, self.truth))

    def localisation_error(self) -> np.ndarray:
        """Distance between estimated and true position per tick, m."""
        if not self.poses:
            return np.zeros(0)
        e, g = np.asarray(self.poses), np.asarray(self.truth)
        return np.hypot(e[:, 0] - g[:, 0], e[:, 1] - g[:, 1])


def _grid_sample(cm: Any, tick: int, t: float, copy: bool = True) -> GridSample:
    m = cm.costmap
    costs = m.costs.copy() if copy else m.costs
    return GridSample(tick, t, costs, float(m.resolution), float(m.origin_x), float(m.origin_y))
