"""PipelineSequence (Nav2)."""

from __future__ import annotations

from behaviors.base import FAILURE, RUNNING, SUCCESS, Control, PortInformation, Ticking


class PipelineSequence(Control):
    """Re-tick every earlier child each tick while a later one runs (Nav2 ``PipelineSequence``).

    So ``RateController(ComputePathToPose)`` keeps replanning while ``FollowPath`` runs. Any child
    FAILURE halts all and fails; SUCCESS when the last child succeeds.
    """

    INPUT_PORTS: dict[str, PortInformation] = {}
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def __init__(self, *args, **kwargs) -> None:  # noqa: D107
        super().__init__(*args, **kwargs)
        self._last = 0

    def tick(self) -> Ticking:
        if self.begin_tick():
            self._last = 0
        for i, child in enumerate(self.children):
            self.current_child = child
            yield from child.tick()
            if child.status is FAILURE:
                self._last = 0
                yield self.finish(FAILURE)
                return
            if child.status is RUNNING and i >= self._last:
                self._last = i
                yield self.finish(RUNNING)
                return
        self._last = 0
        yield self.finish(SUCCESS)
