"""WhileDoElse (BehaviorTree.CPP 4 control)."""

from __future__ import annotations

from behaviors.base import FAILURE, INVALID, RUNNING, SUCCESS, Control, PortInformation, Ticking


class WhileDoElse(Control):
    """Each tick: the first child (condition); SUCCESS ticks the second (halting the third),
    FAILURE the third (halting the second), or FAILURE without a third; the branch's status
    is returned (BT.CPP ``WhileDoElse``, reactive unlike IfThenElse)."""

    INPUT_PORTS: dict[str, PortInformation] = {}
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    MIN_CHILDREN, MAX_CHILDREN = 2, 3

    def tick(self) -> Ticking:
        self.begin_tick()
        cond = self.children[0]
        yield from cond.tick()
        if cond.status is RUNNING:
            yield self.finish(RUNNING)
            return
        if cond.status is SUCCESS:
            if len(self.children) == 3:
                self.halt_children(2)
            branch = self.children[1]
        elif len(self.children) == 3:
            if self.children[1].status is RUNNING:
                self.children[1].stop(INVALID)
            branch = self.children[2]
        else:
            yield self.finish(FAILURE)
            return
        self.current_child = branch
        yield from branch.tick()
        yield self.finish(branch.status)
