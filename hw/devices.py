"""Open a robot's devices from the ``robot.devices`` section of its config.

Each entry is ``<device>://<port>`` or a mapping ``{url: ..., params: {...}, mount: [x, y, theta]}``:

    devices:
      base:  "kobuki:///dev/ttyUSB0"           # a tty path
      laser: "urg04lx://sim?corrupt=0.001"     # the emulator: sim://urg04lx?corrupt=0.001
      imu:   {url: "vectornav://socket://10.0.0.5:7000", params: {async_output_rate: 50}}

``<port>`` is a path, ``sim`` (the device's emulator, URL options passed on), or any pyserial URL
(``socket://``, ``rfc2217://``, ``hwgrep://``, ``sim://...``). Drivers come back started; their
readers never block, and ``close_devices`` stops them. With ``lockstep=True`` they come back without
threads instead: the caller drives them with ``poll_devices`` once per cycle (deterministic on a
SimClock with ``sim://`` emulators).
"""

from __future__ import annotations

from typing import Any, Callable, Mapping

from navcore.clock import Clock
from navcore.types import Pose2D
from hw.errors import HwError

ROLES = {"base": ("kobuki", "arduino"), "laser": ("urg04lx", "lms200", "lms291"),
         "imu": ("razor", "vectornav")}


class DeviceConfigError(HwError, ValueError):
    """The devices section is wrong; the message names the entry and the problem."""


def _factory(device: str) -> Callable[..., Any]:
    # imported lazily: a robot with only a laser does not load the base drivers
    if device == "kobuki":
        from hw.drivers.kobuki import KobukiDriver
        return lambda url, clock, params, mount: KobukiDriver(url, clock, params)
    if device == "arduino":
        from hw.drivers.arduino import ArduinoBaseDriver
        return lambda url, clock, params, mount: ArduinoBaseDriver(url, clock, params)
    if device == "urg04lx":
        from hw.drivers.urg04lx import Urg04lxDriver
        return Urg04lxDriver
    if device in ("lms200", "lms291"):
        from hw.drivers.lms2xx import Lms2xxDriver
        return lambda url, clock, params, mount: Lms2xxDriver(url, clock, params, device, mount)
    if device == "razor":
        from hw.drivers.razor import RazorDriver
        return RazorDriver
    from hw.drivers.vectornav import VectorNavDriver
    return VectorNavDriver


def parse_device_url(role: str, url: str) -> tuple[str, str]:
    """``"<device>://<port>"`` -> (device, pyserial port URL), checked against the role."""
    where = f"devices.{role}"
    if role not in ROLES:
        raise DeviceConfigError(f"{where}: unknown role {role!r} (known: {', '.join(ROLES)})")
    if not isinstance(url, str) or "://" not in url:
        raise DeviceConfigError(f"{where}: {url!r} is not '<device>://<port>', e.g. "
                                f"'{ROLES[role][0]}:///dev/ttyUSB0' or '{ROLES[role][0]}://sim'")
    device, port = url.split("://", 1)
    if device not in ROLES[role]:
        raise DeviceConfigError(f"{where}: {device!r} is not a {role} device "
                                f"(known: {', '.join(ROLES[role])})")
    if not port:
        raise DeviceConfigError(f"{where}: {url!r} names no port")
    if port == "sim" or port.startswith("sim?"):
        port = f"sim://{device}" + port[3:]
    return device, port


def open_devices(devices: Mapping[str, Any], clock: Clock, lockstep: bool = False
                 ) -> dict[str, Any]:
    """Build and start the driver of every role in ``devices`` (keys: base, laser, imu).
    Configuration errors are raised before any driver starts. ``lockstep``: no reader threads;
    the drivers connect and read on ``poll_devices``."""
    if not isinstance(devices, Mapping):
        raise DeviceConfigError(f"devices: expected a mapping of role to URL, got {devices!r}")
    plans = []
    for role, entry in devices.items():
        params: Mapping[str, Any] = {}
        mount = Pose2D()
        if isinstance(entry, Mapping):
            unknown = set(entry) - {"url", "params", "mount"}
            if unknown:
                raise DeviceConfigError(f"devices.{role}: unknown key(s) {sorted(unknown)} "
                                        f"(known: url, params, mount)")
            url = entry.get("url")
            params = entry.get("params") or {}
            m = entry.get("mount", [0.0, 0.0, 0.0])
            if not (isinstance(m, (list, tuple)) and len(m) == 3
                    and all(isinstance(v, (int, float)) for v in m)):
                raise DeviceConfigError(f"devices.{role}.mount: expected [x, y, theta], got {m!r}")
            mount = Pose2D(*map(float, m))
        else:
            url = entry
        device, port = parse_device_url(role, url)
        try:
            drv = _factory(device)(port, clock, params, mount)
        except ValueError as e:          # ParameterError names the parameter
            raise DeviceConfigError(f"devices.{role}: {e}") from None
        plans.append((role, drv))
    if lockstep:
        return dict(plans)
    return {role: drv.start() for role, drv in plans}


def poll_devices(opened: Mapping[str, Any]) -> None:
    """One lock-step turn of every thread-free driver (base first: on an emulated robot its
    emulator steps the world the others then measure)."""
    for role in sorted(opened, key=lambda r: r != "base"):
        opened[role].poll()


def close_devices(opened: Mapping[str, Any]) -> None:
    """Stop every driver (the base gets a stop command on the way out) and join its thread."""
    for drv in opened.values():
        drv.close()
