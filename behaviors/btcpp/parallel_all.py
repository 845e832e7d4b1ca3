"""ParallelAll (BehaviorTree.CPP 4 control)."""

from __future__ import annotations

from behaviors.base import (FAILURE, RUNNING, SUCCESS, Control, Port, PortInformation, Status,
                            Ticking)


class ParallelAll(Control):
    """Tick every unfinished child each tick until all have finished; then FAILURE if at
    least ``max_failures`` failed, else SUCCESS (BT.CPP ``ParallelAll``)."""

    INPUT_PORTS = {"max_failures": Port(int, False, "failures that make it fail", 1, low=1)}
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def tick(self) -> Ticking:
        if self.begin_tick():
            self._done: dict[int, Status] = {}
        for i, child in enumerate(self.children):
            if i in self._done:
                continue
            yield from child.tick()
            if child.status in (SUCCESS, FAILURE):
                self._done[i] = child.status
        if len(self._done) < len(self.children):
            yield self.finish(RUNNING)
            return
        failures = sum(1 for s in self._done.values() if s is FAILURE)
        self.say(f"{failures} of {len(self.children)} failed")
        yield self.finish(FAILURE if failures >= self.get_input("max_failures") else SUCCESS)
