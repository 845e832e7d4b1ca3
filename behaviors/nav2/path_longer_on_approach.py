"""PathLongerOnApproach (Nav2 decorator)."""

from __future__ import annotations

from typing import Any

import numpy as np

from behaviors.base import RUNNING, SUCCESS, DecoratorNode, PortInformation, Ticking
from navcore.types import Path


def _path_updated(new: Path | None, old: Path | None) -> bool:
    """Nav2's isPathUpdated: both non-empty, a different number of poses, same goal point."""
    return (old is not None and new is not None and len(old) > 0 and len(new) > 0
            and len(new) != len(old) and bool(np.array_equal(old.poses[-1, :2],
                                                             new.poses[-1, :2])))


class PathLongerOnApproach(DecoratorNode):
    """Tick the child only when, within ``prox_len`` m (path length) of the goal, a new
    ``path`` to the same goal is more than ``length_factor`` times longer than the previous
    one (someone stepped in the way near the goal: Nav2 then stops and waits). Otherwise
    SUCCESS without ticking it. While ticked: the child's RUNNING; its SUCCESS or FAILURE is
    returned and the new path becomes the reference. A new goal (last pose moved) is never a
    "longer path". (Nav2 ``PathLongerOnApproach``.)"""

    INPUT_PORTS = {
        "path": PortInformation(Path, True, "the planned path"),
        "prox_len": PortInformation(float, False, "path length to the goal that counts as "
                                    "approaching, m", 3.0),
        "length_factor": PortInformation(float, False, "how much longer a new path must be",
                                         2.0),
    }
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    DEFAULT_KEYS = {"path": "path"}

    def __init__(self, *args: Any, **kwargs: Any) -> None:  # noqa: D107
        super().__init__(*args, **kwargs)
        self._old: Path | None = None
        self._first = True

    def setup(self, **kwargs: Any) -> None:
        pass

    def tick(self) -> Ticking:
        self.begin_tick()
        new = self.read("path")
        old = self._old
        if not self._first and (old is None or len(old) == 0 or new is None or len(new) == 0
                                or not np.array_equal(old.poses[-1], new.poses[-1])):
            self._first = True  # a new goal: nothing to compare with yet
        if (_path_updated(new, old) and old.length() < self.get_input("prox_len")
                and new.length() > self.get_input("length_factor") * old.length()
                and not self._first):
            child = self.decorated
            yield from child.tick()
            if child.status is RUNNING:
                self.say("new path much longer near the goal: child running")
                yield self.finish(RUNNING)
                return
            self._old = new
            status = child.status
            self.halt_children()
            yield self.finish(status)
            return
        self._old = new
        self._first = False
        yield self.finish(SUCCESS)
