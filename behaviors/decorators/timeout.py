"""Timeout and Delay (BT.CPP), in the injected clock's time."""

from __future__ import annotations

from typing import Any

from behaviors.base import FAILURE, RUNNING, DecoratorNode, Port, PortInformation, Ticking


class Timed(DecoratorNode):
    """A decorator that needs the clock."""

    INPUT_PORTS: dict[str, PortInformation]
    OUTPUT_PORTS: dict[str, PortInformation]

    def setup(self, **kwargs: Any) -> None:
        self.clock = self.component(kwargs, "clock")


class Timeout(Timed):
    """FAILURE (child halted) if the child is still RUNNING ``msec`` milliseconds after it started.

    Otherwise the child's status. The clock starts on the first tick of a run.
    """

    INPUT_PORTS = {"msec": Port(int, True, "time allowed, ms", low=0)}
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def tick(self) -> Ticking:
        self.begin_tick()
        now = self.clock.now()
        if self.status is not RUNNING:
            self._deadline = now + self.get_input("msec") / 1000.0
        if now >= self._deadline:
            self.say("timed out")
            yield self.finish(FAILURE)
            return
        yield from self.decorated.tick()
        yield self.finish(self.decorated.status)


class Delay(Timed):
    """RUNNING for ``delay_msec`` milliseconds, then tick the child and return its status."""

    INPUT_PORTS = {"delay_msec": Port(int, True, "delay before the child runs, ms", low=0)}
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def tick(self) -> Ticking:
        self.begin_tick()
        now = self.clock.now()
        if self.status is not RUNNING:
            self._start_at = now + self.get_input("delay_msec") / 1000.0
        if now < self._start_at:
            self.say("waiting {:.2f} s", self._start_at - now)
            yield self.finish(RUNNING)
            return
        yield from self.decorated.tick()
        yield self.finish(self.decorated.status)
