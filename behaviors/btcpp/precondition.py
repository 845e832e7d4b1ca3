"""Precondition (BehaviorTree.CPP 4 decorator)."""

from __future__ import annotations

from behaviors.base import RUNNING, DecoratorNode, PortInformation, Ticking
from behaviors.btcpp.scripted import STATUS_NAMES, STORAGE, Scripted, skipped_status


class Precondition(Scripted, DecoratorNode):
    """Tick the child only if ``if`` (a script expression) is true when a run starts; else
    return ``else`` (SUCCESS, FAILURE, RUNNING or SKIPPED) without ticking it. Once the child
    runs, it is ticked until it finishes without checking again. (BT.CPP ``Precondition``.)"""

    INPUT_PORTS = {
        "if": PortInformation(str, True, "condition, a script expression"),
        "else": PortInformation(str, False, "status when false: SUCCESS, FAILURE, RUNNING or "
                                "SKIPPED", "FAILURE"),
    }
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    SCRIPT_PORTS = ("if",)
    CHOICES = {"else": tuple(STATUS_NAMES)}

    def tick(self) -> Ticking:
        self.begin_tick()
        child = self.decorated
        if child.status is not RUNNING:
            program = self.program("if")
            if program is None or not program.true(STORAGE):
                status = STATUS_NAMES[self.get_input("else")]
                yield self.finish(skipped_status(self) if status is None else status)
                return
        yield from child.tick()
        yield self.finish(child.status)
