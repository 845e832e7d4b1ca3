"""BehaviorTree.CPP 4's pre- and post-condition attributes, which any node may carry:
``_failureIf``, ``_successIf``, ``_skipIf``, ``_while`` (checked before a run starts; ``_while``
also while it runs) and ``_onSuccess``, ``_onFailure``, ``_post``, ``_onHalted`` (scripts run
after). The loader wraps such a node in ``PrePostConditions``; nothing else changes."""

from __future__ import annotations

from typing import Iterator

import py_trees

from behaviors.base import FAILURE, INVALID, RUNNING, SUCCESS, Status
from behaviors.btcpp.scripted import STORAGE, skipped_status
from behaviors.btcpp.scripting import Program

PRE = ("_failureIf", "_successIf", "_skipIf", "_while")
POST = ("_onSuccess", "_onFailure", "_post", "_onHalted")
ATTRIBUTES = PRE + POST


class PrePostConditions(py_trees.decorators.Decorator):
    """Runs the node's condition scripts around it, as BT.CPP does in ``executeTick``:

    * before a run starts, in this order: ``_failureIf`` true: FAILURE; ``_successIf`` true:
      SUCCESS; ``_skipIf`` true or ``_while`` false: skipped; the node is not ticked;
    * while it runs, ``_while`` false halts it and it is skipped;
    * after it finishes: ``_onSuccess`` or ``_onFailure``, then ``_post``; ``_onHalted`` when
      it is halted while running.

    navbt has py_trees' four statuses: "skipped" is SUCCESS under a Sequence-like parent and
    FAILURE under a Fallback-like one, so that the parent moves on as in BT.CPP.
    """

    def __init__(self, child: py_trees.behaviour.Behaviour, scripts: dict[str, Program]) -> None:
        super().__init__(name=child.name, child=child)
        self.scripts = scripts

    def _true(self, attr: str) -> bool | None:
        program = self.scripts.get(attr)
        return None if program is None else program.true(STORAGE)

    def update(self) -> Status:  # py_trees declares it abstract; tick decides
        return self.decorated.status

    def tick(self) -> Iterator[py_trees.behaviour.Behaviour]:
        child = self.decorated
        outcome: Status | None = None
        if child.status is not RUNNING:
            if self._true("_failureIf"):
                outcome = FAILURE
            elif self._true("_successIf"):
                outcome = SUCCESS
            elif self._true("_skipIf") or self._true("_while") is False:
                outcome = skipped_status(self)
        elif self._true("_while") is False:
            self._halt_child()
            outcome = skipped_status(self)
        if outcome is None:
            yield from child.tick()
            outcome = child.status
            if outcome in (SUCCESS, FAILURE):
                after = self.scripts.get("_onSuccess" if outcome is SUCCESS else "_onFailure")
                if after is not None:
                    after.run(STORAGE)
                if "_post" in self.scripts:
                    self.scripts["_post"].run(STORAGE)
        self.status = outcome
        yield self

    def _halt_child(self) -> None:
        """Halt the running node and run its ``_onHalted`` (BT.CPP's haltNode)."""
        self.decorated.stop(INVALID)
        if "_onHalted" in self.scripts:
            self.scripts["_onHalted"].run(STORAGE)

    def stop(self, new_status: Status = INVALID) -> None:
        if new_status is INVALID and self.decorated.status is RUNNING:
            self._halt_child()
        self.status = new_status
