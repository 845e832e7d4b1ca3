"""Helpers for running drivers against emulators in tests and demos."""

from __future__ import annotations

import threading
from typing import Callable

from serial.serialutil import Timeout

from navcore.clock import SimClock

_idle = threading.Event()   # never set: an interruptible wall-time wait


def wait_until(predicate: Callable[[], bool], timeout: float = 3.0,
               clock: SimClock | None = None, step: float = 0.01) -> bool:
    """Poll ``predicate`` until true or ``timeout`` wall seconds pass (driver threads run in wall
    time). With a SimClock, advance it by ``step`` per poll so timed emulators make progress."""
    deadline = Timeout(timeout)
    while not deadline.expired():
        if predicate():
            return True
        if clock is not None:
            clock.advance(step)
        _idle.wait(0.002)
    return predicate()
