"""LoopInt, LoopDouble, LoopBool, LoopString (BehaviorTree.CPP 4 decorators)."""

from __future__ import annotations

from typing import Any

from behaviors.base import FAILURE, RUNNING, SUCCESS, DecoratorNode, PortInformation, Ticking
from behaviors.btcpp.scripted import STATUS_NAMES, STORAGE, skipped_status


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

    def tick(self) -> Ticking:
        if self.begin_tick():
            self._items, self._child_running = self._queue(), False
        if not self._child_running:
            if not self._items:
                done = self.get_input("if_empty")
                yield self.finish(skipped_status(self) if done == "SKIPPED" else STATUS_NAMES[done])
                return
            value = self._items.pop(0)
            self.write("value", value)
            key = self._keys.get("queue")
            if key is not None and isinstance(STORAGE.get(key), list):
                STORAGE[key] = list(self._items)  # a shared queue is consumed
        yield from self.decorated.tick()
        status = self.decorated.status
        self._child_running = status is RUNNING
        if status is FAILURE:
            yield self.finish(FAILURE)
            return
        if status is SUCCESS:
            self.halt_children()
        yield self.finish(RUNNING)


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
