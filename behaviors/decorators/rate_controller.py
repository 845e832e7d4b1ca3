"""RateController (Nav2)."""

from __future__ import annotations

import math

from behaviors.base import RUNNING, Port, PortInformation, Status
from behaviors.decorators.throttle import Throttle
from behaviors.decorators.timeout import Timed


class RateController(Throttle, Timed):
    """Tick the child at most ``hz`` times per second (Nav2 ``RateController``).

    The child is ticked on the first tick of a run, whenever it is RUNNING, and when ``1/hz``
    seconds passed since its last success, and its status is returned. In between it is not
    ticked and the node returns RUNNING, as Nav2's does (every distribution); so in a
    PipelineSequence the later children keep running, and in a plain Sequence they wait.
    ``hz: 0`` ticks it once per run (move_base's ``planner_frequency: 0``).
    """

    INPUT_PORTS = {"hz": Port(float, False, "rate, Hz; 0 = once per run", 10.0, low=0.0)}
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def start_run(self) -> None:
        self._last_ok = -math.inf

    def due(self) -> bool:
        self._now, self._hz = self.clock.now(), self.get_input("hz")
        return self._hz > 0.0 and self._now - self._last_ok >= 1.0 / self._hz - 1e-9  # float sums

    def child_succeeded(self) -> None:
        self._last_ok = self._now

    def throttled(self) -> Status:
        hz = self._hz
        self.say("throttled: {:.2f} s to the next tick", self._last_ok + 1.0 / hz - self._now
                 if hz > 0.0 else math.inf)
        return RUNNING
