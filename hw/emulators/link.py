"""The wire between a driver and an emulated device, with fault injection.

``Emulator`` is a device state machine: ``receive(bytes)`` takes what the host wrote,
``advance(now)`` lets the device do what it does on its own (stream scans, send 50 Hz feedback),
and output accumulates in ``outbox``. ``Link`` wraps one emulator for a transport (the ``sim://``
pyserial handler or a pty pair) and injects faults into the device-to-host bytes: corrupted bytes,
dropped bytes, garbage bursts, slow replies, and unplug / replug.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass

import numpy as np

from navcore.clock import Clock
from hw.errors import HwError


class Emulator:
    """Base class of device emulators: time comes from the injected clock."""

    device = "generic"

    def __init__(self, clock: Clock) -> None:
        self.clock = clock
        self.outbox = bytearray()
        # the host's bit rate as the transport reports it; None when it cannot (a pty ignores it)
        self.baudrate: int | None = None

    def receive(self, data: bytes) -> None:
        """Bytes written by the host."""
        raise NotImplementedError

    def advance(self, now: float) -> None:
        """Produce whatever the device emits on its own up to time ``now``."""

    def power_cycle(self) -> None:
        """Unplug/replug resets the device to its power-on state (override to reset more)."""
        self.outbox.clear()

    def emit(self, data: bytes) -> None:
        self.outbox += data


@dataclass
class Faults:
    """Fault injection settings. Probabilities are per byte except ``garbage`` (per read)."""

    corrupt: float = 0.0      # flip a device->host byte to a random other value
    drop: float = 0.0         # lose a device->host byte
    garbage: float = 0.0      # insert a burst of random bytes
    delay: float = 0.0        # hold device->host bytes back this long (clock seconds)
    host_corrupt: float = 0.0  # flip a host->device byte
    host_drop: float = 0.0     # lose a host->device byte


class Unplugged(HwError, OSError):
    """The emulated device is not connected."""


class Link:
    """One emulated device on a wire, shared by a transport and by a test/simulator.

    Thread-safe: the transport calls ``write``/``read`` from the driver's thread while a test
    flips faults or unplugs from another."""

    def __init__(self, emulator: Emulator, faults: Faults | None = None, seed: int = 0) -> None:
        self.emulator = emulator
        self.faults = faults or Faults()
        self._rng = np.random.default_rng(seed)
        self._lock = threading.Lock()
        self._pending: list[tuple[float, bytes]] = []   # (release time, bytes) for slow replies
        self.plugged = True
        self.generation = 0      # bumps on every unplug, so an open port knows it is stale
        self.bytes_corrupted = 0
        self.bytes_dropped = 0

    @property
    def clock(self) -> Clock:
        return self.emulator.clock

    def unplug(self) -> None:
        with self._lock:
            self.plugged = False
            self.generation += 1
            self._pending.clear()
            self.emulator.power_cycle()

    def replug(self) -> None:
        with self._lock:
            self.plugged = True

    def set_baudrate(self, baud: int) -> None:
        with self._lock:
            self.emulator.baudrate = int(baud)

    def write(self, data: bytes) -> None:
        with self._lock:
            if not self.plugged:
                raise Unplugged("device unplugged")
            self.emulator.advance(self.clock.now())
            self.emulator.receive(self._mangle(bytes(data), self.faults.host_corrupt,
                                               self.faults.host_drop))

    def read(self, limit: int = 1 << 16) -> bytes:
        """Up to ``limit`` device->host bytes available now (possibly none)."""
        with self._lock:
            if not self.plugged:
                raise Unplugged("device unplugged")
            now = self.clock.now()
            self.emulator.advance(now)
            f = self.faults
            if self.emulator.outbox:
                out = bytes(self.emulator.outbox)
                self.emulator.outbox.clear()
                out = self._mangle(out, f.corrupt, f.drop)
                if f.garbage > 0 and self._rng.random() < f.garbage:
                    k = int(self._rng.integers(0, len(out) + 1))
                    junk = self._rng.integers(0, 256, int(self._rng.integers(1, 32)),
                                              dtype=np.uint8).tobytes()
                    out = out[:k] + junk + out[k:]
                self._pending.append((now + f.delay, out))
            ready = bytearray()
            while self._pending and self._pending[0][0] <= now and len(ready) < limit:
                ready += self._pending.pop(0)[1]
            if len(ready) > limit:
                self._pending.insert(0, (now, bytes(ready[limit:])))
                del ready[limit:]
            return bytes(ready)

    def _mangle(self, data: bytes, p_corrupt: float, p_drop: float) -> bytes:
        if not data or (p_corrupt <= 0 and p_drop <= 0):
            return data
        a = np.frombuffer(data, dtype=np.uint8).copy()
        if p_corrupt > 0:
            hit = self._rng.random(len(a)) < p_corrupt
            if hit.any():
                a[hit] ^= self._rng.integers(1, 256, int(hit.sum()), dtype=np.uint8)
                self.bytes_corrupted += int(hit.sum())
        if p_drop > 0:
            keep = self._rng.random(len(a)) >= p_drop
            self.bytes_dropped += int((~keep).sum())
            a = a[keep]
        return a.tobytes()
