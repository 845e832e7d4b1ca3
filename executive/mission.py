"""Wiring: a robot config + a map + a tree file -> a ready Executive on the simulator (or hardware).

This is the one place that knows how each component is constructed; the Executive itself only
sees the ``behaviors.components`` contract. ``run_mission`` adds the run folder and progress line
that the CLI and the scenario runner share.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from typing import Any, Callable

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
def _costmaps(config: RobotConfig, grid: OccupancyGrid, clock: Clock) -> tuple[Any, Any]:
    from executive.config import make_costmap
    fp = [list(p) for p in config.footprint()]
    g = config.ns("global_costmap")
    g.setdefault("footprint", fp)
    local = config.ns("local_costmap")
    local.setdefault("footprint", fp)
    local.setdefault("rolling_window", True)
    return (make_costmap(g, grid, "global_costmap", clock),
            make_costmap(local, grid, "local_costmap", clock))


def _planner(config: RobotConfig, global_cm: Any) -> Any:
    from navcore.planners import make_planner
    ns = config.global_planner_namespace()
    return make_planner(config.move_base.base_global_planner, global_cm.costmap, config.ns(ns),
                        global_cm.footprint_cost)


def _controller(config: RobotConfig, local_cm: Any) -> Any:
    from navcore.controllers import make_controller
    ns = config.local_planner_namespace()
    params = config.ns(ns)
    # as in ROS, the local planner's sim_period follows move_base's controller_frequency
    params.setdefault("controller_frequency", config.move_base.controller_frequency)
    # the costmap's padded footprint, as move_base hands the local planner the costmap's one
    return make_controller(config.move_base.base_local_planner, local_cm.costmap,
                           np.asarray(local_cm.footprint, np.float64), params)


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


class HardwareIO:
    """RobotIO over real drivers (hw/devices.py): no ground truth, contacts from the bumper."""

    def __init__(self, devices: dict[str, Any]) -> None:
        self.devices = devices
        self.base = devices["base"]
        self.laser = devices.get("laser")

    def step_to(self, t: float) -> None:
        pass  # the drivers' reader threads keep the newest messages

    def true_pose(self) -> Pose2D | None:
        return None

    def in_collision(self) -> bool:
        return bool(self.base.events().bumper)

    def close(self) -> None:
        from hw.devices import close_devices
        close_devices(self.devices)


class _LockstepBase:
    """A thread-free base driver whose command goes on the wire at once: in lock-step a command
    sent after the cycle's poll would otherwise wait a whole cycle for the next one."""

    def __init__(self, driver: Any) -> None:
        self.driver = driver
        self.closed = False     # after close a poll would open the port again

    def send(self, cmd: Any) -> None:
        self.driver.send(cmd)
        if not self.closed:
            self.driver.poll()

    def odometry(self) -> Any:
        return self.driver.odometry()

    def battery(self) -> Any:
        return self.driver.battery()

    def events(self) -> Any:
        return self.driver.events()


class EmulatedIO(HardwareIO):
    """RobotIO over the real Kobuki and URG-04LX drivers in lock-step (polled once per cycle on
    the mission clock), their emulators driven by the simulator (``hw.sim.emulated_devices``).

    The executive's control sees only the drivers (pose from AMCL over their odometry and
    scans); ``true_pose`` and ``in_collision`` are the simulator's, for the record and scoring."""

    def __init__(self, devices: dict[str, Any], bridge: Any) -> None:
        super().__init__(devices)
        self.base = _LockstepBase(devices["base"])
        self.bridge = bridge
        self.sim = bridge.sim

    def step_to(self, t: float) -> None:
        from hw.devices import poll_devices
        poll_devices(self.devices)   # the base emulator steps the simulator up to the clock

    def true_pose(self) -> Pose2D | None:
        return self.sim.true_pose()

    def in_collision(self) -> bool:
        return bool(self.sim.in_collision())

    def close(self) -> None:
        self.base.closed = True
        try:
            super().close()
        finally:
            self.bridge.unplug()


def _emulated_io(config: RobotConfig, sim: Any, clock: Clock, rng: np.random.Generator,
                 ident: str) -> EmulatedIO:
    """Kobuki and URG-04LX emulators on ``sim``, their drivers opened thread-free and started
    (connected and delivering) in lock-step. When ``robot.devices`` names these devices on
    ``sim`` ports, their driver ``params`` and URL fault options (``urg04lx://sim?corrupt=0.001``)
    are used."""
    from urllib.parse import parse_qs, urlsplit

    from hw.devices import DeviceConfigError, open_devices
    from hw.emulators import Faults
    from hw.sim.emulated_devices import SimDevices, lockstep_start
    noise_rng, wire_rng = rng.spawn(2)     # children: the mission's own draws stay as they are
    try:
        bridge = SimDevices(sim, noise_rng, ident.strip("/"))
    except ValueError as e:
        raise WiringError(f"{config.source}: {e}") from None
    params: dict[str, Any] = {}
    faults: dict[str, Any] = {}
    for role, device in (("base", "kobuki"), ("laser", "urg04lx")):
        given = (config.devices or {}).get(role)
        url = str(given.get("url", "")) if isinstance(given, dict) else str(given or "")
        if not url.startswith(device + "://sim"):
            continue
        if isinstance(given, dict):
            params[role] = given.get("params") or {}
        q = {k: v[-1] for k, v in parse_qs(urlsplit(url).query).items()}
        try:
            faults[role] = Faults(**{k: float(v) for k, v in q.items() if k not in ("id", "seed")})
        except (TypeError, ValueError) as e:
            raise WiringError(f"{config.source}: robot: devices: {role}: {url}: bad fault "
                              f"option ({e})") from None
    urls = bridge.plug(faults, seed=int(wire_rng.integers(0, 2 ** 31)))
    m = bridge.mount
    entries: dict[str, Any] = {
        "base": {"url": urls["base"], "params": params.get("base", {})},
        "laser": {"url": urls["laser"], "params": params.get("laser", {}),
                  "mount": [m.x, m.y, m.theta]}}
    try:
        devices = open_devices(entries, clock, lockstep=True)
        lockstep_start(devices, clock)
    except (DeviceConfigError, TimeoutError) as e:
        bridge.unplug()
        raise WiringError(f"{config.source}: emulated devices: {e}") from None
    return EmulatedIO(devices, bridge)


def hardware_mode(hardware: bool | str) -> str:
    """``build_mission``'s ``hardware`` -> "sim", "devices" (robot.devices, wall clock, reader
    threads) or "emulated" (the simulator behind device emulators, drivers in lock-step)."""
    if hardware is False or hardware in ("sim", "", None):
        return "sim"
    if hardware is True or hardware == "devices":
        return "devices"
    if hardware == "emulated":
        return "emulated"
    raise WiringError(f"hardware: expected False, True, 'devices' or 'emulated', got {hardware!r}")


def amcl_estimator(config: RobotConfig, grid: OccupancyGrid, start: Pose2D | None,
                   mount: Pose2D, rng: np.random.Generator) -> tuple[Any, Any]:
    """AMCL (navcore.localization) as the executive's estimator: map pose = map->odom (+) odom.

    The filter starts at ``start`` unless the config gives ``initial_pose_*``."""
    from navcore.localization.amcl import Amcl
    params = config.ns("amcl")
    if start is not None:
        params.setdefault("initial_pose_x", start.x)
        params.setdefault("initial_pose_y", start.y)
        params.setdefault("initial_pose_a", start.theta)
    amcl = Amcl(grid, params, rng)

    def estimate(odom: Any, scan: Any, now: float) -> Pose2D | None:
        if odom is None:
            return None
        amcl.update(odom.pose, scan, mount)
        return amcl.map_to_odom().compose(odom.pose)
    return amcl, estimate


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


def paint_phantom(cm: Any, shape: Shape) -> int:
    """Mark a shape LETHAL in every clearable (obstacle) layer of a costmap; returns the cells.

    The cells persist like any stale observation: until a clear recovery resets the layer or a
    laser ray passes through them (ray-trace clearing), exactly as a ghost obstacle would."""
    from navcore.costmap.cost_values import LETHAL_OBSTACLE
    x0, y0, x1, y1 = _bbox(shape)
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


def _bbox(shape: Shape) -> tuple[float, float, float, float]:
    if shape.kind == "box":
        return shape.values  # type: ignore[return-value]
    x, y, r = shape.values
    return x - r, y - r, x + r, y + r


def build_mission(tree_path: str, config: RobotConfig, grid: OccupancyGrid,
                  start: Pose2D | None, *,
                  world: World | None = None, seed: int = 0, realtime: bool = False,
                  recorder: Recorder | None = None, meta: dict[str, Any] | None = None,
                  hardware: bool | str = False) -> Mission:
    """Load the tree, build every component from ``config`` and put them in an Executive.

    ``hardware``: False runs the simulator's direct interfaces; True (or "devices") the drivers
    of ``robot.devices`` on the wall clock with reader threads; "emulated" the real Kobuki and
    URG-04LX drivers in lock-step over ``sim://`` byte streams whose emulators the simulator
    drives (deterministic on the simulated clock, one trace per seed)."""
    world = world or World()
    mode = hardware_mode(hardware)
    clock: Clock = WallClock() if realtime or mode == "devices" else SimClock()
    rng = np.random.default_rng(seed)
    from executive.executive import _mission_ids  # shared counter keeps namespaces unique
    namespace = f"/mission_{next(_mission_ids)}"
    tree = load_tree_file(tree_path, namespace=namespace)
    try:
        global_cm, local_cm = _costmaps(config, grid, clock)
        planner = _planner(config, global_cm)
        controller = _controller(config, local_cm)
    except ImportError as e:
        raise WiringError(f"component not available: {e}") from None
    sim = None
    if mode == "devices":
        if config.robot.devices != "hw" or "base" not in config.devices:
            raise WiringError(f"{config.source}: robot: devices: give {{base: URL, laser: URL}} "
                              "to drive real hardware")
        from hw.devices import DeviceConfigError, open_devices
        try:
            io: Any = HardwareIO(open_devices(config.devices, clock))
        except (DeviceConfigError, OSError) as e:
            raise WiringError(f"{config.source}: {e}") from None
        mount = getattr(io.laser, "mount", Pose2D())
    elif mode == "emulated":
        sim = _simulator(config, grid, start or Pose2D(), world, clock, rng)
        io = _emulated_io(config, sim, clock, rng, namespace)
        mount = io.laser.mount
    else:
        sim = _simulator(config, grid, start or Pose2D(), world, clock, rng)
        io = SimIO(sim)
        mount = sim.config.laser.mount if sim.config.laser is not None else Pose2D()
    localizer, estimator = None, None
    if "amcl" in config.namespaces or mode != "sim":   # drivers give no ground truth
        localizer, estimator = amcl_estimator(config, grid, start, mount, rng)
    components = {
        "global_costmap": global_cm,
        "local_costmap": local_cm,
        "planners": {"GridBased": planner},
        "controllers": {"FollowPath": controller},
        "localizer": localizer,
        "parameters": live_parameters(config, global_cm, local_cm, planner, controller,
                                      localizer),
    }

    periods = {id(global_cm): _update_period(global_cm), id(local_cm): _update_period(local_cm)}
    due = {id(global_cm): -math.inf, id(local_cm): -math.inf}
    phantoms_pending = list(world.phantoms)
    scans = LazyScans([local_cm, global_cm])

    def perceive(pose: Pose2D, scan: LaserScan | None, now: float) -> None:
        if scan is not None and scan is not state.get("scan"):
            state["scan"] = scan
            laser_pose = pose.compose(mount)
            scans.add(local_cm, scan, laser_pose)
            scans.add(global_cm, scan, laser_pose)
        for cm in (local_cm, global_cm):
            if now >= due[id(cm)] - _SCHEDULE_SLACK:
                scans.flush(cm)
                cm.update_map(pose)
                # a fixed rate like ros::Rate: the next deadline is one period after this one
                # (now + period would let float sums push it one control tick late each time);
                # after a stall longer than a period the schedule restarts from now
                period = periods[id(cm)]
                nxt = due[id(cm)] + period
                due[id(cm)] = nxt if nxt > now else now + period
        if phantoms_pending:
            # after the first update, so the rolling window is already around the robot
            for shape, which in phantoms_pending:
                for cm in {"global": [global_cm], "local": [local_cm],
                           "both": [global_cm, local_cm]}[which]:
                    paint_phantom(cm, shape)
            phantoms_pending.clear()
            scans.flush(local_cm)
            scans.flush(global_cm)
            local_cm.update_map(pose)
            global_cm.update_map(pose)

    state: dict[str, Any] = {}
    try:
        ex = Executive(tree, io, clock, config.control_period(), components,
                       safety=SafetyGate(config.safety), recorder=recorder,
                       perceivers=[perceive], estimator=estimator, namespace=namespace,
                       meta=dict(meta or {}, tree=os.path.abspath(tree_path),
                                 start=None if start is None else [start.x, start.y,
                                                                   start.theta]))
    except Exception as e:  # noqa: BLE001 - a node's setup (e.g. a missing component)
        if isinstance(io, HardwareIO):
            io.close()       # drivers opened for a mission that will not run
        raise WiringError(f"{tree_path}: tree setup failed: {e}") from None
    return Mission(ex, grid, config, sim, components, world, tree_path)


def live_parameters(config: RobotConfig, global_cm: Any, local_cm: Any, planner: Any,
                    controller: Any, localizer: Any) -> dict[str, Any]:
    """ROS namespace -> the live Parameters object each component reads (SetParameters's view).

    The components' own objects, not copies: a change takes effect at their next cycle."""
    out: dict[str, Any] = dict(config.all_parameters())
    for cm in (global_cm, local_cm):
        if hasattr(cm, "parameter_namespaces"):
            out.update(cm.parameter_namespaces())
    if getattr(planner, "params", None) is not None:
        out[config.global_planner_namespace()] = planner.params
    if getattr(controller, "params", None) is not None:
        out[config.local_planner_namespace()] = controller.params
    if localizer is not None and getattr(localizer, "params", None) is not None:
        out["amcl"] = localizer.params
    return out


class LazyScans:
    """Scans for costmaps whose sensor buffers keep only the newest reading and check no reading
    rate (ROS's defaults): such a costmap only ever uses the last scan before something reads
    its buffers, so each scan is kept aside and added (converted to points) just before an
    update or a clear (which recomposes the map at once), or a change of the costmap's
    parameters; a reset forgets it, as it would have cleared it from the buffers. The costmaps end up exactly as with every scan added at once,
    at the cost of one conversion per update instead of one per scan. Scans are values: nobody
    changes one after publishing it."""

    def __init__(self, costmaps: list[Any]) -> None:
        self._unadded: dict[int, tuple[LaserScan, Pose2D]] = {}
        for cm in costmaps:
            self._hook(cm)

    def add(self, cm: Any, scan: LaserScan, laser_pose: Pose2D) -> None:
        """A new scan for ``cm``, taken with the laser at ``laser_pose``."""
        if (self.newest_only(cm) and math.isfinite(laser_pose.x)
                and math.isfinite(laser_pose.y)):  # (an unusable pose still fails at once)
            self._unadded[id(cm)] = (scan, laser_pose)
        else:
            self.flush(cm)
            cm.add_scan(scan, laser_pose)

    def flush(self, cm: Any) -> None:
        """Add the scan kept aside for ``cm``, if any."""
        item = self._unadded.pop(id(cm), None)
        if item is not None:
            cm.add_scan(*item)

    @staticmethod
    def newest_only(cm: Any) -> bool:
        layers = getattr(cm, "obstacle_layers", None)
        if layers is None:
            return False
        for layer in layers():
            for buf in layer.buffers.values():
                p = buf.params
                if p.observation_persistence != 0.0 or p.expected_update_rate != 0.0:
                    return False
        return True

    def _hook(self, cm: Any) -> None:
        if getattr(cm, "obstacle_layers", None) is None:
            return  # never kept aside (see newest_only)
        reset, clear_outside, clear_inside = cm.reset_layers, cm.clear_outside, cm.clear_inside

        def reset_layers() -> None:
            self._unadded.pop(id(cm), None)
            reset()

        def clearing(clear: Callable[..., None]) -> Callable[..., None]:
            def call(*args: Any, **kwargs: Any) -> None:
                self.flush(cm)
                clear(*args, **kwargs)
            return call
        cm.reset_layers = reset_layers
        cm.clear_outside = clearing(clear_outside)
        cm.clear_inside = clearing(clear_inside)
        # a scan kept aside is added with the parameters it arrived under (obstacle_range,
        # heights, persistence...), as it would have been at once
        for params in cm.parameter_namespaces().values():
            params.before_change(lambda _values, _cm=cm: self.flush(_cm))


# s: a deadline this close to a tick counts as reached. The clock and the deadlines are sums of
# float periods; their rounding drifts apart by ~1e-9 s per half hour simulated, 1 us by far later.
_SCHEDULE_SLACK = 1e-6


def _update_period(cm: Any) -> float:
    f = float(getattr(cm.params, "update_frequency", 0.0))
    return 1.0 / f if f > 0 else 0.0


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
