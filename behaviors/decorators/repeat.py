"""RetryUntilSuccessful and Repeat (BT.CPP)."""

from __future__ import annotations

from typing import ClassVar

from behaviors.base import (FAILURE, INVALID, RUNNING, SUCCESS, DecoratorNode, Port,
                            PortInformation, Status, Ticking)


class Rerun(DecoratorNode):
    """Run the child again each time it ends with ``RERUN_ON``, until it has done so
    ``LIMIT_PORT`` times in all (-1: forever); RUNNING in between, so the rerun starts on the next
    tick. Any other final status passes through. (Shared by RetryUntilSuccessful and Repeat.)
    """

    RERUN_ON: ClassVar[Status]
    LIMIT_PORT: ClassVar[str]
    FEEDBACK: ClassVar[str]  # said at each counted run: {n} runs so far, {limit}

    def tick(self) -> Ticking:
        if self.begin_tick():
            self._count = 0
        yield from self.decorated.tick()
        status = self.decorated.status
        if status is self.RERUN_ON:
            self._count += 1
            limit = self.get_input(self.LIMIT_PORT)
            self.say(self.FEEDBACK.format(n=self._count, limit=limit))
            if limit < 0 or self._count < limit:
                self.decorated.stop(INVALID)
                status = RUNNING
        yield self.finish(status)


class RetryUntilSuccessful(Rerun):
    """Run the child again after a failure, up to ``num_attempts`` attempts in all (-1: forever).

    SUCCESS as soon as the child succeeds; FAILURE after the last failed attempt. Unlike BT.CPP,
    a failed attempt is retried on the *next* tick (RUNNING in between), so a synchronous child
    that keeps failing cannot stall the control loop.
    """

    INPUT_PORTS = {"num_attempts": Port(int, False, "attempts in all; -1 = forever", 1, low=-1)}
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    RERUN_ON, LIMIT_PORT = FAILURE, "num_attempts"
    FEEDBACK = "attempt {n} of {limit} failed"


class Repeat(Rerun):
    """Run the child ``num_cycles`` times in a row (-1: forever), one run per tick at most.

    RUNNING between runs; FAILURE as soon as a run fails; SUCCESS after the last success.
    """

    INPUT_PORTS = {"num_cycles": Port(int, False, "successful runs; -1 = forever", 1, low=-1)}
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    RERUN_ON, LIMIT_PORT = SUCCESS, "num_cycles"
    FEEDBACK = "cycle {n} of {limit} done"
