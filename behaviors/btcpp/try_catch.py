"""TryCatch (BehaviorTree.CPP 4 control)."""

from __future__ import annotations

from behaviors.base import (FAILURE, INVALID, RUNNING, SUCCESS, Control, PortInformation, Status,
                            Ticking)


class TryCatch(Control):
    """The children but the last run as a Sequence; if one fails, the last child (the catch)
    runs to completion and the node FAILs; SUCCESS when all the others succeed (BT.CPP
    ``TryCatch``)."""

    INPUT_PORTS = {"catch_on_halt": PortInformation(bool, False, "also tick the catch once "
                                                    "when halted while trying", False)}
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    MIN_CHILDREN = 2

    def tick(self) -> Ticking:
        if self.begin_tick():
            self._index, self._catching = 0, False
        if not self._catching:
            while self._index < len(self.children) - 1:
                child = self.children[self._index]
                self.current_child = child
                yield from child.tick()
                if child.status is RUNNING:
                    yield self.finish(RUNNING)
                    return
                if child.status is FAILURE:
                    self._catching = True
                    break
                self._index += 1
            if not self._catching:
                yield self.finish(SUCCESS)
                return
        catch = self.children[-1]
        self.current_child = catch
        yield from catch.tick()
        yield self.finish(RUNNING if catch.status is RUNNING else FAILURE)

    def stop(self, new_status: Status = INVALID) -> None:
        if new_status is INVALID and self.status is RUNNING and not self._catching \
                and self.get_input("catch_on_halt"):
            self.halt_children()
            for _ in self.children[-1].tick():  # BT.CPP ticks the catch once on a halt
                pass
        super().stop(new_status)
