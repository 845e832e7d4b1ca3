"""The shape of Nav2's throttling decorators (RateController, DistanceController,
SpeedController, GoalUpdatedController): tick the child only now and then."""

from __future__ import annotations

from typing import ClassVar

from behaviors.base import INVALID, RUNNING, SUCCESS, DecoratorNode, Status, Ticking


class Throttle(DecoratorNode):
    """Tick the child on the first tick of a run, while it is RUNNING, and when ``due()``;
    otherwise return ``throttled()``: RUNNING, as Nav2's RateController, DistanceController,
    SpeedController and GoalUpdatedController do (they return their own status, set to
    RUNNING, without ticking the child). Subclasses say when it is due, what a new run resets (``start_run``) and what
    a success of the child restarts (``child_succeeded``). With ``RESTART_WHEN_DUE`` a child
    still RUNNING when it falls due is halted and started again."""

    RESTART_WHEN_DUE: ClassVar[bool] = False

    def start_run(self) -> None:
        """A new run of this node (it was INVALID)."""

    def due(self) -> bool:
        """Whether the child is due this tick (called once per tick)."""
        raise NotImplementedError(f"{type(self).__name__}: no due()")

    def child_succeeded(self) -> None:
        """The child just succeeded."""

    def throttled(self) -> Status:
        """This node's status on a tick that does not tick the child."""
        return RUNNING

    def tick(self) -> Ticking:
        self.begin_tick()
        if self.status is INVALID:
            self._last_status = INVALID
            self.start_run()
        due = self.due()
        child = self.decorated
        if self._last_status is INVALID or child.status is RUNNING or due:
            if due and self.RESTART_WHEN_DUE and child.status is RUNNING:
                self.halt_children()
            yield from child.tick()
            self._last_status = child.status
            if self._last_status is SUCCESS:
                self.child_succeeded()
            yield self.finish(self._last_status)
            return
        yield self.finish(self.throttled())

