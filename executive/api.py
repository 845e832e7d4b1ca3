"""navbt's public API: load a tree and a robot, build a mission, give it goals, step or run it.

>>> from executive import api
>>> nav = api.open_mission("nav2", api.load_config(), "map.yaml")                   # doctest: +SKIP
>>> nav.go_to_pose(Pose2D(5.0, 2.0))                                                # doctest: +SKIP
>>> while not nav.is_task_complete():                                               # doctest: +SKIP
...     nav.step()
>>> nav.get_result().outcome                                                        # doctest: +SKIP
'succeeded'

The verbs are nav2_simple_commander's (``goToPose``, ``followWaypoints``, ``isTaskComplete``,
``getFeedback``, ``cancelTask``, ``getResult``) in Python spelling. A mission runs on the
simulator, on the drivers of the config, or on a robot of your own (``open_mission(..., io=)``
with an object implementing ``hw.interfaces.RobotIO``). ``docs/api.md`` has worked examples.
"""

from __future__ import annotations

import math
import os
from typing import Any, Callable, Iterable, Mapping

import numpy as np

from hw.interfaces import RobotIO
from navcore.clock import Clock, SimClock, WallClock
from navcore.maps import OccupancyGrid, load_map
from navcore.types import Pose2D

from executive.config import (ConfigError, ConfigSources, RobotConfig, config_from_mapping,
                              load_config_sources)
from executive.config import load_config as _load_config_file
from executive.errors import ExecutiveError, WiringError
from executive.executive import Executive, new_namespace
from executive.mission import Mission, assemble, build_mission
from executive.recorder import Recorder
from executive.robot_io import hardware_mode
from executive.stack import Stack
from executive.task import Feedback, MissionResult, Task
from executive.tree_loader import (LoadedTree, TreeLoadError, load_tree_file, load_tree_text,
                                   shipped_tree)
from executive.world import World, free_start

__all__ = ["load_tree", "parse_tree", "load_config", "load_map", "shipped_tree", "free_start",
           "open_mission", "Navigator", "Feedback", "MissionResult",
           "World", "Pose2D", "RobotIO", "ExecutiveError", "TreeLoadError", "ConfigError",
           "WiringError", "ConfigSources"]


def _tree_path(path: str | os.PathLike) -> str:
    """A file path as given, or the path of a shipped tree named without a suffix (``nav2``)."""
    path = str(path)
    if not os.path.exists(path) and os.sep not in path and "." not in path:
        return shipped_tree(path)
    return path


def load_tree(path: str | os.PathLike, config: RobotConfig | None = None,
              nav2_distro: str | None = None) -> LoadedTree:
    """A YAML or BT.CPP XML tree file (or the name of a shipped tree: ``"nav2"``), built under
    a blackboard namespace of its own. ``config``: the robot config whose server parameters
    fill the ports the tree leaves unset (``behavior_server``, ``move_base``), as
    ``open_mission`` does for a tree given by path. ``nav2_distro`` (humble, jazzy, kilted,
    main): the Nav2 distribution whose semantics apply, over the file's own (docs/trees.md).
    Errors are ``TreeLoadError`` naming file, line, node."""
    return load_tree_file(_tree_path(path), namespace=new_namespace(), nav2_distro=nav2_distro,
                          port_defaults=None if config is None else config.port_defaults())


def parse_tree(text: str, name: str = "<text>") -> LoadedTree:
    """A tree from YAML or BT.CPP XML text (XML when it starts with ``<``)."""
    return load_tree_text(text, namespace=new_namespace(), name=name)


def load_config(source: str | os.PathLike | Mapping[str, Any] | ConfigSources | None = None
                ) -> RobotConfig:
    """A robot config: a YAML file, an already parsed mapping of ROS namespaces, ROS files
    (``ConfigSources(launch=..., args=..., params=[...], nav2_params=[...])``, see
    docs/ros-users.md), or None for the bundled robot. Errors are ``ConfigError`` naming file,
    line, namespace and parameter."""
    if isinstance(source, ConfigSources):
        return load_config_sources(source)
    if isinstance(source, Mapping):
        return config_from_mapping(source, "<mapping>")
    return _load_config_file(None if source is None else str(source))


def _grid(grid: OccupancyGrid | str | os.PathLike) -> OccupancyGrid:
    return grid if isinstance(grid, OccupancyGrid) else load_map(str(grid))


def _tree(tree: LoadedTree | str | os.PathLike, config: RobotConfig) -> LoadedTree:
    """A loaded tree as given, or loaded from its path with the config's port defaults (as
    ``build_mission`` loads one)."""
    return tree if isinstance(tree, LoadedTree) else load_tree(tree, config)


def open_mission(tree: LoadedTree | str | os.PathLike, config: RobotConfig | None = None,
                 grid: OccupancyGrid | str | os.PathLike | None = None,
                 start: Pose2D | None = None, *, io: RobotIO | None = None,
                 clock: Clock | None = None, realtime: bool = False, seed: int = 0,
                 world: World | None = None,
                 hardware: bool | str = False, localise: bool | None = None,
                 recorder: Recorder | None = None,
                 meta: dict[str, Any] | None = None) -> Navigator:
    """A mission ready for goals: ``tree`` (a path, a shipped tree's name or a ``load_tree`` /
    ``parse_tree`` result) on a robot, with the components of ``config`` (default: the bundled
    robot) on ``grid`` (a map or a map_server YAML path).

    The robot is ``io`` when given: your own ``hw.interfaces.RobotIO``. Otherwise the config's:
    the simulator (with ``world``'s objects), or with ``hardware=True`` the drivers of
    ``robot.devices``, or with ``hardware="emulated"`` the real drivers over the simulator's
    device emulators. ``start``: where the simulated robot starts and AMCL's first guess
    (default on the simulator: the map's most open spot). ``realtime``: run on the wall clock
    (a real robot needs it); otherwise simulated time runs as fast as the computer allows.
    ``clock``: with ``io``, the mission's clock when your robot needs it too (a simulator of
    your own stamping its messages); default a new one as ``realtime`` says.
    ``localise``: with ``io``, run AMCL (needs a laser) rather than trust ``io.true_pose``;
    by default only when the config has an ``amcl`` namespace or there is no ground truth.
    ``recorder``: where tick records go (``executive.run_folder.open_recorder(folder)`` writes
    a run folder's ``ticks.jsonl``; default: kept in memory only, as ``Executive.trace``).
    ``seed`` seeds every random draw: the same seed gives the same run."""
    if grid is None:
        raise WiringError("open_mission: give a map (an OccupancyGrid or a map YAML path)")
    config = config if config is not None else load_config()
    occupancy = _grid(grid)
    if io is None:
        if clock is not None:
            raise WiringError("open_mission: 'clock' goes with your own robot I/O; the config's "
                              "robot gets the clock 'realtime' asks for")
        if localise is not None:
            raise WiringError("open_mission: 'localise' applies to your own robot I/O; the "
                              "config's robot localises with AMCL when it has an 'amcl' "
                              "namespace or runs on drivers")
        if start is None and hardware_mode(hardware) != "devices":
            start = free_start(occupancy)
        loaded = tree if isinstance(tree, LoadedTree) else _tree_path(tree)
        return Navigator(build_mission(loaded, config, occupancy, start, world=world, seed=seed,
                                       realtime=realtime, recorder=recorder, meta=meta,
                                       hardware=hardware))
    if world is not None or hardware is not False:
        raise WiringError("open_mission: 'world' and 'hardware' describe the config's robot; "
                          "with your own robot I/O leave them out")
    loaded = _tree(tree, config)
    if clock is None:
        clock = WallClock() if realtime else SimClock()
    if localise is None:
        localise = "amcl" in config.namespaces or io.true_pose() is None
    if localise and io.laser is None:
        raise WiringError("open_mission: localisation (AMCL) needs a laser and the robot I/O "
                          "has none; give localise=False and a true_pose")
    stack = Stack.from_config(config, occupancy, clock)
    return Navigator(assemble(loaded, loaded.source, config, occupancy, start, stack, io, clock,
                              np.random.default_rng(seed), localise=localise,
                              recorder=recorder, meta=meta,
                              require_laser=io.laser is not None))


class Navigator:
    """One mission, driven with nav2_simple_commander's verbs.

    Give a task (``go_to_pose``, ``follow_waypoints``); a new one replaces the running one at
    once, as a new goal preempts the old one in Nav2. Then either call ``step()`` once per
    control period from your own loop, or ``run()`` until the task ends. ``cancel_task()``
    halts the tree and sends the base a zero velocity. ``close()`` (or a ``with`` block) stops
    the robot and releases the tree and the robot I/O.
    """

    def __init__(self, mission: Mission) -> None:
        self.mission = mission
        self.executive: Executive = mission.executive
        self._task: Task | None = None
        self._closed = False

    # ----------------------------------------------------------------- tasks
    def go_to_pose(self, pose: Pose2D, time_limit: float = math.inf) -> None:
        """Navigate to ``pose`` (in ``map``); the task fails after ``time_limit`` s."""
        self.follow_waypoints([pose], time_limit)

    def follow_waypoints(self, poses: Iterable[Pose2D], time_limit: float = math.inf) -> None:
        """Navigate to each pose in turn; the task fails at the first one that fails."""
        goals = list(poses)
        if not goals:
            raise ValueError("follow_waypoints: no poses given")
        self._check_open()
        self._task = Task(self.executive, goals, time_limit)

    def update_goal(self, pose: Pose2D) -> None:
        """Replace the goal the running task drives to, keeping the tree running: Nav2's
        navigator on a pre-empting goal for the same tree. The new goal goes on the
        blackboard (``goal``, ``goals``); the tree reacts to it (``GoalUpdated``). Unlike
        ``go_to_pose``, the task, its clock and its counts go on."""
        self._running_task("update_goal").update_goal(pose)

    def add_waypoint(self, pose: Pose2D) -> None:
        """Append ``pose`` to the running task's waypoints (visited after the others)."""
        self._running_task("add_waypoint").add_goal(pose)

    def _running_task(self, what: str) -> Task:
        self._check_open()
        if self._task is None or self._task.done:
            raise RuntimeError(f"Navigator.{what}: no running task")
        return self._task

    def cancel_task(self) -> None:
        """Stop the running task: the tree is halted and the base gets zero velocity."""
        if self._task is not None and not self._task.done:
            self._task.finish("canceled", "canceled by caller")

    # ----------------------------------------------------------------- the loop
    def step(self) -> bool:
        """One control cycle; True once the task has ended (then nothing more is done)."""
        self._check_open()
        if self._task is None:
            raise RuntimeError("Navigator.step: no task (call go_to_pose or follow_waypoints)")
        return self._task.step()

    def run(self, time_limit: float | None = None,
            on_tick: Callable[[Executive], bool | None] | None = None) -> MissionResult:
        """Step until the task ends and return its result. ``time_limit`` (s since the task
        began) replaces the task's own; ``on_tick(executive)`` is called after every cycle and
        returning True stops the task (outcome ``stopped``)."""
        self._check_open()
        if self._task is None:
            raise RuntimeError("Navigator.run: no task (call go_to_pose or follow_waypoints)")
        if time_limit is not None:
            self._task.time_limit = float(time_limit)
        try:
            return self._task.run(on_tick)
        finally:
            self.executive.stop_robot()

    # ----------------------------------------------------------------- reading
    def is_task_complete(self) -> bool:
        """True when there is no task or the task has ended."""
        return self._task is None or self._task.done

    def get_feedback(self) -> Feedback | None:
        """How the task goes (pose, goal, waypoint, distance left, time, recoveries)."""
        return None if self._task is None else self._task.feedback()

    def get_result(self) -> MissionResult | None:
        """The ended task's result, None while it runs or when there is none."""
        return None if self._task is None else self._task.result

    @property
    def status(self) -> str:
        """``idle`` (no task), ``running``, or the ended task's outcome."""
        if self._task is None:
            return "idle"
        return "running" if self._task.result is None else self._task.result.outcome

    def pose(self) -> Pose2D:
        """The robot's pose in ``map`` as the executive last estimated it."""
        return self.executive.robot.pose()

    def blackboard(self, key: str, default: Any = None) -> Any:
        """A mission-level blackboard key (``path``, ``goal``, an output of your node...)."""
        return self.executive.blackboard_get(key, default)

    @property
    def clock(self) -> Clock:
        return self.executive.clock

    @property
    def sim(self) -> Any:
        """The simulator of a simulated mission (None on hardware or your own robot)."""
        return self.mission.sim

    # ----------------------------------------------------------------- ending
    def close(self) -> None:
        """Stop the robot and release the tree and the robot I/O (``io.close()`` if it has
        one). Calling it again does nothing."""
        if self._closed:
            return
        self._closed = True
        self.cancel_task()
        self.executive.shutdown()
        close = getattr(self.executive.io, "close", None)
        if callable(close):
            close()

    def _check_open(self) -> None:
        if self._closed:
            raise RuntimeError("Navigator: the mission is closed")

    def __enter__(self) -> Navigator:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
