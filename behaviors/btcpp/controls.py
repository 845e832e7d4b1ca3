"""AsyncSequence, AsyncFallback, ParallelAll, WhileDoElse, TryCatch, Switch2-Switch6
(BehaviorTree.CPP 4 controls)."""

from __future__ import annotations

from typing import ClassVar

from behaviors.base import (FAILURE, INVALID, RUNNING, SUCCESS, Control, Port, PortInformation,
                            Status, Ticking)


class _Async(Control):
    """Sequence/Fallback that yields after each child that moves it on: RUNNING, and the next
    child on the next tick (BT.CPP ``asynch`` flag)."""

    STOP_ON: ClassVar[Status]
    ALL_DONE: ClassVar[Status]
    INPUT_PORTS: dict[str, PortInformation]
    OUTPUT_PORTS: dict[str, PortInformation]

    def __init__(self, *args, **kwargs) -> None:  # noqa: D107
        super().__init__(*args, **kwargs)
        self._index = 0

    def tick_children(self) -> Ticking:
        if self.status is not RUNNING:
            self._index = 0
        child = self.children[self._index]
        self.current_child = child
        yield from child.tick()
        if child.status is RUNNING:
            return RUNNING
        if child.status is self.STOP_ON:
            self._index = 0
            return self.STOP_ON
        self._index += 1
        if self._index == len(self.children):
            self._index = 0
            return self.ALL_DONE
        return RUNNING


class AsyncSequence(_Async):
    """A Sequence that returns RUNNING after each child's SUCCESS and ticks the next child on
    the next tick, so a long list never takes one whole tick (BT.CPP ``AsyncSequence``)."""

    INPUT_PORTS: dict[str, PortInformation] = {}
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    STOP_ON, ALL_DONE = FAILURE, SUCCESS


class AsyncFallback(_Async):
    """A Fallback that returns RUNNING after each child's FAILURE and ticks the next child on
    the next tick (BT.CPP ``AsyncFallback``)."""

    INPUT_PORTS: dict[str, PortInformation] = {}
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    STOP_ON, ALL_DONE = SUCCESS, FAILURE


class ParallelAll(Control):
    """Tick every unfinished child each tick until all have finished; then FAILURE if at
    least ``max_failures`` failed, else SUCCESS (BT.CPP ``ParallelAll``)."""

    INPUT_PORTS = {"max_failures": Port(int, False, "failures that make it fail", 1, low=1)}
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def tick_children(self) -> Ticking:
        if self.status is not RUNNING:
            self._done: dict[int, Status] = {}
        for i, child in enumerate(self.children):
            if i in self._done:
                continue
            yield from child.tick()
            if child.status in (SUCCESS, FAILURE):
                self._done[i] = child.status
        if len(self._done) < len(self.children):
            return RUNNING
        failures = sum(1 for s in self._done.values() if s is FAILURE)
        self.say(f"{failures} of {len(self.children)} failed")
        return FAILURE if failures >= self.get_input("max_failures") else SUCCESS


class WhileDoElse(Control):
    """Each tick: the first child (condition); SUCCESS ticks the second (halting the third),
    FAILURE the third (halting the second), or FAILURE without a third; the branch's status
    is returned (BT.CPP ``WhileDoElse``, reactive unlike IfThenElse)."""

    INPUT_PORTS: dict[str, PortInformation] = {}
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    MIN_CHILDREN, MAX_CHILDREN = 2, 3

    def tick_children(self) -> Ticking:
        cond = self.children[0]
        yield from cond.tick()
        if cond.status is RUNNING:
            return RUNNING
        if cond.status is SUCCESS:
            if len(self.children) == 3:
                self.halt_children(2)
            branch = self.children[1]
        elif len(self.children) == 3:
            if self.children[1].status is RUNNING:
                self.children[1].stop(INVALID)
            branch = self.children[2]
        else:
            return FAILURE
        self.current_child = branch
        yield from branch.tick()
        return branch.status


class TryCatch(Control):
    """The children but the last run as a Sequence; if one fails, the last child (the catch)
    runs to completion and the node FAILs; SUCCESS when all the others succeed (BT.CPP
    ``TryCatch``)."""

    INPUT_PORTS = {"catch_on_halt": PortInformation(bool, False, "also tick the catch once "
                                                    "when halted while trying", False)}
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    MIN_CHILDREN = 2

    def tick_children(self) -> Ticking:
        if self.status is not RUNNING:
            self._index, self._catching = 0, False
        if not self._catching:
            while self._index < len(self.children) - 1:
                child = self.children[self._index]
                self.current_child = child
                yield from child.tick()
                if child.status is RUNNING:
                    return RUNNING
                if child.status is FAILURE:
                    self._catching = True
                    break
                self._index += 1
            if not self._catching:
                return SUCCESS
        catch = self.children[-1]
        self.current_child = catch
        yield from catch.tick()
        return RUNNING if catch.status is RUNNING else FAILURE

    def stop(self, new_status: Status = INVALID) -> None:
        if new_status is INVALID and self.status is RUNNING and not self._catching \
                and self.get_input("catch_on_halt"):
            self.halt_children()
            for _ in self.children[-1].tick():  # BT.CPP ticks the catch once on a halt
                pass
        super().stop(new_status)


class _Switch(Control):
    """Tick the child whose ``case_i`` equals ``variable`` (compared as text, or as numbers
    when both are numbers), the last child when none does; a different running child is
    halted first. Its status is returned. (BT.CPP ``SwitchN``: N cases + a default.)"""

    CASES: ClassVar[int]
    INPUT_PORTS: dict[str, PortInformation]
    OUTPUT_PORTS: dict[str, PortInformation]

    def tick_children(self) -> Ticking:
        variable = self.read("variable")
        match = self.CASES
        if variable is not None:
            for i in range(self.CASES):
                case = self.read(f"case_{i + 1}")
                if case is not None and _same(variable, case):
                    match = i
                    break
        for i, child in enumerate(self.children):
            if i != match and child.status is RUNNING:
                child.stop(INVALID)
        child = self.children[match]
        self.current_child = child
        yield from child.tick()
        return child.status


def _same(a: object, b: object) -> bool:
    if str(a) == str(b):
        return True
    try:
        return float(str(a)) == float(str(b))
    except ValueError:
        return False


def _switch_ports(n: int) -> dict[str, PortInformation]:
    ports = {"variable": PortInformation(object, True, "value to match, e.g. {mode}")}
    ports.update({f"case_{i}": PortInformation(object, False, f"value of case {i}")
                  for i in range(1, n + 1)})
    return ports


class Switch2(_Switch):
    """Tick one of 2 cases or the default (BT.CPP ``Switch2``)."""

    CASES, MIN_CHILDREN, MAX_CHILDREN = 2, 3, 3
    INPUT_PORTS, OUTPUT_PORTS = _switch_ports(2), {}


class Switch3(_Switch):
    """Tick one of 3 cases or the default (BT.CPP ``Switch3``)."""

    CASES, MIN_CHILDREN, MAX_CHILDREN = 3, 4, 4
    INPUT_PORTS, OUTPUT_PORTS = _switch_ports(3), {}


class Switch4(_Switch):
    """Tick one of 4 cases or the default (BT.CPP ``Switch4``)."""

    CASES, MIN_CHILDREN, MAX_CHILDREN = 4, 5, 5
    INPUT_PORTS, OUTPUT_PORTS = _switch_ports(4), {}


class Switch5(_Switch):
    """Tick one of 5 cases or the default (BT.CPP ``Switch5``)."""

    CASES, MIN_CHILDREN, MAX_CHILDREN = 5, 6, 6
    INPUT_PORTS, OUTPUT_PORTS = _switch_ports(5), {}


class Switch6(_Switch):
    """Tick one of 6 cases or the default (BT.CPP ``Switch6``)."""

    CASES, MIN_CHILDREN, MAX_CHILDREN = 6, 7, 7
    INPUT_PORTS, OUTPUT_PORTS = _switch_ports(6), {}
