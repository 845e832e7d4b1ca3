"""The two shapes of the Sequence/Fallback family: in order (resuming) and reactive."""

from __future__ import annotations

from typing import ClassVar

from behaviors.base import RUNNING, Control, Status, Ticking


class InOrder(Control):
    """Children in order, resuming at the RUNNING child (shared by Sequence, Fallback and kin).

    A child that ends with ``STOP_ON`` ends the node with that status; any other final status
    moves on to the next child; ``ALL_DONE`` once every child has moved on. With ``MEMORY`` the
    position survives a ``STOP_ON`` ending, so the next run resumes at that child.
    (No ports declared: abstract, so it is not registered as a node.)
    """

    STOP_ON: ClassVar[Status]
    ALL_DONE: ClassVar[Status]
    MEMORY: ClassVar[bool] = False

    def __init__(self, *args, **kwargs) -> None:  # noqa: D107
        super().__init__(*args, **kwargs)
        self._index = 0

    def tick(self) -> Ticking:
        self.begin_tick()
        if not self.MEMORY and self.status is not RUNNING:
            self._index = 0
        while self._index < len(self.children):
            child = self.children[self._index]
            self.current_child = child
            yield from child.tick()
            if child.status is RUNNING:
                yield self.finish(RUNNING)
                return
            if child.status is self.STOP_ON:
                if not self.MEMORY:
                    self._index = 0
                yield self.finish(self.STOP_ON)
                return
            self._index += 1
        self._index = 0
        yield self.finish(self.ALL_DONE)


class Reactive(Control):
    """Every child from the first on each tick (shared by ReactiveSequence and ReactiveFallback).

    A child RUNNING halts the later children and gives RUNNING; a child ending with ``STOP_ON``
    ends the node with that status; ``ALL_DONE`` when no child did either in this tick.
    (No ports declared: abstract, so it is not registered as a node.)
    """

    STOP_ON: ClassVar[Status]
    ALL_DONE: ClassVar[Status]

    def tick(self) -> Ticking:
        self.begin_tick()
        for i, child in enumerate(self.children):
            self.current_child = child
            yield from child.tick()
            if child.status is RUNNING:
                self.halt_children(i + 1)
                yield self.finish(RUNNING)
                return
            if child.status is self.STOP_ON:
                yield self.finish(self.STOP_ON)
                return
        yield self.finish(self.ALL_DONE)
