"""The one source of time. Nothing in navbt reads the system clock except ``WallClock``.

A ``SimClock`` jumps when told to, which makes scenario runs deterministic and faster than real
time; a ``WallClock`` follows the monotonic system clock and really sleeps.
"""

from __future__ import annotations

import time
from typing import Protocol


class Clock(Protocol):
    """What every time-dependent component is handed."""

    def now(self) -> float:
        """Seconds since the clock's epoch."""
        ...

    def sleep_until(self, t: float) -> None:
        """Return once ``now() >= t``: a simulated clock jumps, a wall clock sleeps."""
        ...


class SimClock:
    """Simulated time that only moves when advanced. Never goes backwards."""

    def __init__(self, start: float = 0.0) -> None:
        self._t = float(start)

    def now(self) -> float:
        return self._t

    def advance(self, dt: float) -> float:
        if dt < 0:
            raise ValueError(f"SimClock.advance: dt must be >= 0, got {dt}")
        self._t += dt
        return self._t

    def sleep_until(self, t: float) -> None:
        if t > self._t:
            self._t = float(t)


class WallClock:
    """Monotonic wall time, measured from construction."""

    def __init__(self) -> None:
        self._t0 = time.monotonic()

    def now(self) -> float:
        return time.monotonic() - self._t0

    def sleep_until(self, t: float) -> None:
        delay = t - self.now()
        if delay > 0:
            time.sleep(delay)
