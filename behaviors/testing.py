"""Scripted stand-ins for the components, for whole-tree tests without the simulator.

In the style of Nav2's behaviour-tree system tests: a kinematic robot that integrates the
commanded velocity, costmaps that count clearings and answer footprint queries from a function,
a planner and a controller that fail on the calls you choose, and ``run_tree``, the control loop
in miniature (tick, integrate, advance the clock). With ``fixed_path`` / ``fixed_command`` the
planner and controller cost next to nothing (benchmarks of tree overhead); ``noop_components``
assembles the doubles for an Executive. The robot I/O double the Executive drives is
hw/testing.py's ``KinematicRobot`` (RobotIO is hw's interface, which behaviors must not import).
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, field
from typing import Any, Callable, Iterable

import numpy as np

from navcore.clock import SimClock
from navcore.costmap.costmap2d import Costmap2D
from navcore.controllers.result import ControlResult, ControlStatus
from navcore.params import Param, Parameters
from navcore.planners.result import PlanReason, PlanResult
from navcore.types import BaseEvents, BatteryState, Path, Pose2D, Twist, angle_diff


class FakeRobot:
    """A robot whose pose follows the commanded body velocity exactly (no dynamics)."""

    def __init__(self, pose: Pose2D = Pose2D(), battery: BatteryState | None = None) -> None:
        self._pose = pose
        self._vel = Twist.zero()
        self._battery = battery
        self.trajectory: list[Pose2D] = [pose]

    def pose(self) -> Pose2D:
        return self._pose

    def velocity(self) -> Twist:
        return self._vel

    def battery(self) -> BatteryState | None:
        return self._battery

    def events(self) -> BaseEvents:
        return BaseEvents()

    def teleport(self, pose: Pose2D) -> None:
        self._pose = pose

    def apply(self, cmd: Twist, dt: float) -> None:
        """Integrate ``cmd`` for ``dt`` seconds (exact arc for a unicycle)."""
        p = self._pose
        if abs(cmd.wz) < 1e-9:
            dx, dy = cmd.vx * dt, cmd.vy * dt
        else:
            r = cmd.vx / cmd.wz
            dx, dy = r * math.sin(cmd.wz * dt), r * (1.0 - math.cos(cmd.wz * dt))
        self._pose = p.compose(Pose2D(dx, dy, cmd.wz * dt))
        self._vel = cmd
        self.trajectory.append(self._pose)


Footprint = Callable[[float, float, float], int]


class FakeCostmap:
    """A CostmapHandle: a free grid, a footprint-cost function, and counters of clearings."""

    def __init__(self, footprint: Footprint | None = None, size_m: float = 20.0,
                 resolution: float = 0.05, origin: float = -10.0) -> None:
        n = int(round(size_m / resolution))
        self.costmap = Costmap2D(n, n, resolution, origin, origin)
        self.footprint = footprint or (lambda x, y, t: 0)
        self.resets = 0
        self.clear_outside_calls: list[tuple[float, float, float]] = []
        self.clear_inside_calls: list[tuple[float, float, float]] = []

    def reset_layers(self) -> None:
        self.resets += 1

    def clear_outside(self, x: float, y: float, reset_distance: float) -> None:
        self.clear_outside_calls.append((x, y, reset_distance))

    def clear_inside(self, x: float, y: float, reset_distance: float) -> None:
        self.clear_inside_calls.append((x, y, reset_distance))

    def footprint_cost(self, x: float, y: float, theta: float) -> int:
        return int(self.footprint(x, y, theta))

    @property
    def clearings(self) -> int:
        return self.resets + len(self.clear_outside_calls) + len(self.clear_inside_calls)


def straight_path(start: Pose2D, goal: Pose2D, step: float = 0.05) -> Path:
    """Poses from start to goal on a straight line, heading along it, goal heading last."""
    d = start.distance_to(goal)
    n = max(2, int(math.ceil(d / step)) + 1)
    heading = math.atan2(goal.y - start.y, goal.x - start.x) if d > 1e-9 else goal.theta
    xs = np.linspace(start.x, goal.x, n)
    ys = np.linspace(start.y, goal.y, n)
    th = np.full(n, heading)
    th[-1] = goal.theta
    return Path(np.column_stack([xs, ys, th]))


def _in(i: int, which: Iterable[int] | Callable[[int], bool] | None) -> bool:
    if which is None:
        return False
    if callable(which):
        return bool(which(i))
    return i in which


class ScriptedPlanner:
    """Straight-line planner that fails on chosen calls (1-based call numbers) or always, with
    ``reason`` (a failing ``PlanReason``). Given ``fixed_path`` it returns that path on every
    other call, whatever the start and goal: planning then costs nothing (benchmarks)."""

    def __init__(self, fail_calls: Iterable[int] | Callable[[int], bool] | None = None,
                 reason: PlanReason = PlanReason.NO_PATH, fail_always: bool = False,
                 step: float = 0.05, fixed_path: Path | None = None) -> None:
        if not isinstance(reason, PlanReason):
            raise TypeError(f"ScriptedPlanner: reason must be a PlanReason, got {reason!r}")
        if reason is PlanReason.NONE:
            raise ValueError("ScriptedPlanner: reason must say why planning fails, got NONE")
        self.fail_calls = set(fail_calls) if isinstance(fail_calls, (list, tuple, set, range)) \
            else fail_calls
        self.reason = reason
        self.step = step  # spacing of the straight path's poses, m
        self.fail_always = fail_always
        self._fixed = None if fixed_path is None else PlanResult(True, fixed_path, PlanReason.NONE)
        self.calls = 0
        self.goals: list[Pose2D] = []

    def make_plan(self, start: Pose2D, goal: Pose2D) -> PlanResult:
        self.calls += 1
        self.goals.append(goal)
        if self.fail_always or (self.fail_calls is not None and _in(self.calls, self.fail_calls)):
            return PlanResult.failure(self.reason)
        if self._fixed is not None:
            return self._fixed
        return PlanResult(True, straight_path(start, goal, self.step), PlanReason.NONE)


class ScriptedController:
    """Turn toward the end of the plan and drive there; "no_valid_trajectory" on chosen calls.

    Goal reached within ``xy_goal_tolerance``. ``parameters`` (DWAPlannerROS-like) lets
    SetParameters be observed: ``bias_log`` records ``path_distance_bias`` at every call. Given
    ``fixed_command`` it answers every other call "following" with that command, plan or not,
    and never reaches the goal: controlling then costs nothing (benchmarks).
    """

    def __init__(self, fail_calls: Iterable[int] | Callable[[int], bool] | None = None,
                 fail_always: bool = False, max_vel_x: float = 0.5, max_vel_theta: float = 1.0,
                 xy_goal_tolerance: float = 0.1, parameters: Parameters | None = None,
                 fixed_command: Twist | None = None) -> None:
        self.fail_calls = set(fail_calls) if isinstance(fail_calls, (list, tuple, set, range)) \
            else fail_calls
        self.fail_always = fail_always
        self.max_vel_x, self.max_vel_theta = max_vel_x, max_vel_theta
        self.tol = xy_goal_tolerance
        self.parameters = parameters
        self._fixed = None if fixed_command is None \
            else ControlResult(fixed_command, ControlStatus.FOLLOWING)
        self.calls = 0
        self.plans_set = 0
        self.resets = 0
        self.plan: Path | None = None
        self._reached = False
        self.bias_log: list[float] = []
        self._goal_of: Path | None = None
        self._goal = Pose2D()

    def set_plan(self, path: Path) -> None:
        self.plans_set += 1
        self.plan = path
        self._reached = False

    def reset(self) -> None:
        self.resets += 1
        self._reached = False

    def is_goal_reached(self) -> bool:
        return self._reached

    def compute_velocity(self, pose: Pose2D, velocity: Twist, path: Path | None = None
                         ) -> ControlResult:
        self.calls += 1
        if self.parameters is not None and "path_distance_bias" in self.parameters:
            self.bias_log.append(self.parameters.path_distance_bias)
        if path is not None:
            self.set_plan(path)
        if self.fail_always or (self.fail_calls is not None and _in(self.calls, self.fail_calls)):
            return ControlResult(Twist.zero(), ControlStatus.NO_VALID_TRAJECTORY)
        if self._fixed is not None:
            return self._fixed
        if self.plan is None:
            return ControlResult(Twist.zero(), ControlStatus.NO_VALID_TRAJECTORY)
        if self._goal_of is not self.plan:  # the plan's last pose, read once per plan
            self._goal_of, self._goal = self.plan, self.plan.pose(len(self.plan) - 1)
        goal = self._goal
        d = pose.distance_to(goal)
        if d <= self.tol:
            self._reached = True
            return ControlResult(Twist.zero(), ControlStatus.GOAL_REACHED)
        err = angle_diff(math.atan2(goal.y - pose.y, goal.x - pose.x), pose.theta)
        wz = max(-self.max_vel_theta, min(self.max_vel_theta, 2.0 * err))
        vx = self.max_vel_x * max(0.0, math.cos(err)) if abs(err) < 0.8 else 0.0
        vx = min(vx, d / 0.05 * 0.5)
        return ControlResult(Twist(vx, 0.0, wz), ControlStatus.FOLLOWING)


DWA_LIKE = (Param("path_distance_bias", 32.0, float, "weight of staying on the path", 0.0),
            Param("goal_distance_bias", 24.0, float, "weight of reaching the local goal", 0.0),
            Param("occdist_scale", 0.01, float, "weight of obstacle distance", 0.0))


class ReversingController:
    """A local planner allowed to reverse (min_vel_x < 0): straight at its plan's last pose at
    0.3 m/s, backwards when that pose lies behind; GOAL_REACHED within 0.05 m. ``calls``
    counts ``compute_velocity``."""

    def __init__(self) -> None:
        self.plan: Path | None = None
        self.calls = 0

    def set_plan(self, path: Path) -> None:
        self.plan = path

    def reset(self) -> None:
        pass

    def is_goal_reached(self) -> bool:
        return False

    def compute_velocity(self, pose: Pose2D, velocity: Twist, path: Path | None = None
                         ) -> ControlResult:
        self.calls += 1
        assert self.plan is not None
        ahead = self.plan.pose(len(self.plan) - 1).relative_to(pose)
        if math.hypot(ahead.x, ahead.y) < 0.05:
            return ControlResult(Twist.zero(), ControlStatus.GOAL_REACHED)
        return ControlResult(Twist(math.copysign(0.3, ahead.x), 0.0, 0.0),
                             ControlStatus.FOLLOWING)


@dataclass
class ScriptedWorld:
    """Everything ``tree.setup`` needs, scripted (a test double, not the simulator's
    ``hw.sim.SimWorld`` nor a scenario's ``executive.World``); ``components()`` gives the kwargs."""

    clock: SimClock = field(default_factory=SimClock)
    robot: FakeRobot = field(default_factory=FakeRobot)
    local_costmap: FakeCostmap = field(default_factory=FakeCostmap)
    global_costmap: FakeCostmap = field(default_factory=FakeCostmap)
    planner: ScriptedPlanner = field(default_factory=ScriptedPlanner)
    controller: ScriptedController | None = None
    parameters: dict[str, Parameters] = field(default_factory=dict)
    control_period: float = 0.05

    def __post_init__(self) -> None:
        if "DWAPlannerROS" not in self.parameters:
            self.parameters["DWAPlannerROS"] = Parameters(DWA_LIKE, where="DWAPlannerROS")
        if self.controller is None:
            self.controller = ScriptedController(parameters=self.parameters["DWAPlannerROS"])

    def components(self) -> dict[str, Any]:
        return {"clock": self.clock, "robot": self.robot, "local_costmap": self.local_costmap,
                "global_costmap": self.global_costmap, "planners": {"GridBased": self.planner},
                "controllers": {"FollowPath": self.controller}, "localizer": None,
                "parameters": self.parameters, "control_period": self.control_period}

    def step(self, cmd: Twist) -> None:
        """Apply a command for one period and advance the clock."""
        self.robot.apply(cmd, self.control_period)
        self.clock.advance(self.control_period)


class NodeRig:
    """One node (or a small subtree) under test in a blackboard namespace of its own, set up with
    ``components`` (a dict, or a ``ScriptedWorld`` whose ``components()`` are read when a node is
    made): ``node`` makes and sets it up, ``put`` / ``get`` reach its blackboard, ``tick`` ticks
    it once. ``run`` ticks it until it finishes, the robot of a ``ScriptedWorld`` following
    ``cmd_vel``."""

    _ids = itertools.count()

    def __init__(self, components: dict[str, Any] | ScriptedWorld | None = None) -> None:
        from py_trees.blackboard import Client
        self.world = components if isinstance(components, ScriptedWorld) else None
        self.components = {} if components is None or self.world else dict(components)
        self.ns = f"/rig{next(self._ids)}"
        self.bb = Client(name="rig", namespace=self.ns)

    def node(self, node_type: str, **ports: Any) -> Any:
        from behaviors.base import make
        node = make(node_type, namespace=self.ns, **ports)
        given = self.world.components() if self.world is not None else self.components
        for n in node.iterate():
            n.setup(**given)
        return node

    def put(self, key: str, value: Any) -> None:
        self._register(key)
        self.bb.set(key, value)

    def get(self, key: str) -> Any:
        self._register(key)
        return self.bb.get(key) if self.bb.exists(key) else None

    def _register(self, key: str) -> None:
        from py_trees.common import Access
        if not self.bb.is_registered(key):
            self.bb.register_key(key, access=Access.WRITE)

    @staticmethod
    def tick(node: Any) -> Any:
        node.tick_once()
        return node.status

    def run(self, node: Any, max_ticks: int = 2000) -> tuple[Any, int]:
        """Tick until it finishes, applying ``cmd_vel`` to the ScriptedWorld's robot each period:
        (final status, ticks used)."""
        from py_trees.common import Status
        assert self.world is not None, "run needs a ScriptedWorld"
        for i in range(max_ticks):
            self.put("cmd_vel", Twist.zero())
            node.tick_once()
            if node.status != Status.RUNNING:
                return node.status, i + 1
            self.world.step(self.get("cmd_vel"))
        return node.status, max_ticks


def run_tree(tree: Any, world: ScriptedWorld, max_ticks: int = 5000,
             on_tick: Callable[[int, ScriptedWorld], None] | None = None) -> tuple[Any, int]:
    """Tick a LoadedTree-like object (``tick() -> Twist``, ``status``) until it finishes.

    Returns (final status, ticks used). ``on_tick(i, world)`` runs before each tick (to change
    the goal, move an obstacle, ...).
    """
    from py_trees.common import Status
    for i in range(max_ticks):
        if on_tick is not None:
            on_tick(i, world)
        cmd = tree.tick()
        if tree.status in (Status.SUCCESS, Status.FAILURE):
            return tree.status, i + 1
        world.step(cmd)
    return tree.status, max_ticks


def noop_components(parameters: dict[str, Parameters]) -> dict[str, Any]:
    """The ``tree.setup`` components of an Executive with no real algorithm: free costmaps over
    hw.testing's square room, a straight-line planner and a controller driving toward the
    plan's end, so trees run their real paths to success. ``parameters`` are the live
    Parameters by namespace (the executive's config makes them: behaviors cannot)."""
    return {
        "global_costmap": FakeCostmap(size_m=10.0, origin=-5.0),
        "local_costmap": FakeCostmap(size_m=10.0, origin=-5.0),
        "planners": {"GridBased": ScriptedPlanner(step=0.3)},
        "controllers": {"FollowPath": ScriptedController(max_vel_theta=1.5)},
        "localizer": None,
        "parameters": parameters,
    }


__all__ = ["FakeRobot", "FakeCostmap", "ScriptedPlanner", "ScriptedController",
           "ReversingController", "ScriptedWorld",
           "NodeRig", "noop_components", "run_tree", "straight_path", "DWA_LIKE"]
