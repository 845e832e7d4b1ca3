"""Wiring: a robot config + a map + a tree file -> a ready Executive on the simulator (or hardware).

``build_mission`` puts together what the other modules build: the ``Stack`` of components
(executive/stack.py), the robot I/O (executive/robot_io.py), ``Perception``
(executive/perception.py) and the tree (executive/tree_loader.py), and hands them to an
``Executive``. ``run_mission`` runs one to its goals and stops the robot whatever happened.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from typing import Any, Callable

import numpy as np

from hw.interfaces import RobotIO
from navcore.clock import Clock, SimClock, WallClock
from navcore.maps import OccupancyGrid
from navcore.types import Pose2D

from executive.config import RobotConfig
from executive.errors import WiringError
from executive.executive import Executive, MissionResult, new_namespace
from executive.tree_loader import LoadedTree, load_tree_file
from executive.perception import Localisation, Perception, paint_phantom
from executive.progress import progress_callback
from executive.recorder import Recorder
from executive.robot_io import (EmulatedIO, HardwareIO, SimIO, hardware_mode, laser_mount,
                                open_robot_io)
from executive.safety import SafetyGate
from executive.stack import Stack
from executive.world import World, free_start

__all__ = ["Mission", "WiringError", "World", "build_mission", "assemble", "perception_for",
           "run_mission", "free_start",
           "progress_callback", "paint_phantom", "hardware_mode", "SimIO", "HardwareIO",
           "EmulatedIO"]


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
    stack: Stack | None = None


def build_mission(tree_path: str | LoadedTree, config: RobotConfig, grid: OccupancyGrid,
                  start: Pose2D | None, *,
                  world: World | None = None, seed: int = 0, realtime: bool = False,
                  recorder: Recorder | None = None, meta: dict[str, Any] | None = None,
                  hardware: bool | str = False) -> Mission:
    """Load the tree (or take a loaded one), build every component from ``config`` and put
    them in an Executive.

    ``hardware``: False runs the simulator's direct interfaces; True (or "devices") the drivers
    of ``robot.devices`` on the wall clock with reader threads; "emulated" the real Kobuki and
    URG-04LX drivers in lock-step over ``sim://`` byte streams whose emulators the simulator
    drives (deterministic on the simulated clock, one trace per seed)."""
    world = world or World()
    mode = hardware_mode(hardware)
    clock: Clock = WallClock() if realtime or mode == "devices" else SimClock()
    rng = np.random.default_rng(seed)
    if isinstance(tree_path, LoadedTree):
        tree, source, namespace = tree_path, tree_path.source, tree_path.namespace
    else:
        namespace = new_namespace()
        tree = load_tree_file(tree_path, namespace=namespace,
                              port_defaults=config.port_defaults())
        source = str(tree_path)
    stack = Stack.from_config(config, grid, clock)
    io, sim = open_robot_io(mode, config, grid, start, world, clock, rng, namespace)
    return assemble(tree, source, config, grid, start, stack, io, clock, rng,
                    localise="amcl" in config.namespaces or mode != "sim",  # drivers: no truth
                    sim=sim, world=world, recorder=recorder, meta=meta, namespace=namespace)


def assemble(tree: LoadedTree | Any, tree_source: str, config: RobotConfig, grid: OccupancyGrid,
             start: Pose2D | None, stack: Stack, io: RobotIO, clock: Clock,
             rng: np.random.Generator, *, localise: bool, sim: Any = None,
             world: World | None = None, recorder: Recorder | None = None,
             meta: dict[str, Any] | None = None, require_laser: bool = True,
             namespace: str | None = None, perception: Perception | None = None) -> Mission:
    """Put a loaded tree, a stack and a robot I/O together in an Executive. ``localise``: run
    AMCL (from the ``amcl`` namespace) rather than take the robot I/O's ground truth.
    ``perception``: the estimate and perceive phases, by default ``perception_for`` this stack;
    give one only when it wraps what ``perception_for`` built (a fault drill does)."""
    world = world or World()
    if perception is None:
        perception = perception_for(stack, grid, start, rng, io, world, localise=localise)
    components = stack.components()
    namespace = namespace or getattr(tree, "namespace", None)
    try:
        ex = Executive(tree, io, clock, config.control_period(), components,
                       safety=SafetyGate(config.safety, require_laser=require_laser),
                       recorder=recorder, perception=perception, namespace=namespace,
                       meta=dict(meta or {}, tree=_where(tree_source),
                                 start=None if start is None else [start.x, start.y,
                                                                   start.theta]))
    except Exception as e:  # noqa: BLE001 - a node's setup (e.g. a missing component)
        if isinstance(io, HardwareIO):
            io.close()       # drivers opened for a mission that will not run
        raise WiringError(f"{tree_source}: tree setup failed: {e}") from None
    return Mission(ex, grid, config, sim, components, world, tree_source, stack)


def perception_for(stack: Stack, grid: OccupancyGrid, start: Pose2D | None,
                   rng: np.random.Generator, io: RobotIO, world: World, *,
                   localise: bool) -> Perception:
    """The stack's costmaps (local, then global) fed from ``io``'s laser, the world's phantoms,
    and with ``localise`` AMCL (added to the stack here, after the robot I/O drew from
    ``rng``)."""
    mount = laser_mount(io)
    localisation = None
    if localise:
        stack.add_localizer(grid, start, rng)
        localisation = Localisation(stack.localizer, mount)
    return Perception({"local": stack.local_costmap, "global": stack.global_costmap},
                      mount, localisation, world.phantoms, stack.observed_space)


def _where(tree_source: str) -> str:
    """The tree's file as an absolute path for the record (text sources stay as named)."""
    return tree_source if tree_source.startswith("<") else os.path.abspath(tree_source)


def run_mission(mission: Mission, goals: list[Pose2D], time_limit: float,
                on_tick: Callable[[Executive], bool | None] | None = None) -> MissionResult:
    """Run to the goals; the executive stops the robot at the end whatever happened."""
    try:
        return mission.executive.run(goals, time_limit=time_limit, on_tick=on_tick)
    finally:
        mission.executive.stop_robot()
