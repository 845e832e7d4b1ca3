"""Precondition, RunOnce, LoopInt/LoopBool/LoopDouble/LoopString, SkipUnlessUpdated,
WaitValueUpdate (BehaviorTree.CPP 4 decorators)."""

from __future__ import annotations

from typing import Any

from behaviors.base import (FAILURE, INVALID, RUNNING, SUCCESS, DecoratorNode, PortInformation,
                            Status, Ticking)
from behaviors.btcpp.scripted import STORAGE, Scripted, skipped_status
from behaviors.btcpp.script_nodes import _NEVER, entry_changed

STATUS_NAMES = {"SUCCESS": SUCCESS, "FAILURE": FAILURE, "RUNNING": RUNNING, "SKIPPED": None}


class Precondition(Scripted, DecoratorNode):
    """Tick the child only if ``if`` (a script expression) is true when a run starts; else
    return ``else`` (SUCCESS, FAILURE, RUNNING or SKIPPED) without ticking it. Once the child
    runs, it is ticked until it finishes without checking again. (BT.CPP ``Precondition``.)"""

    INPUT_PORTS = {
        "if": PortInformation(str, True, "condition, a script expression"),
        "else": PortInformation(str, False, "status when false: SUCCESS, FAILURE, RUNNING or "
                                "SKIPPED", "FAILURE"),
    }
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    SCRIPT_PORTS = ("if",)
    CHOICES = {"else": tuple(STATUS_NAMES)}

    def tick_children(self) -> Ticking:
        child = self.decorated
        if child.status is not RUNNING:
            program = self.program("if")
            if program is None or not program.true(STORAGE):
                status = STATUS_NAMES[self.get_input("else")]
                return skipped_status(self) if status is None else status
        yield from child.tick()
        return child.status


class RunOnce(DecoratorNode):
    """Tick the child until it finishes once; afterwards never again: SKIPPED with
    ``then_skip`` (navbt: what lets the parent move on), else the status it finished with.
    (BT.CPP ``RunOnce``; the memory lasts for the tree's life.)"""

    INPUT_PORTS = {"then_skip": PortInformation(bool, False, "skip after the first run, else "
                                                "repeat its result", True)}
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def __init__(self, *args: Any, **kwargs: Any) -> None:  # noqa: D107
        super().__init__(*args, **kwargs)
        self._done: Status | None = None

    def setup(self, **kwargs: Any) -> None:
        pass

    def tick_children(self) -> Ticking:
        if self._done is not None:
            return skipped_status(self) if self.get_input("then_skip") else self._done
        yield from self.decorated.tick()
        status = self.decorated.status
        if status in (SUCCESS, FAILURE):
            self._done = status
        return status


class _Loop(DecoratorNode):
    """Pop a value from ``queue`` into ``value`` and tick the child, once per value (BT.CPP
    ``LoopNode<T>``): RUNNING between values, FAILURE when the child fails, ``if_empty`` when
    the queue is (or becomes) empty. ``queue`` is a list or ``;``-separated text; a queue on
    the blackboard is consumed in place."""

    ITEM: type = str
    INPUT_PORTS: dict[str, PortInformation]
    OUTPUT_PORTS: dict[str, PortInformation]
    CHOICES = {"if_empty": ("SUCCESS", "FAILURE", "SKIPPED")}

    def setup(self, **kwargs: Any) -> None:
        pass

    def _queue(self) -> list:
        raw = self.read("queue")
        if raw is None:
            return []
        if isinstance(raw, str):
            raw = [v for v in raw.split(";") if v.strip()]
        items = []
        for v in raw:
            if self.ITEM is bool and isinstance(v, str):
                items.append(v.strip().lower() == "true")
            else:
                items.append(self.ITEM(v.strip() if isinstance(v, str) else v))
        return items

    def tick_children(self) -> Ticking:
        if self.status is not RUNNING:
            self._items, self._child_running = self._queue(), False
        if not self._child_running:
            if not self._items:
                done = self.get_input("if_empty")
                return skipped_status(self) if done == "SKIPPED" else STATUS_NAMES[done]
            value = self._items.pop(0)
            self.write("value", value)
            key = self._keys.get("queue")
            if key is not None and isinstance(STORAGE.get(key), list):
                STORAGE[key] = list(self._items)  # a shared queue is consumed
        yield from self.decorated.tick()
        status = self.decorated.status
        self._child_running = status is RUNNING
        if status is FAILURE:
            return FAILURE
        if status is SUCCESS:
            self.halt_child()
        return RUNNING


def _loop_ports(item: type, doc: str) -> tuple[dict, dict]:
    return ({"queue": PortInformation(object, True, f"values ({doc}): a list or 'a;b;c'"),
             "if_empty": PortInformation(str, False, "status once the queue is empty",
                                         "SUCCESS")},
            {"value": PortInformation(item, True, "the value popped for this iteration")})


class LoopInt(_Loop):
    """Tick the child once per integer of ``queue`` (BT.CPP ``LoopInt``)."""

    ITEM = int
    INPUT_PORTS, OUTPUT_PORTS = _loop_ports(int, "integers")


class LoopDouble(_Loop):
    """Tick the child once per number of ``queue`` (BT.CPP ``LoopDouble``)."""

    ITEM = float
    INPUT_PORTS, OUTPUT_PORTS = _loop_ports(float, "numbers")


class LoopBool(_Loop):
    """Tick the child once per boolean of ``queue`` (BT.CPP ``LoopBool``)."""

    ITEM = bool
    INPUT_PORTS, OUTPUT_PORTS = _loop_ports(bool, "true/false")


class LoopString(_Loop):
    """Tick the child once per string of ``queue`` (BT.CPP ``LoopString``)."""

    ITEM = str
    INPUT_PORTS, OUTPUT_PORTS = _loop_ports(str, "strings")


class _EntryUpdated(Scripted, DecoratorNode):
    NOT_UPDATED: str = "SKIPPED"
    INPUT_PORTS: dict[str, PortInformation]
    OUTPUT_PORTS: dict[str, PortInformation]

    def __init__(self, *args: Any, **kwargs: Any) -> None:  # noqa: D107
        super().__init__(*args, **kwargs)
        self._seen: Any = _NEVER

    def tick_children(self) -> Ticking:
        child = self.decorated
        if child.status is not RUNNING and not entry_changed(self, "entry"):
            return skipped_status(self) if self.NOT_UPDATED == "SKIPPED" else RUNNING
        yield from child.tick()
        return child.status

    def stop(self, new_status: Status = INVALID) -> None:
        super().stop(new_status)


class SkipUnlessUpdated(_EntryUpdated):
    """Tick the child only when the entry named by ``entry`` changed since the last check
    (or the child is still running); otherwise SKIPPED (BT.CPP ``SkipUnlessUpdated``)."""

    INPUT_PORTS = {"entry": PortInformation(str, True, "name of the entry to watch")}
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    KEY_PORTS = ("entry",)


class WaitValueUpdate(_EntryUpdated):
    """RUNNING until the entry named by ``entry`` changes, then tick the child (BT.CPP
    ``WaitValueUpdate``)."""

    INPUT_PORTS = {"entry": PortInformation(str, True, "name of the entry to watch")}
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    KEY_PORTS = ("entry",)
    NOT_UPDATED = "RUNNING"
