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

    def tick_children(self) -> Ticking:
        if self.status is not RUNNING:
            self._last = 0
        for i, child in enumerate(self.children):
            self.current_child = child
            yield from child.tick()
            if child.status is FAILURE:
                self._last = 0
                return FAILURE
            if child.status is RUNNING and i >= self._last:
                self._last = i
                return RUNNING
        self._last = 0
        return SUCCESS
