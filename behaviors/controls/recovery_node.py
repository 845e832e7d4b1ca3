"""RecoveryNode (Nav2)."""

from __future__ import annotations

from typing import Any

import py_trees

from behaviors.base import (FAILURE, INVALID, RUNNING, SUCCESS, Control, Port,
                            PortInformation, Status, Ticking)


Behaviour = py_trees.behaviour.Behaviour


class RecoveryNode(Control):
    """Run the first child; on its failure run the second (recovery) and try again, same tick.

    * first child SUCCESS: SUCCESS. RUNNING: RUNNING.
    * first child FAILURE: if fewer than ``number_of_retries`` recoveries ran, halt it and tick
      the recovery in the same tick; otherwise FAILURE.
    * recovery SUCCESS: count one retry and tick the first child again, same tick.
      RUNNING: RUNNING. FAILURE: FAILURE.
    Finishing or being halted resets the retry count. The main action thus gets up to
    ``number_of_retries + 1`` attempts. (Nav2 ``RecoveryNode``; exactly two children.)

    With ``reset_after`` > 0 (seconds, a navbt addition), a main child that has kept RUNNING
    that long since the last recovery counts as recovered: the retry count and the position of
    any RoundRobin inside the recovery start again (move_base and move_base_flex restart their
    recovery list once planning or control works again).
    """

    INPUT_PORTS = {
        "number_of_retries": Port(int, False, "recoveries before giving up", 1, low=0),
        "reset_after": Port(float, False,
                                       "s of RUNNING main child that reset the recoveries; "
                                       "0 = never (Nav2)", 0.0, low=0.0),
    }
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    MIN_CHILDREN = 2
    MAX_CHILDREN = 2

    def __init__(self, *args, **kwargs) -> None:  # noqa: D107
        super().__init__(*args, **kwargs)
        self._retries = 0
        self._index = 0
        self._clock = None
        self._since = 0.0

    def setup(self, **kwargs: Any) -> None:
        self._clock = kwargs.get("clock")

    def _maybe_reset(self, recovery: Behaviour) -> None:
        """The main child has been RUNNING ``reset_after`` s since the last recovery: start the
        recovery list again."""
        if self._retries == 0 or self._clock is None:
            return
        reset_after = self.get_input("reset_after")
        if reset_after <= 0.0:
            return
        if self._clock.now() - self._since >= reset_after - 1e-9:  # float sums of periods
            self._retries = 0
            for node in recovery.iterate():
                new_run = getattr(node, "new_run", None)
                if callable(new_run):
                    new_run()
            self.say("main child recovered: recoveries start again")

    def tick(self) -> Ticking:
        if self.begin_tick():
            self._retries, self._index = 0, 0
        limit = self.get_input("number_of_retries")
        main, recovery = self.children
        while True:
            if self._index == 0:
                self.current_child = main
                yield from main.tick()
                if main.status is RUNNING:
                    if self._retries:  # (else nothing to reset: the usual tick, no call)
                        self._maybe_reset(recovery)
                    yield self.finish(RUNNING)
                    return
                if main.status is SUCCESS:
                    yield self.finish(SUCCESS)
                    return
                if self._retries >= limit:
                    self.say(f"main child failed after {self._retries} recoveries")
                    yield self.finish(FAILURE)
                    return
                main.stop(INVALID)
                self._index = 1
            else:
                self.current_child = recovery
                yield from recovery.tick()
                if recovery.status is RUNNING:
                    yield self.finish(RUNNING)
                    return
                if recovery.status is FAILURE:
                    self.say(f"recovery {self._retries + 1} failed")
                    yield self.finish(FAILURE)
                    return
                recovery.stop(INVALID)
                self._retries += 1
                self._since = self._clock.now() if self._clock is not None else 0.0
                self.say(f"recovery {self._retries} of {limit} done, retrying")
                self._index = 0

    def terminate(self, new_status: Status) -> None:
        self._retries, self._index = 0, 0
