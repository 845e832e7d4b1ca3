"""Wiring: a robot config + a map + a tree file -> a ready Executive on the simulator (or hardware).

This is the one place that knows how each component is constructed; the Executive itself only
sees the ``behaviors.components`` contract. ``run_mission`` adds the run folder and progress line
that the CLI and the scenario runner share.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from typing import Any, Callable, Sequence

import numpy as np

from navcore.clock import Clock, SimClock, WallClock
from navcore.maps import OccupancyGrid
from navcore.types import LaserScan, Pose2D

from executive.config import RobotConfig
from executive.executive import Executive, MissionResult
from executive.loading import load_tree_file
from executive.recorder import Recorder
from executive.safety import SafetyGate
from executive.scenario import MovingObstacle, Shape


class WiringError(RuntimeError):
    """A component could not be built from the config; the message names it and why."""


@dataclass
class World:
    """What the simulated world holds beyond the map (from a scenario)."""

    objects: list[Shape] = field(default_factory=list)
    moving: list[MovingObstacle] = field(default_factory=list)
    phantoms: list[tuple[Shape, str]] = field(default_factory=list)
    faults: list[dict[str, Any]] = field(default_factory=list)


# --------------------------------------------------------------------------- component builders
def _costmaps(config: RobotConfig, grid: OccupancyGrid) -> tuple[Any, Any]:
    from navcore.costmap.layered import LayeredCostmap
    fp = config.footprint()
    g = LayeredCostmap.from_params(config.ns("global_costmap"), footprint=fp, static_map=grid,
                                   name="global_costmap")
    loc = config.ns("local_costmap")
    loc.setdefault("rolling_window", True)
    local = LayeredCostmap.from_params(loc, footprint=fp, static_map=grid, name="local_costmap")
    return g, local


def _planner(config: RobotConfig, global_cm: Any) -> Any:
    from navcore.planners import make_planner
    ns = config.global_planner_namespace()
    return make_planner(config.move_base.base_global_planner, global_cm.costmap, config.ns(ns),
                        global_cm.footprint_cost)


def _controller(config: RobotConfig, local_cm: Any) -> Any:
    from navcore.controllers import make_controller
    ns = config.local_planner_namespace()
    return make_controller(config.move_base.base_local_planner, local_cm.costmap,
                           np.asarray(config.footprint(), np.float64), config.ns(ns))


def _simulator(config: RobotConfig, grid: OccupancyGrid, start: Pose2D, world: World,
               clock: Clock, rng: np.random.Generator) -> Any:
    from hw.sim import Box, Circle, MovingObstacle, Simulator
    from hw.sim import World as SimWorld
    objects: list[Any] = []
    for i, s in enumerate(world.objects):
        if s.kind == "box":
            objects.append(Box(*s.values, name=f"object{i}"))
        else:
            objects.append(Circle(*s.values, name=f"object{i}"))
    for i, m in enumerate(world.moving):
        objects.append(MovingObstacle(tuple(m.waypoints), speed=m.speed, radius=m.radius,
                                      start_time=m.start_time, loop=m.loop, name=f"moving{i}"))
    sim = Simulator(SimWorld(grid, objects), config.ns("sim"), clock, rng, start=start)
    sim.add_faults(world.faults)
    return sim


class SimIO:
    """RobotIO over the simulator."""

    def __init__(self, sim: Any) -> None:
        self.sim = sim
        self.base = sim.base
        self.laser = sim.laser

    def step_to(self, t: float) -> None:
        self.sim.step_to(t)

    def true_pose(self) -> Pose2D | None:
        return self.sim.true_pose()

    def in_collision(self) -> bool:
        return bool(self.sim.in_collision())


# --------------------------------------------------------------------------- the mission
@dataclass
class Mission:
    """A wired mission: the executive plus what pictures and scenarios need to see."""

    executive: Executive
    grid: OccupancyGrid
    config: RobotConfig
    sim: Any
    components: dict[str, Any]
    world: World
    tree_path: str


def _paint_phantoms(phantoms: Sequence[tuple[Shape, str]], global_cm: Any, local_cm: Any) -> None:
    for shape, which in phantoms:
        targets = {"global": [global_cm], "local": [local_cm], "both": [global_cm, local_cm]}[which]
        for cm in targets:
            cm.add_phantom(shape.polygon())


def build_mission(tree_path: str, config: RobotConfig, grid: OccupancyGrid, start: Pose2D, *,
                  world: World | None = None, seed: int = 0, realtime: bool = False,
                  recorder: Recorder | None = None, meta: dict[str, Any] | None = None
                  ) -> Mission:
    """Load the tree, build every component from ``config`` and put them in an Executive."""
    world = world or World()
    clock: Clock = WallClock() if realtime else SimClock()
    rng = np.random.default_rng(seed)
    from executive.executive import _mission_ids  # shared counter keeps namespaces unique
    namespace = f"/mission_{next(_mission_ids)}"
    tree = load_tree_file(tree_path, namespace=namespace)
    try:
        global_cm, local_cm = _costmaps(config, grid)
        planner = _planner(config, global_cm)
        controller = _controller(config, local_cm)
    except ImportError as e:
        raise WiringError(f"component not available: {e}") from None
    if config.robot.devices != "sim":
        raise WiringError(f"{config.source}: robot: devices: hw is only available through "
                          "`mission run --hw` with drivers installed")
    sim = _simulator(config, grid, start, world, clock, rng)
    _paint_phantoms(world.phantoms, global_cm, local_cm)
    io = SimIO(sim)
    components = {
        "global_costmap": global_cm,
        "local_costmap": local_cm,
        "planners": {"GridBased": planner},
        "controllers": {"FollowPath": controller},
        "localizer": None,
        "parameters": config.all_parameters(),
    }
    mount = sim.config.laser.mount if sim.config.laser is not None else Pose2D()

    def perceive(pose: Pose2D, scan: LaserScan | None, now: float) -> None:
        if scan is not None:
            laser_pose = pose.compose(mount)
            local_cm.add_scan(scan, laser_pose)
            global_cm.add_scan(scan, laser_pose)
        local_cm.update_map(pose, now)
        global_cm.update_map(pose, now)

    ex = Executive(tree, io, clock, config.control_period(), components,
                   safety=SafetyGate(config.safety), recorder=recorder, perceivers=[perceive],
                   namespace=namespace, meta=dict(meta or {}, tree=os.path.abspath(tree_path),
                                                  start=[start.x, start.y, start.theta]))
    return Mission(ex, grid, config, sim, components, world, tree_path)


def free_start(grid: OccupancyGrid) -> Pose2D:
    """A default start: the free cell with the most clearance (the most open spot)."""
    from navcore.raycast import distance_field
    occ = (grid.data != 0)
    d = np.asarray(distance_field(occ.astype(np.uint8)), float)
    my, mx = np.unravel_index(int(np.argmax(d)), d.shape)
    x, y = grid.map_to_world(mx + 0.5, my + 0.5)
    return Pose2D(x, y, 0.0)


def run_mission(mission: Mission, goals: list[Pose2D], time_limit: float,
                on_tick: Callable[[Executive], bool | None] | None = None) -> MissionResult:
    """Run to the goals; the executive stops the robot at the end whatever happened."""
    try:
        return mission.executive.run(goals, time_limit=time_limit, on_tick=on_tick)
    finally:
        mission.executive.stop_robot()


def progress_callback(progress: Any, time_limit: float, label: str = ""
                      ) -> Callable[[Executive], None]:
    """An ``on_tick`` that updates a Progress line with sim time, speed-up and recoveries."""
    wall = WallClock()

    def on_tick(ex: Executive) -> None:
        from executive.progress import bar
        t = ex.clock.now()
        w = max(wall.now(), 1e-6)
        p = ex.robot.pose()
        progress.update(f"{label}{bar(t / time_limit)} t={t:6.1f}s x{t / w:5.1f} "
                        f"pose=({p.x:5.2f},{p.y:5.2f}) recoveries={len(ex.trace.recoveries)}")
    return on_tick


def goal_distance(a: Pose2D, b: Pose2D) -> float:
    return math.hypot(a.x - b.x, a.y - b.y)
