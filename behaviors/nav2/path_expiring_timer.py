"""PathExpiringTimer (Nav2 condition)."""

from __future__ import annotations

from behaviors.base import FAILURE, SUCCESS, PortInformation, Status
from behaviors.conditions.condition import Condition
from navcore.types import Path


class PathExpiringTimer(Condition):
    """SUCCESS once ``seconds`` passed since the timer started, which restarts it; FAILURE
    before. A new ``path`` restarts the timer. The first tick of the node's life starts it and
    returns FAILURE (Nav2 ``PathExpiringTimer``: its memory outlives halts)."""

    INPUT_PORTS = {
        "seconds": PortInformation(float, False, "period, s", 1.0),
        "path": PortInformation(Path, False, "path whose change restarts the timer"),
    }
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    DEFAULT_KEYS = {"path": "path"}

    def __init__(self, *args, **kwargs) -> None:  # noqa: D107
        super().__init__(*args, **kwargs)
        self._first = True

    def update(self) -> Status:
        now, path = self.clock.now(), self.read("path")
        if self._first:
            self._first, self._path, self._start = False, path, now
            self._period = self.get_input("seconds")
            return FAILURE
        if path is not self._path:
            self._path, self._start = path, now
        if now - self._start < self._period:
            self.say("{:.1f} of {:.1f} s", now - self._start, self._period)
            return FAILURE
        self._start = now
        return SUCCESS

    def new_run(self) -> None:
        self._first = True
