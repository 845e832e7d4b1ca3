"""Parallel (BT.CPP)."""

from __future__ import annotations

from behaviors.base import (FAILURE, RUNNING, SUCCESS, Control, Port, PortInformation,
                            Status, Ticking)


class Parallel(Control):
    """Tick all unfinished children every tick (one thread, in order).

    SUCCESS when ``success_count`` children succeeded (-1: all), FAILURE when ``failure_count``
    failed (-1: all); either halts the rest. Otherwise RUNNING. (BT.CPP ``Parallel``.)
    """

    INPUT_PORTS = {
        "success_count": Port(int, False, "children that must succeed; -1 = all", -1, low=-1),
        "failure_count": Port(int, False, "children failing to fail the node; -1 = all", 1, low=-1),
    }
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def _threshold(self, port: str) -> int:
        n = self.get_input(port)
        return len(self.children) if n < 0 else min(n, len(self.children))

    def tick(self) -> Ticking:
        if self.begin_tick():
            self._done: dict[int, Status] = {}
        need_success, need_failure = self._threshold("success_count"), self._threshold("failure_count")
        for i, child in enumerate(self.children):
            if i in self._done:
                continue
            yield from child.tick()
            if child.status is SUCCESS or child.status is FAILURE:
                self._done[i] = child.status
        successes = sum(1 for s in self._done.values() if s is SUCCESS)
        failures = len(self._done) - successes
        if successes >= need_success:
            yield self.finish(SUCCESS)
        elif failures >= need_failure or len(self._done) == len(self.children):
            yield self.finish(FAILURE)
        else:
            yield self.finish(RUNNING)
