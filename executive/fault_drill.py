"""Fault drills: drive a simulated robot down a corridor, inject one fault while it moves, and
count the control periods from the first tick at which the fault is observable to the first
tick whose command is zero (docs/robustness.md). The braking after that is physics and is not
counted. ``bench/bench_robustness.py`` runs every drill; tests run some.

The faults of the simulator (laser drop-out, frozen laser) are its own scripted faults; the
others wrap the robot I/O or the perception a mission is assembled with, the way a broken
driver or a broken component would behave.
"""

from __future__ import annotations

import math
import os
import tempfile
from dataclasses import dataclass
from typing import Any

import numpy as np

from navcore.clock import SimClock, WallClock
from navcore.types import LaserScan, Odometry, Pose2D, Twist

FAULTS = ("laser_dropout", "odometry_stops", "odometry_frozen", "laser_frozen",
          "scan_stamp_future", "scan_stamp_nan", "costmap_raises", "localisation_raises",
          "loop_stall", "tree_disables_timeout")

_CORRIDOR = "\n".join(["#" * 160] + ["#" + "." * 158 + "#"] * 18 + ["#" * 160])


@dataclass
class DrillResult:
    """What one drill measured."""

    fault: str
    stop_periods: float          # control periods from observable to a zero command
    moving_before: bool          # the robot was commanded to move just before the fault
    faults_seen: list[str]       # the gate's fault names at the stopping tick


class _Faulty:
    """The fault switch shared by the wrappers: on from ``start`` on the mission clock."""

    def __init__(self, kind: str, start: float, clock: Any) -> None:
        self.kind, self.start, self.clock = kind, start, clock

    def on(self, kind: str) -> bool:
        return self.kind == kind and self.clock.now() >= self.start - 1e-9


class _Base:
    def __init__(self, inner: Any, f: _Faulty, wall: WallClock) -> None:
        self.inner, self.f, self.wall = inner, f, wall
        self._held: Odometry | None = None
        self.sent: list[tuple[float, Twist]] = []   # wall time of every command sent

    def send(self, cmd: Twist) -> None:
        self.sent.append((self.wall.now(), cmd))
        self.inner.send(cmd)

    def odometry(self) -> Odometry | None:
        odom = self.inner.odometry()
        f = self.f
        if f.on("odometry_stops"):
            return self._held              # the driver stopped delivering: the last one stays
        if f.on("odometry_frozen") or f.on("tree_disables_timeout"):
            if self._held is None or odom is None:
                return self._held
            h = self._held                 # same content, fresh stamps
            return Odometry(odom.stamp, h.pose, h.twist, h.pose_covariance, h.twist_covariance)
        self._held = odom
        return odom

    def battery(self) -> Any:
        return self.inner.battery()

    def events(self) -> Any:
        return self.inner.events()


class _Laser:
    def __init__(self, inner: Any, f: _Faulty) -> None:
        self.inner, self.f = inner, f
        self.mount = inner.mount
        self.config = getattr(inner, "config", None)

    def scan(self) -> LaserScan | None:
        s = self.inner.scan()
        if s is None:
            return s
        if self.f.on("scan_stamp_future"):
            return LaserScan(s.stamp + 5.0, s.angle_min, s.angle_max, s.angle_increment,
                             s.time_increment, s.scan_time, s.range_min, s.range_max, s.ranges)
        if self.f.on("scan_stamp_nan"):
            return LaserScan(math.nan, s.angle_min, s.angle_max, s.angle_increment,
                             s.time_increment, s.scan_time, s.range_min, s.range_max, s.ranges)
        return s


class _IO:
    def __init__(self, inner: Any, f: _Faulty, wall: WallClock) -> None:
        self.inner = inner
        self.base = _Base(inner.base, f, wall)
        self.laser = _Laser(inner.laser, f) if inner.laser is not None else None

    def step_to(self, t: float) -> None:
        self.inner.step_to(t)

    def true_pose(self) -> Pose2D | None:
        return self.inner.true_pose()

    def in_collision(self) -> bool:
        return self.inner.in_collision()


class _Perception:
    def __init__(self, inner: Any, f: _Faulty, stall: float, wall: WallClock) -> None:
        self.inner, self.f, self.stall, self.wall = inner, f, stall, wall
        self.stalled = False
        self.stall_wall = math.nan   # wall.now() when the hung cycle began

    def estimate(self, odom: Any, scan: Any) -> Any:
        if self.f.on("localisation_raises"):
            raise RuntimeError("drill: localisation failed")
        if self.f.on("loop_stall") and not self.stalled:
            self.stalled = True
            self.stall_wall = self.wall.now()
            self.wall.sleep_until(self.stall_wall + self.stall)  # a hung cycle, on the wall
        return self.inner.estimate(odom, scan)

    def perceive(self, pose: Any, scan: Any, now: float) -> None:
        if self.f.on("costmap_raises"):
            raise RuntimeError("drill: costmap update failed")
        self.inner.perceive(pose, scan, now)


def _tree_file(kind: str, directory: str) -> str:
    from executive.tree_loader import shipped_tree
    base = shipped_tree("move_base")
    if kind != "tree_disables_timeout":
        return base
    path = os.path.join(directory, "disables_timeout.yaml")
    with open(path, "w", encoding="utf-8") as fh:
        fh.write(f"main_tree: Drill\ninclude: [{base}]\ntrees:\n  Drill:\n    SetParameters:\n"
                 "      namespace: safety\n      values: {sensor_timeout: .inf}\n"
                 "      required: false\n      child: {SubTree: {id: MoveBase, _autoremap: true}}\n")
    return path


def drill(kind: str, start: float = 4.0, seed: int = 0, stall: float = 1.5,
          after: float = 2.0) -> DrillResult:
    """Run one drill (``kind`` in ``FAULTS``) and measure the stop latency in control periods.

    ``loop_stall`` runs on the wall clock (the cycle at ``start`` hangs ``stall`` seconds and the
    executive's watchdog stops the base from its thread); every other drill on a simulated clock.
    """
    if kind not in FAULTS:
        raise ValueError(f"drill: unknown fault {kind!r}; one of {', '.join(FAULTS)}")
    from executive.executive import new_namespace
    from executive.mission import assemble, perception_for
    from executive.robot_io import open_robot_io
    from executive.scenario import scenario_config, scenario_from_mapping
    from executive.stack import Stack
    from executive.tree_loader import load_tree_file
    from executive.world import World
    sim_fault = {"laser_dropout": "laser_dropout", "laser_frozen": "laser_frozen"}.get(kind)
    doc = {"name": f"drill_{kind}", "map": {"resolution": 0.1, "ascii": _CORRIDOR},
           "start": [0.8, 1.0, 0.0], "goals": [[15.0, 1.0, 0.0]], "time_limit": 60, "seed": seed,
           "faults": [{"kind": sim_fault, "start": start}] if sim_fault else []}
    sc = scenario_from_mapping(doc, f"<drill {kind}>")
    config = scenario_config(sc, None)
    world = World(sc.objects, sc.moving, sc.phantoms, sc.faults)
    # build_mission's steps on the simulator, with the faulty I/O and perception put in place
    clock = WallClock() if kind == "loop_stall" else SimClock()
    rng = np.random.default_rng(seed)
    namespace = new_namespace()
    with tempfile.TemporaryDirectory() as tmp:
        tree_path = _tree_file(kind, tmp)
        tree = load_tree_file(tree_path, namespace=namespace,
                              port_defaults=config.port_defaults())
    stack = Stack.from_config(config, sc.grid, clock)
    sim_io, sim = open_robot_io("sim", config, sc.grid, sc.start, world, clock, rng, namespace)
    f = _Faulty(kind, start, clock)
    wall = WallClock()  # the commands' and the stall's times, compared with each other
    io = _IO(sim_io, f, wall)
    localise = "amcl" in config.namespaces
    perception = _Perception(perception_for(stack, sc.grid, sc.start, rng, io, world,
                                            localise=localise), f, stall, wall)
    mission = assemble(tree, tree_path, config, sc.grid, sc.start, stack, io, clock, rng,
                       localise=localise, sim=sim, world=world, namespace=namespace,
                       perception=perception)
    ex = mission.executive
    ex.set_goal(sc.goals[0])
    period = ex.period
    ticks: list[tuple[float, Twist, list[str]]] = []
    try:
        while ex.clock.now() < start + after:
            t = ex.clock.now()
            before = dict(ex.trace.faults)
            ex.step()
            seen = sorted(k for k, n in ex.trace.faults.items() if n > before.get(k, 0))
            ticks.append((t, ex.last_cmd, seen))
    finally:
        ex.shutdown()
    onset = next(i for i, (t, _, _) in enumerate(ticks) if t >= start - 1e-9)
    moving = onset > 0 and _moving(ticks[onset - 1][1])
    if kind == "loop_stall":
        return DrillResult(kind, _watchdog_periods(io.base.sent, perception.stall_wall, period),
                           moving, ["watchdog"])
    for i in range(onset, len(ticks)):
        if not _moving(ticks[i][1]):
            return DrillResult(kind, float(i - onset), moving, ticks[i][2])
    return DrillResult(kind, math.inf, moving, [])


def _moving(cmd: Twist) -> bool:
    return cmd.vx != 0.0 or cmd.vy != 0.0 or cmd.wz != 0.0


def _watchdog_periods(sent: list[tuple[float, Twist]], stall_wall: float,
                      period: float) -> float:
    """Periods from when the hung cycle's command was due (one period after the last command
    before the hang) to the zero command the watchdog sent during the hang."""
    before = [w for w, _ in sent if w <= stall_wall]
    zeros = [w for w, c in sent if w > stall_wall and not _moving(c)]
    if not before or not zeros:
        return math.inf
    return max(0.0, (zeros[0] - (before[-1] + period)) / period)
