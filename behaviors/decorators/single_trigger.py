"""SingleTrigger (Nav2)."""

from __future__ import annotations

from behaviors.base import FAILURE, INVALID, RUNNING, DecoratorNode, PortInformation, Ticking


class SingleTrigger(DecoratorNode):
    """Run the child once per activation; afterwards FAILURE until the parent resets this node.

    (Nav2 ``SingleTrigger``: e.g. one Spin per navigation attempt.)
    """

    INPUT_PORTS: dict[str, PortInformation] = {}
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def tick(self) -> Ticking:
        self.begin_tick()
        if self.status is INVALID:
            self._fired = False
        if self._fired and self.decorated.status is not RUNNING:
            yield self.finish(FAILURE)
            return
        yield from self.decorated.tick()
        if self.decorated.status is not RUNNING:
            self._fired = True
        yield self.finish(self.decorated.status)
