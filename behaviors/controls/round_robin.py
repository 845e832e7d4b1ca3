"""RoundRobin (Nav2)."""

from __future__ import annotations

from typing import Any, Iterable

import py_trees

from behaviors.base import (FAILURE, INVALID, RUNNING, SUCCESS, Control, PortInformation, Status,
                            Ticking)


class RoundRobin(Control):
    """Tick one child per attempt, moving on to the next child each time one finishes.

    A child SUCCESS: SUCCESS (the next run starts at the following child). FAILURE: the next
    child is tried in the same tick. FAILURE once every child has failed in a row, or, with
    ``wrap_around: false``, once the last child has been attempted (so a recovery list is tried
    at most once per navigation; the position then returns to the first child). Halting it
    while RUNNING resets the position; halting it after it finished does not.
    (Nav2 ``RoundRobin``, main branch.) A tree that follows Nav2 main (``nav2_distro: main``)
    gets main's exact rule: without wrap, the last child's SUCCESS also gives FAILURE at once;
    before main the loader makes it always wrap (docs/trees.md).
    """

    INPUT_PORTS = {
        "wrap_around": PortInformation(bool, False, "start again at the first child after the last",
                                       False),
    }
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    USES_NAV2_DISTRO = True

    def __init__(self, name: str = "",
                 children: Iterable[py_trees.behaviour.Behaviour] | None = None,
                 nav2_distro: str | None = None, **kwargs: Any) -> None:
        """``nav2_distro``: the distribution the tree follows (None: navbt's own semantics)."""
        super().__init__(name, children, **kwargs)
        self.nav2_distro = nav2_distro
        self._index = 0
        self._failed = 0

    def tick(self) -> Ticking:
        self.begin_tick()
        n = len(self.children)
        wrap = self.get_input("wrap_around")
        if self._index >= n:  # the last child succeeded last time and there is no wrap
            self._index, self._failed = 0, 0
            self.say("every child attempted")
            yield self.finish(FAILURE)
            return
        while self._failed < n:
            child = self.children[self._index]
            self.current_child = child
            yield from child.tick()
            if child.status is RUNNING:
                yield self.finish(RUNNING)
                return
            self._index += 1
            exhausted = self._index == n
            if exhausted and wrap:
                self._index = 0
            if child.status is SUCCESS and exhausted and not wrap and \
                    self.nav2_distro == "main":
                break  # Nav2 main: the end of the list without wrap is FAILURE, even on success
            if child.status is SUCCESS:
                self._failed = 0
                yield self.finish(SUCCESS)
                return
            self._failed += 1
            if exhausted and not wrap:
                break
        self._failed = 0
        self._index = self._index % n if wrap else 0
        self.say("every child attempted")
        yield self.finish(FAILURE)

    def terminate(self, new_status: Status) -> None:
        # Interrupted while running (goal change, parent halted): forget the position.
        if new_status is INVALID and self.status is RUNNING:
            self._index, self._failed = 0, 0

    def new_run(self) -> None:
        """Start again at the first child: the tree is interrupted for a new goal."""
        self._index, self._failed = 0, 0
