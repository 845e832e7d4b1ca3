"""Sequence, SequenceWithMemory and ReactiveSequence (BT.CPP)."""

from __future__ import annotations

from behaviors.base import FAILURE, SUCCESS, PortInformation
from behaviors.controls.ordered import InOrder, Reactive


class Sequence(InOrder):
    """Tick children in order; resume at the RUNNING child on the next tick.

    A child's FAILURE fails the sequence (and the next run starts from the first child).
    SUCCESS once every child has succeeded. (BT.CPP ``Sequence``.)
    """

    INPUT_PORTS: dict[str, PortInformation] = {}
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    STOP_ON, ALL_DONE = FAILURE, SUCCESS


class SequenceWithMemory(InOrder):
    """Like Sequence, but a failed child is ticked again (not the first child) on the next run.

    The memory is kept until the whole sequence succeeds. (BT.CPP ``SequenceWithMemory``.)
    """

    INPUT_PORTS: dict[str, PortInformation] = {}
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    STOP_ON, ALL_DONE = FAILURE, SUCCESS
    MEMORY = True


class ReactiveSequence(Reactive):
    """Tick every child from the first on each tick (conditions are re-checked every tick).

    A child RUNNING: later children are halted, RUNNING. A child FAILURE: the running branch is
    halted, FAILURE. SUCCESS when all succeed in one tick. (BT.CPP ``ReactiveSequence``.)
    """

    INPUT_PORTS: dict[str, PortInformation] = {}
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    STOP_ON, ALL_DONE = FAILURE, SUCCESS
