"""Fallback and ReactiveFallback (BT.CPP)."""

from __future__ import annotations

from behaviors.base import FAILURE, SUCCESS, PortInformation
from behaviors.controls.ordered import InOrder, Reactive


class Fallback(InOrder):
    """Tick children in order until one does not fail; resume at the RUNNING child.

    SUCCESS at the first child that succeeds; FAILURE when all have failed. (BT.CPP ``Fallback``.)
    """

    INPUT_PORTS: dict[str, PortInformation] = {}
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    STOP_ON, ALL_DONE = SUCCESS, FAILURE


class ReactiveFallback(Reactive):
    """Tick every child from the first on each tick; higher priorities preempt a running one.

    A child RUNNING: later children are halted, RUNNING. SUCCESS at the first success;
    FAILURE when all fail in one tick. (BT.CPP ``ReactiveFallback``.)
    """

    INPUT_PORTS: dict[str, PortInformation] = {}
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    STOP_ON, ALL_DONE = SUCCESS, FAILURE
