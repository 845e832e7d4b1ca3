"""AsyncSequence and AsyncFallback (BehaviorTree.CPP 4 controls)."""

from __future__ import annotations

from typing import ClassVar

from behaviors.base import FAILURE, RUNNING, SUCCESS, Control, PortInformation, Status, Ticking


class _Async(Control):
    """Sequence/Fallback that yields after each child that moves it on: RUNNING, and the next
    child on the next tick (BT.CPP ``asynch`` flag)."""

    STOP_ON: ClassVar[Status]
    ALL_DONE: ClassVar[Status]
    INPUT_PORTS: dict[str, PortInformation]
    OUTPUT_PORTS: dict[str, PortInformation]

    def __init__(self, *args, **kwargs) -> None:  # noqa: D107
        super().__init__(*args, **kwargs)
        self._index = 0

    def tick(self) -> Ticking:
        if self.begin_tick():
            self._index = 0
        child = self.children[self._index]
        self.current_child = child
        yield from child.tick()
        if child.status is RUNNING:
            yield self.finish(RUNNING)
            return
        if child.status is self.STOP_ON:
            self._index = 0
            yield self.finish(self.STOP_ON)
            return
        self._index += 1
        if self._index == len(self.children):
            self._index = 0
            yield self.finish(self.ALL_DONE)
            return
        yield self.finish(RUNNING)


class AsyncSequence(_Async):
    """A Sequence that returns RUNNING after each child's SUCCESS and ticks the next child on
    the next tick, so a long list never takes one whole tick (BT.CPP ``AsyncSequence``)."""

    INPUT_PORTS: dict[str, PortInformation] = {}
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    STOP_ON, ALL_DONE = FAILURE, SUCCESS


class AsyncFallback(_Async):
    """A Fallback that returns RUNNING after each child's FAILURE and ticks the next child on
    the next tick (BT.CPP ``AsyncFallback``)."""

    INPUT_PORTS: dict[str, PortInformation] = {}
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    STOP_ON, ALL_DONE = SUCCESS, FAILURE
