"""IsDithering: moving without getting nearer to the goal; optionally commit for a while."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from behaviors.base import FAILURE, SUCCESS, Port, PortInformation, Status
from behaviors.conditions.condition import Condition
from navcore.motion.dither import DitherCheck
from navcore.motion.path_progress import length_to_go, remaining_length
from navcore.types import Path, Pose2D


class IsDithering(Condition):
    """SUCCESS when the robot has driven ``min_travel`` metres since the length of ``path`` left
    from it (its distance to go) last improved by ``min_progress`` metres, at least ``window``
    seconds ago: it swings between two ways (two gaps at a junction) and arrives nowhere. It
    then stays SUCCESS for ``commit_time`` seconds (0: one tick), so that a tree can commit to
    one way meanwhile. ``dithering`` holds the verdict of the last tick (a tree that fails
    navigation on it reads there why). The check restarts when ``goal`` changes and after each
    detection. FAILURE otherwise, and without a path.
    (move_base's oscillation check, IsOscillating, misses a robot that swings farther than
    ``oscillation_distance``.)"""

    INPUT_PORTS = {
        "path": PortInformation(Path, True, "the plan being followed"),
        "goal": PortInformation(Pose2D, False, "the check restarts when this changes"),
        "window": Port(float, False, "s without progress", 10.0, low=0.0),
        "min_travel": Port(float, False, "m driven meanwhile", 1.0, low=0.0),
        "min_progress": Port(float, False, "m the distance to go must improve by", 0.5,
                             low=0.0),
        "commit_time": Port(float, False, "s the SUCCESS lasts after a detection", 0.0,
                            low=0.0),
    }
    OUTPUT_PORTS = {"dithering": PortInformation(bool, False, "the verdict of the last tick, "
                                                 "for a recovery branch to read")}
    DEFAULT_KEYS = {"path": "path", "goal": "goal", "dithering": "dithering"}

    def setup(self, **kwargs: Any) -> None:
        super().setup(**kwargs)
        self._check = DitherCheck()
        self._goal: Pose2D | None = None
        self._until = -math.inf
        self._path: Path | None = None
        self._to_go: np.ndarray | None = None

    def update(self) -> Status:
        now, goal = self.clock.now(), self.read("goal")
        if goal is not self._goal and goal != self._goal:  # (the same object: no dataclass ==)
            self._goal, self._until = goal, -math.inf
            self._check.reset(now)
        if now < self._until:
            return self._verdict(True)
        path = self.read("path")
        if path is None or len(path) < 2:
            return self._verdict(False)
        if path is not self._path:  # a new plan: sum its lengths once
            self._path, self._to_go = path, length_to_go(path.poses)
        pose = self.pose()
        self._check.update(now, pose.x, pose.y, remaining_length(path, pose, self._to_go),
                           self.get_input("min_progress"))
        if not self._check.dithering(now, self.get_input("window"), self.get_input("min_travel")):
            return self._verdict(False)
        self.say(f"dithering: {self._check.travelled:.2f} m driven in "
                 f"{now - self._check.since:.1f} s, no nearer than {self._check.best:.2f} m")
        self._until = now + self.get_input("commit_time")
        self._check.reset(now)
        return self._verdict(True)

    def _verdict(self, dithering: bool) -> Status:
        self.write("dithering", dithering)
        return SUCCESS if dithering else FAILURE
