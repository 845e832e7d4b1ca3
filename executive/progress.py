"""A one-line progress display that stays quiet when the output is not a terminal (CI logs)."""

from __future__ import annotations

import math
import sys
from typing import Any, Sequence, TextIO

import numpy as np

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
        if self.due():
            self.show(text)

    def due(self) -> bool:
        """Count one update; True when this one is shown (every ``every``-th, on a terminal)."""
        self._n += 1
        return self.enabled and self._n % self.every == 0

    def show(self, text: str) -> None:
        """Rewrite the line with ``text`` now."""
        if not self.enabled:
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
    """An ``on_tick`` for ``Executive.run`` that shows progress against what is left: the goals
    still to reach and the length of the planned path from the robot to the current goal (the
    straight line before there is a path), with an ETA at the average speed so far and the
    speed-up over the wall clock, both labelled. Costs nothing when the Progress is quiet."""

    def __init__(self, progress: Progress, time_limit: float, label: str = "",
                 goals: Sequence[Any] | None = None, wall_clock: Any = None) -> None:
        self.progress = progress
        self.time_limit = time_limit
        self.label = label
        self.goals = [(float(g.x), float(g.y)) for g in goals or ()]
        self._wall = wall_clock if wall_clock is not None else WallClock()
        self._wall0: float | None = None
        self._t0: float | None = None
        self._index = 0
        self._goal: tuple[float, float] | None = None
        self._initial = 0.0
        self._last: tuple[float, float] | None = None
        self._driven = 0.0

    def __call__(self, ex: Any) -> None:
        if not self.progress.enabled:
            return
        t = ex.clock.now()
        p = ex.robot.pose()
        if self._t0 is None:
            self._t0, self._wall0 = t, self._wall.now()
        if self._last is not None:
            self._driven += math.hypot(p.x - self._last[0], p.y - self._last[1])
        self._last = (p.x, p.y)
        if not self.progress.due():
            return
        self.progress.show(self.text(ex, t, p))

    def text(self, ex: Any, t: float, p: Any) -> str:
        """The progress line for the executive's state now."""
        goal = ex.blackboard_get("goal")
        if goal is not None and (goal.x, goal.y) != self._goal:
            self._goal = (goal.x, goal.y)
            self._index = self._goal_index(self._goal)
            self._initial = 0.0
        left = remaining_path(ex.blackboard_get("path"), p, goal)
        self._initial = max(self._initial, left)
        n = max(1, len(self.goals))
        done_here = 1.0 - left / self._initial if self._initial > 1e-9 else 0.0
        fraction = (self._index + done_here) / n
        later = sum(math.dist(a, b) for a, b in zip(self.goals[self._index:],
                                                    self.goals[self._index + 1:]))
        elapsed = t - (self._t0 or 0.0)
        wall = max(self._wall.now() - (self._wall0 or 0.0), 1e-6)
        speedup = elapsed / wall
        speed = self._driven / elapsed if elapsed > 0 else 0.0
        if speed > 0.02:
            eta = (left + later) / speed
            eta_text = f"ETA {eta:.0f} s sim = {eta / max(speedup, 1e-6):.1f} s wall"
        else:
            eta_text = "ETA -"
        return (f"{self.label}{bar(fraction)} {100 * fraction:3.0f}% goal {self._index + 1}/{n}"
                f" {left + later:.1f} m left | {eta_text} | t={t:.1f} s sim, "
                f"x{speedup:.1f} real time | recoveries {len(ex.trace.recoveries)}")

    def _goal_index(self, goal: tuple[float, float]) -> int:
        for i in range(self._index, len(self.goals)):
            if math.dist(self.goals[i], goal) < 1e-6:
                return i
        return self._index


def remaining_path(path: Any, pose: Any, goal: Any) -> float:
    """Metres left along ``path`` from the point of it nearest ``pose`` (plus the step to it);
    the straight line to ``goal`` without a path (0 without either)."""
    poses = getattr(path, "poses", None)
    if poses is not None and len(poses) >= 2:
        xy = np.asarray(poses, dtype=np.float64)[:, :2]
        a, ab = xy[:-1], np.diff(xy, axis=0)
        seg = np.hypot(ab[:, 0], ab[:, 1])
        p = np.array([pose.x, pose.y])
        u = np.clip(((p - a) * ab).sum(axis=1) / np.maximum(seg * seg, 1e-18), 0.0, 1.0)
        proj = a + u[:, None] * ab
        d = np.hypot(proj[:, 0] - p[0], proj[:, 1] - p[1])
        k = int(np.argmin(d))
        return float(d[k] + (1.0 - u[k]) * seg[k] + seg[k + 1:].sum())
    if goal is not None:
        return math.hypot(goal.x - pose.x, goal.y - pose.y)
    return 0.0


def progress_callback(progress: Progress, time_limit: float, label: str = "",
                      goals: Sequence[Any] | None = None) -> TickProgress:
    """``TickProgress(progress, time_limit, label, goals)``."""
    return TickProgress(progress, time_limit, label, goals)
