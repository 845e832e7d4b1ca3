"""IfThenElse (BT.CPP)."""

from __future__ import annotations

from behaviors.base import FAILURE, RUNNING, SUCCESS, Control, PortInformation, Ticking


class IfThenElse(Control):
    """First child is the condition: SUCCESS runs the second child, FAILURE the third.

    With only two children a false condition gives FAILURE. The chosen branch keeps running
    until it finishes; its status is returned. (BT.CPP ``IfThenElse``; 2 or 3 children.)
    """

    INPUT_PORTS: dict[str, PortInformation] = {}
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    MIN_CHILDREN = 2
    MAX_CHILDREN = 3

    def __init__(self, *args, **kwargs) -> None:  # noqa: D107
        super().__init__(*args, **kwargs)
        self._branch = 0

    def tick(self) -> Ticking:
        if self.begin_tick():
            self._branch = 0
        if self._branch == 0:
            cond = self.children[0]
            yield from cond.tick()
            if cond.status is RUNNING:
                yield self.finish(RUNNING)
                return
            if cond.status is SUCCESS:
                self._branch = 1
            elif len(self.children) == 3:
                self._branch = 2
            else:
                yield self.finish(FAILURE)
                return
        branch = self.children[self._branch]
        self.current_child = branch
        yield from branch.tick()
        yield self.finish(branch.status)
