"""RateController (Nav2)."""

from __future__ import annotations

import math

from behaviors.base import INVALID, RUNNING, SUCCESS, Port, PortInformation, Ticking
from behaviors.decorators.timeout import Timed


class RateController(Timed):
    """Tick the child at most ``hz`` times per second (Nav2 ``RateController``).

    The child is ticked on the first tick of a run, whenever it is RUNNING, and when ``1/hz``
    seconds passed since its last success, and its status is returned. In between it is not
    ticked and the node returns RUNNING, as Nav2's does (every distribution); so in a
    PipelineSequence the later children keep running, and in a plain Sequence they wait.
    ``hz: 0`` ticks it once per run (move_base's ``planner_frequency: 0``).
    """

    INPUT_PORTS = {"hz": Port(float, False, "rate, Hz; 0 = once per run", 10.0, low=0.0)}
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def tick_children(self) -> Ticking:
        now = self.clock.now()
        hz = self.get_input("hz")
        if self.status is INVALID:
            self._last_ok = -math.inf
            self._last_status = INVALID
        due = hz > 0.0 and now - self._last_ok >= 1.0 / hz - 1e-9  # float sums of periods
        if (self._last_status is INVALID or self.decorated.status is RUNNING or due):
            yield from self.decorated.tick()
            self._last_status = self.decorated.status
            if self._last_status is SUCCESS:
                self._last_ok = now
            return self._last_status
        self.say("throttled: {:.2f} s to the next tick", self._last_ok + 1.0 / hz - now
                 if hz > 0.0 else math.inf)
        return RUNNING
