"""A one-line progress display that stays quiet when the output is not a terminal (CI logs)."""

from __future__ import annotations

import sys
from typing import Any, TextIO

from navcore.clock import WallClock


class Progress:
    """Rewrites one status line with ``\\r``; silent unless ``stream`` is a TTY (or forced)."""

    def __init__(self, stream: TextIO | None = None, enabled: bool | None = None,
                 every: int = 10) -> None:
        self.stream = stream if stream is not None else sys.stdout
        isatty = getattr(self.stream, "isatty", lambda: False)
        self.enabled = isatty() if enabled is None else enabled
        self.every = max(1, every)
        self._n = 0
        self._width = 0

    def update(self, text: str) -> None:
        self._n += 1
        if not self.enabled or self._n % self.every:
            return
        pad = max(0, self._width - len(text))
        self.stream.write("\r" + text + " " * pad)
        self.stream.flush()
        self._width = len(text) + pad  # what is on the line now, padding included

    def done(self) -> None:
        if self.enabled and self._width:
            self.stream.write("\r" + " " * self._width + "\r")
            self.stream.flush()
            self._width = 0


def bar(fraction: float, width: int = 20) -> str:
    fraction = min(1.0, max(0.0, fraction))
    full = int(round(fraction * width))
    return "[" + "#" * full + "." * (width - full) + "]"


class TickProgress:
    """An ``on_tick`` for ``Executive.run`` that updates a Progress line with simulated time,
    the speed-up over the wall clock, the pose and the recoveries so far."""

    def __init__(self, progress: Progress, time_limit: float, label: str = "") -> None:
        self.progress = progress
        self.time_limit = time_limit
        self.label = label
        self._wall = WallClock()

    def __call__(self, ex: Any) -> None:
        t = ex.clock.now()
        w = max(self._wall.now(), 1e-6)
        p = ex.robot.pose()
        self.progress.update(f"{self.label}{bar(t / self.time_limit)} t={t:6.1f}s x{t / w:5.1f} "
                             f"pose=({p.x:5.2f},{p.y:5.2f}) "
                             f"recoveries={len(ex.trace.recoveries)}")


def progress_callback(progress: Progress, time_limit: float, label: str = "") -> TickProgress:
    """``TickProgress(progress, time_limit, label)``."""
    return TickProgress(progress, time_limit, label)
