"""Faithful device emulators behind a pyserial URL scheme (``sim://<device>``) and pty pairs.

Importing this package registers the ``sim://`` scheme with pyserial. Emulator instances live in
a registry keyed by id, so a driver that reconnects after an unplug finds the same device, and a
simulator or test can create an emulator (with its data source) and plug it in under an id:

    link = plug("front", Urg04lxEmulator(clock, ranges_source=world_rays))
    serial.serial_for_url("sim://urg04lx?id=front")
"""

from __future__ import annotations

import threading
from urllib.parse import parse_qs, urlsplit

import serial

from hw.emulators.link import Emulator, Faults, Link, Unplugged
from navcore.clock import Clock, WallClock

if "hw.emulators" not in serial.protocol_handler_packages:
    serial.protocol_handler_packages.append("hw.emulators")

_registry: dict[str, Link] = {}
_lock = threading.Lock()


def plug(ident: str, emulator: Emulator, faults: Faults | None = None, seed: int = 0) -> Link:
    """Register ``emulator`` under ``ident`` (replacing any previous one) and return its Link."""
    link = Link(emulator, faults, seed)
    with _lock:
        _registry[ident] = link
    return link


def unplug(ident: str) -> None:
    """Forget the emulator registered under ``ident`` (if any)."""
    with _lock:
        _registry.pop(ident, None)


def unplug_all() -> None:
    """Forget every registered emulator (test teardown)."""
    with _lock:
        _registry.clear()


def lookup(ident: str) -> Link | None:
    with _lock:
        return _registry.get(ident)


_DEVICES = {  # URL device name -> (module, class)
    "urg04lx": ("urg04lx", "Urg04lxEmulator"),
    "kobuki": ("kobuki", "KobukiEmulator"),
    "lms200": ("lms2xx", "Lms200Emulator"),
    "lms291": ("lms2xx", "Lms291Emulator"),
    "arduino": ("arduino", "ArduinoBridgeEmulator"),
    "razor": ("razor", "RazorEmulator"),
    "vectornav": ("vectornav", "VectorNavEmulator"),
}


def emulator_types() -> dict[str, type]:
    """Device name in a ``sim://`` URL -> emulator class."""
    import importlib
    out: dict[str, type] = {}
    for name, (mod, cls) in _DEVICES.items():
        try:
            out[name] = getattr(importlib.import_module(f"hw.emulators.{mod}"), cls)
        except (ImportError, AttributeError):   # a device whose emulator is not built
            continue
    return out


_FAULT_KEYS = ("corrupt", "drop", "garbage", "delay", "host_corrupt", "host_drop")


def link_for_url(url: str, clock: Clock | None = None) -> Link:
    """The Link a ``sim://<device>?id=..&corrupt=..&seed=..`` URL names, created on first use.

    A registered id is reused (its device type must match); otherwise a fresh emulator with its
    default data source is created on a ``WallClock`` and registered under the id (default: the
    device name)."""
    parts = urlsplit(url)
    if parts.scheme != "sim":
        raise ValueError(f"{url}: not a sim:// URL")
    device = parts.netloc or parts.path.strip("/")
    q = {k: v[-1] for k, v in parse_qs(parts.query).items()}
    unknown = set(q) - set(_FAULT_KEYS) - {"id", "seed"}
    if unknown:
        raise ValueError(f"{url}: unknown option(s) {sorted(unknown)}; known: id, seed, "
                         f"{', '.join(_FAULT_KEYS)}")
    types = emulator_types()
    if device not in types:
        raise ValueError(f"{url}: unknown emulated device {device!r}; known: {sorted(types)}")
    ident = q.get("id", device)
    try:
        faults = {k: float(q[k]) for k in _FAULT_KEYS if k in q}
        seed = int(q.get("seed", 0))
    except ValueError as e:
        raise ValueError(f"{url}: bad option value: {e}") from None
    with _lock:
        link = _registry.get(ident)
        if link is None:
            link = Link(types[device](clock or WallClock()), Faults(**faults), seed)
            _registry[ident] = link
        elif not isinstance(link.emulator, types[device]):
            raise ValueError(f"{url}: id {ident!r} is a {link.emulator.device}, not a {device}")
        elif faults:
            for k, v in faults.items():
                setattr(link.faults, k, v)
    return link


__all__ = ["Emulator", "Faults", "Link", "Unplugged", "plug", "lookup", "unplug", "unplug_all",
           "link_for_url", "emulator_types"]
