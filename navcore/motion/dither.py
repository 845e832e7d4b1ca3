"""Dithering: the robot keeps moving but gets no nearer to its goal, as a robot does that
swings between two gaps at a junction while each replan picks the other one.

move_base's oscillation check (IsOscillating) only sees a robot that stays within
``oscillation_distance`` of one spot; a robot swinging a metre between two gaps moves enough to
pass it and still never arrives. This check measures what matters: the distance still to go
(along the plan) has not improved on its best by ``min_progress`` for ``window`` seconds, while
the robot drove at least ``min_travel`` metres. Waiting in place (a person in the way) is not
dithering: the progress checker deals with a robot that does not move.
"""

from __future__ import annotations

import math


class DitherCheck:
    """Feed ``update(now, x, y, to_go)`` each cycle; ``dithering(...)`` says whether the robot
    drove ``min_travel`` m since ``to_go`` last improved by ``min_progress`` m, and that was at
    least ``window`` s ago."""

    def __init__(self) -> None:
        self.reset()

    def reset(self, now: float = -math.inf) -> None:
        """Start afresh (a new goal, after a break-out)."""
        self.best = math.inf          # the best distance to go so far, m
        self.since = now              # when it last improved, s
        self.travelled = 0.0          # m driven since then
        self._xy: tuple[float, float] | None = None

    def update(self, now: float, x: float, y: float, to_go: float, min_progress: float) -> None:
        if self._xy is not None:
            self.travelled += math.hypot(x - self._xy[0], y - self._xy[1])
        self._xy = (x, y)
        if to_go < self.best - min_progress or not math.isfinite(self.best):
            self.best, self.since, self.travelled = to_go, now, 0.0

    def dithering(self, now: float, window: float, min_travel: float) -> bool:
        return now - self.since >= window and self.travelled >= min_travel
