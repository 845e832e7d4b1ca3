"""Switch2 ... Switch6 (BehaviorTree.CPP 4 controls)."""

from __future__ import annotations

from typing import ClassVar

from behaviors.base import INVALID, RUNNING, Control, PortInformation, Ticking


class _Switch(Control):
    """Tick the child whose ``case_i`` equals ``variable`` (compared as text, or as numbers
    when both are numbers), the last child when none does; a different running child is
    halted first. Its status is returned. (BT.CPP ``SwitchN``: N cases + a default.)"""

    CASES: ClassVar[int]
    INPUT_PORTS: dict[str, PortInformation]
    OUTPUT_PORTS: dict[str, PortInformation]

    def tick(self) -> Ticking:
        self.begin_tick()
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
        yield self.finish(child.status)


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
