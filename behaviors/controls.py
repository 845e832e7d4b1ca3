"""Control nodes with BehaviorTree.CPP / Nav2 semantics.

py_trees' ``Sequence(memory=...)``/``Selector`` cover only part of these, so each is written out
as a ``tick_now`` (see behaviors.base: plain calls, not py_trees' generators). Common rule
(BT.CPP): when a control node finishes (SUCCESS or FAILURE) or is halted, every child is halted,
so a later run starts all of them afresh.
"""

from __future__ import annotations

from typing import Any, ClassVar

import py_trees

from behaviors.base import (FAILURE, INVALID, RUNNING, SUCCESS, Control, PortInformation, Status,
                            tick_child)

Behaviour = py_trees.behaviour.Behaviour


class _InOrder(Control):
    """Children in order, resuming at the RUNNING child (shared by Sequence, Fallback and kin).

    A child that ends with ``STOP_ON`` ends the node with that status; any other final status
    moves on to the next child; ``ALL_DONE`` once every child has moved on. With ``MEMORY`` the
    position survives a ``STOP_ON`` ending, so the next run resumes at that child.
    (No ports declared: abstract, so it is not registered as a node.)
    """

    STOP_ON: ClassVar[Status]
    ALL_DONE: ClassVar[Status]
    MEMORY: ClassVar[bool] = False

    def __init__(self, *args, **kwargs) -> None:  # noqa: D107
        super().__init__(*args, **kwargs)
        self._index = 0

    def tick_now(self) -> None:
        if not self.MEMORY and self.status is not RUNNING:
            self._index = 0
        while self._index < len(self.children):
            child = self.children[self._index]
            self.current_child = child
            tick_child(child)
            if child.status is RUNNING:
                self._finish(RUNNING)
                return
            if child.status is self.STOP_ON:
                if not self.MEMORY:
                    self._index = 0
                self._finish(self.STOP_ON)
                return
            self._index += 1
        self._index = 0
        self._finish(self.ALL_DONE)


class _Reactive(Control):
    """Every child from the first on each tick (shared by ReactiveSequence and ReactiveFallback).

    A child RUNNING halts the later children and gives RUNNING; a child ending with ``STOP_ON``
    ends the node with that status; ``ALL_DONE`` when no child did either in this tick.
    (No ports declared: abstract, so it is not registered as a node.)
    """

    STOP_ON: ClassVar[Status]
    ALL_DONE: ClassVar[Status]

    def tick_now(self) -> None:
        for i, child in enumerate(self.children):
            self.current_child = child
            tick_child(child)
            if child.status is RUNNING:
                self.halt_children(i + 1)
                self._finish(RUNNING)
                return
            if child.status is self.STOP_ON:
                self._finish(self.STOP_ON)
                return
        self._finish(self.ALL_DONE)


class Sequence(_InOrder):
    """Tick children in order; resume at the RUNNING child on the next tick.

    A child's FAILURE fails the sequence (and the next run starts from the first child).
    SUCCESS once every child has succeeded. (BT.CPP ``Sequence``.)
    """

    INPUT_PORTS: dict[str, PortInformation] = {}
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    STOP_ON, ALL_DONE = FAILURE, SUCCESS


class SequenceWithMemory(_InOrder):
    """Like Sequence, but a failed child is ticked again (not the first child) on the next run.

    The memory is kept until the whole sequence succeeds. (BT.CPP ``SequenceWithMemory``.)
    """

    INPUT_PORTS: dict[str, PortInformation] = {}
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    STOP_ON, ALL_DONE = FAILURE, SUCCESS
    MEMORY = True


class ReactiveSequence(_Reactive):
    """Tick every child from the first on each tick (conditions are re-checked every tick).

    A child RUNNING: later children are halted, RUNNING. A child FAILURE: the running branch is
    halted, FAILURE. SUCCESS when all succeed in one tick. (BT.CPP ``ReactiveSequence``.)
    """

    INPUT_PORTS: dict[str, PortInformation] = {}
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    STOP_ON, ALL_DONE = FAILURE, SUCCESS


class Fallback(_InOrder):
    """Tick children in order until one does not fail; resume at the RUNNING child.

    SUCCESS at the first child that succeeds; FAILURE when all have failed. (BT.CPP ``Fallback``.)
    """

    INPUT_PORTS: dict[str, PortInformation] = {}
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    STOP_ON, ALL_DONE = SUCCESS, FAILURE


class ReactiveFallback(_Reactive):
    """Tick every child from the first on each tick; higher priorities preempt a running one.

    A child RUNNING: later children are halted, RUNNING. SUCCESS at the first success;
    FAILURE when all fail in one tick. (BT.CPP ``ReactiveFallback``.)
    """

    INPUT_PORTS: dict[str, PortInformation] = {}
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    STOP_ON, ALL_DONE = SUCCESS, FAILURE


class Parallel(Control):
    """Tick all unfinished children every tick (one thread, in order).

    SUCCESS when ``success_count`` children succeeded (-1: all), FAILURE when ``failure_count``
    failed (-1: all); either halts the rest. Otherwise RUNNING. (BT.CPP ``Parallel``.)
    """

    INPUT_PORTS = {
        "success_count": PortInformation(int, False, "children that must succeed; -1 = all", -1),
        "failure_count": PortInformation(int, False, "children failing to fail the node; -1 = all", 1),
    }
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def _threshold(self, port: str) -> int:
        n = self.get_input(port)
        return len(self.children) if n < 0 else min(n, len(self.children))

    def tick_now(self) -> None:
        if self.status is not RUNNING:
            self._done: dict[int, Status] = {}
        need_success, need_failure = self._threshold("success_count"), self._threshold("failure_count")
        for i, child in enumerate(self.children):
            if i in self._done:
                continue
            tick_child(child)
            if child.status is SUCCESS or child.status is FAILURE:
                self._done[i] = child.status
        successes = sum(1 for s in self._done.values() if s is SUCCESS)
        failures = len(self._done) - successes
        if successes >= need_success:
            self._finish(SUCCESS)
        elif failures >= need_failure or len(self._done) == len(self.children):
            self._finish(FAILURE)
        else:
            self._finish(RUNNING)


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

    def tick_now(self) -> None:
        if self.status is not RUNNING:
            self._last = 0
        for i, child in enumerate(self.children):
            self.current_child = child
            tick_child(child)
            if child.status is FAILURE:
                self._last = 0
                self._finish(FAILURE)
                return
            if child.status is RUNNING and i >= self._last:
                self._last = i
                self._finish(RUNNING)
                return
        self._last = 0
        self._finish(SUCCESS)


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
        "number_of_retries": PortInformation(int, False, "recoveries before giving up", 1),
        "reset_after": PortInformation(float, False,
                                       "s of RUNNING main child that reset the recoveries; "
                                       "0 = never (Nav2)", 0.0),
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
        if self._retries == 0 or self._clock is None:  # the usual tick: nothing to reset
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

    def tick_now(self) -> None:
        if self.status is not RUNNING:
            self._retries, self._index = 0, 0
        limit = self.get_input("number_of_retries")
        main, recovery = self.children
        while True:
            if self._index == 0:
                self.current_child = main
                tick_child(main)
                if main.status is RUNNING:
                    self._maybe_reset(recovery)
                    self._finish(RUNNING)
                    return
                if main.status is SUCCESS:
                    self._finish(SUCCESS)
                    return
                if self._retries >= limit:
                    self.say(f"main child failed after {self._retries} recoveries")
                    self._finish(FAILURE)
                    return
                main.stop(INVALID)
                self._index = 1
            else:
                self.current_child = recovery
                tick_child(recovery)
                if recovery.status is RUNNING:
                    self._finish(RUNNING)
                    return
                if recovery.status is FAILURE:
                    self.say(f"recovery {self._retries + 1} failed")
                    self._finish(FAILURE)
                    return
                recovery.stop(INVALID)
                self._retries += 1
                self._since = self._clock.now() if self._clock is not None else 0.0
                self.say(f"recovery {self._retries} of {limit} done, retrying")
                self._index = 0

    def terminate(self, new_status: Status) -> None:
        self._retries, self._index = 0, 0


class RoundRobin(Control):
    """Tick one child per attempt, moving on to the next child each time one finishes.

    A child SUCCESS: SUCCESS (the next run starts at the following child). FAILURE: the next
    child is tried in the same tick. FAILURE once every child has failed in a row, or, with
    ``wrap_around: false``, once the last child has been attempted (so a recovery list is tried
    at most once per navigation; the position then returns to the first child). Halting it
    while RUNNING resets the position; halting it after it finished does not.
    (Nav2 ``RoundRobin``, main branch.)
    """

    INPUT_PORTS = {
        "wrap_around": PortInformation(bool, False, "start again at the first child after the last",
                                       False),
    }
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def __init__(self, *args, **kwargs) -> None:  # noqa: D107
        super().__init__(*args, **kwargs)
        self._index = 0
        self._failed = 0

    def tick_now(self) -> None:
        n = len(self.children)
        wrap = self.get_input("wrap_around")
        if self._index >= n:  # the last child succeeded last time and there is no wrap
            self._index, self._failed = 0, 0
            self.say("every child attempted")
            self._finish(FAILURE)
            return
        while self._failed < n:
            child = self.children[self._index]
            self.current_child = child
            tick_child(child)
            if child.status is RUNNING:
                self._finish(RUNNING)
                return
            self._index += 1
            exhausted = self._index == n
            if exhausted and wrap:
                self._index = 0
            if child.status is SUCCESS:
                self._failed = 0
                self._finish(SUCCESS)
                return
            self._failed += 1
            if exhausted and not wrap:
                break
        self._failed = 0
        self._index = self._index % n if wrap else 0
        self.say("every child attempted")
        self._finish(FAILURE)

    def terminate(self, new_status: Status) -> None:
        # Interrupted while running (goal change, parent halted): forget the position.
        if new_status is INVALID and self.status is RUNNING:
            self._index, self._failed = 0, 0

    def new_run(self) -> None:
        """Start again at the first child: the tree is interrupted for a new goal."""
        self._index, self._failed = 0, 0


class IfThenElse(Control):
    """First child is the condition: SUCCESS runs the second child, FAILURE the third.

    With only two children a false condition gives FAILURE. The chosen branch keeps running
    until it finishes; its status is returned. (BT.CPP ``IfThenElse``; 2 or 3 children.)
    """

    INPUT_PORTS: dict[str, PortInformation] = {}
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    MIN_CHILDREN = 2
    MAX_CHILDREN = 3

    def __init__(self, *args, **kwargs) -> None:  # noqa: D107
        super().__init__(*args, **kwargs)
        self._branch = 0

    def tick_now(self) -> None:
        if self.status is not RUNNING:
            self._branch = 0
        if self._branch == 0:
            cond = self.children[0]
            tick_child(cond)
            if cond.status is RUNNING:
                self._finish(RUNNING)
                return
            if cond.status is SUCCESS:
                self._branch = 1
            elif len(self.children) == 3:
                self._branch = 2
            else:
                self._finish(FAILURE)
                return
        branch = self.children[self._branch]
        self.current_child = branch
        tick_child(branch)
        self._finish(branch.status)
