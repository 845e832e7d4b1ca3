"""RunOnce (BehaviorTree.CPP 4 decorator)."""

from __future__ import annotations

from typing import Any

from behaviors.base import FAILURE, SUCCESS, DecoratorNode, PortInformation, Status, Ticking
from behaviors.btcpp.scripted import skipped_status


class RunOnce(DecoratorNode):
    """Tick the child until it finishes once; afterwards never again: SKIPPED with
    ``then_skip`` (navbt: what lets the parent move on), else the status it finished with.
    (BT.CPP ``RunOnce``; the memory lasts for the tree's life.)"""

    INPUT_PORTS = {"then_skip": PortInformation(bool, False, "skip after the first run, else "
                                                "repeat its result", True)}
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def __init__(self, *args: Any, **kwargs: Any) -> None:  # noqa: D107
        super().__init__(*args, **kwargs)
        self._done: Status | None = None

    def setup(self, **kwargs: Any) -> None:
        pass

    def tick(self) -> Ticking:
        self.begin_tick()
        if self._done is not None:
            yield self.finish(skipped_status(self) if self.get_input("then_skip") else self._done)
            return
        yield from self.decorated.tick()
        status = self.decorated.status
        if status in (SUCCESS, FAILURE):
            self._done = status
        yield self.finish(status)
