"""Helpers shared by the hw driver tests (no tests of their own here).

The emulator-registry fixture, a 20 Hz command loop, decoding a byte stream fed in pieces as a
serial port may deliver it, and collecting fresh samples from a driver.
"""

from __future__ import annotations

import threading
from typing import Any, Callable, Iterable

import pytest

import hw.emulators as emu
from hw.emulators.harness import wait_until
from navcore.clock import WallClock
from navcore.types import Twist


@pytest.fixture
def clean_registry():
    """Unplug every emulated device after the test; no reader or pty thread may outlive it."""
    yield
    emu.unplug_all()
    assert [t.name for t in threading.enumerate()
            if t.name.endswith("-reader") or t.name == "pty-device"] == []


def drive(drv: Any, cmd: Twist, seconds: float) -> None:
    """Keep commanding, like a 20 Hz control loop (wall time, for WallClock tests)."""
    clock = WallClock()
    end = clock.now() + seconds
    while clock.now() < end:
        drv.send(cmd)
        wait_until(lambda: False, 0.05)


def pieces(stream: bytes, cuts: Iterable[int] = ()) -> list[bytes]:
    """``stream`` cut at the sorted offsets ``cuts``."""
    cuts = list(cuts)
    return [stream[a:b] for a, b in zip([0, *cuts], [*cuts, len(stream)])]


def decode_valid(decoder: Any, parse: Callable[[Any], Any], error: type[Exception],
                 stream: bytes, cuts: Iterable[int] = ()) -> list:
    """Feed ``stream`` to ``decoder`` in pieces and ``parse`` every frame it yields, dropping the
    frames that ``parse`` rejects with ``error``: what a driver would deliver."""
    out = []
    for piece in pieces(stream, cuts):
        for frame in decoder.feed(piece):
            try:
                out.append(parse(frame))
            except error:
                pass
    return out


def collect_fresh(read: Callable[[], Any], n: int, timeout: float,
                  verify: Callable[[Any], None]) -> list:
    """Poll ``read()`` until ``n`` new samples (a new object each) arrived or ``timeout`` (wall
    seconds) passed; ``verify`` checks each new one. The samples seen, in order."""
    seen: list = []

    def more() -> bool:
        s = read()
        if s is not None and (not seen or s is not seen[-1]):
            verify(s)
            seen.append(s)
        return len(seen) >= n
    wait_until(more, timeout)
    return seen
