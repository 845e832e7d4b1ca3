"""The robot I/O adapters (``hw.interfaces.RobotIO``) the executive drives.

``SimIO``: the simulator's direct interfaces. ``HardwareIO``: real drivers (hw/devices.py) with
reader threads on the wall clock. ``EmulatedIO``: the real Kobuki and URG-04LX drivers in
lock-step over byte streams whose device emulators the simulator drives. ``open_robot_io`` picks
one from ``build_mission``'s ``hardware`` argument.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from hw.interfaces import RobotIO
from navcore.clock import Clock
from navcore.maps import OccupancyGrid
from navcore.types import Pose2D

from executive.config import RobotConfig
from executive.errors import WiringError
from executive.world import World


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

    def diagnostics(self) -> dict[str, Any]:
        """Each driver's health (frames delivered, rejected, implausible; last error)."""
        return {role: d.diagnostics() for role, d in self.devices.items()
                if callable(getattr(d, "diagnostics", None))}

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


def simulator(config: RobotConfig, grid: OccupancyGrid, start: Pose2D, world: World,
              clock: Clock, rng: np.random.Generator) -> Any:
    """The simulator (hw.sim) on ``grid`` with the world's objects, moving obstacles and faults."""
    from hw.sim import Box, Circle, MovingObstacle, Simulator
    from hw.sim import SimWorld
    objects: list[Any] = []
    for i, s in enumerate(world.objects):
        if s.kind == "box":
            objects.append(Box(*s.values, name=f"object{i}"))
        else:
            objects.append(Circle(*s.values, name=f"object{i}"))
    for i, m in enumerate(world.moving):
        objects.append(MovingObstacle(tuple(m.waypoints), speed=m.speed, radius=m.radius,
                                      start_time=m.start_time, loop=m.loop, name=f"moving{i}"))
    sim = Simulator(SimWorld(grid, objects, unknown_is_obstacle=world.unknown_solid),
                    config.ns("sim"), clock, rng, start=start)
    sim.add_faults(world.faults)
    return sim


def emulated_io(config: RobotConfig, sim: Any, clock: Clock, rng: np.random.Generator,
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


def open_robot_io(mode: str, config: RobotConfig, grid: OccupancyGrid, start: Pose2D | None,
                  world: World, clock: Clock, rng: np.random.Generator, ident: str
                  ) -> tuple[RobotIO, Any]:
    """The robot I/O of a ``hardware_mode`` and the simulator behind it (None on hardware)."""
    if mode == "devices":
        if config.robot.devices != "hw" or "base" not in config.devices:
            raise WiringError(f"{config.source}: robot: devices: give {{base: URL, laser: URL}} "
                              "to drive real hardware")
        from hw.devices import DeviceConfigError, open_devices
        try:
            return HardwareIO(open_devices(config.devices, clock)), None
        except (DeviceConfigError, OSError) as e:
            raise WiringError(f"{config.source}: {e}") from None
    sim = simulator(config, grid, start or Pose2D(), world, clock, rng)
    if mode == "emulated":
        return emulated_io(config, sim, clock, rng, ident), sim
    return SimIO(sim), sim


def laser_mount(io: RobotIO) -> Pose2D:
    """Where the laser sits on the base (identity when there is none)."""
    mount = getattr(io.laser, "mount", None)
    return mount if mount is not None else Pose2D()
