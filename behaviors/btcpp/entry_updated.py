"""WasEntryUpdated, SkipUnlessUpdated and WaitValueUpdate (BehaviorTree.CPP 4): nodes that
watch a blackboard entry for updates."""

from __future__ import annotations

from typing import Any

from behaviors.base import (FAILURE, INVALID, RUNNING, SUCCESS, DecoratorNode, Leaf,
                            PortInformation, Status, Ticking)
from behaviors.btcpp.scripted import STORAGE, Scripted, skipped_status


class WasEntryUpdated(Scripted, Leaf):
    """SUCCESS when the entry named by ``entry`` holds a different value (or object) than on
    this node's previous tick, FAILURE otherwise or when it does not exist (BT.CPP
    ``WasEntryUpdated``; BT.CPP counts writes, navbt sees changes: writing the same value
    again is not an update here)."""

    CATEGORY = "Condition"
    INPUT_PORTS = {"entry": PortInformation(str, True, "name of the entry to watch")}
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    KEY_PORTS = ("entry",)

    def __init__(self, *args, **kwargs) -> None:  # noqa: D107
        super().__init__(*args, **kwargs)
        self._seen: Any = _NEVER

    def update(self) -> Status:
        changed, self._seen = entry_changed(self.bound_key("entry"), self._seen)
        return SUCCESS if changed else FAILURE


_NEVER = object()


def entry_changed(key: str | None, before: Any) -> tuple[bool, Any]:
    """Has the blackboard entry ``key`` changed since a node saw ``before`` there (first look,
    ``_NEVER``: it has, if it exists)? Returns that and the value to remember."""
    value = STORAGE.get(key, _NEVER) if key is not None else _NEVER
    if value is _NEVER or value is None:
        return False, value
    return before is not value and (before is _NEVER or _differs(before, value)), value


def _differs(a: Any, b: Any) -> bool:
    try:
        return bool(a != b)
    except (TypeError, ValueError):  # arrays and the like: a new object counts as an update
        return True


class _EntryUpdated(Scripted, DecoratorNode):
    NOT_UPDATED: str = "SKIPPED"
    INPUT_PORTS: dict[str, PortInformation]
    OUTPUT_PORTS: dict[str, PortInformation]

    def __init__(self, *args: Any, **kwargs: Any) -> None:  # noqa: D107
        super().__init__(*args, **kwargs)
        self._seen: Any = _NEVER

    def tick(self) -> Ticking:
        self.begin_tick()
        child = self.decorated
        if child.status is not RUNNING:
            changed, self._seen = entry_changed(self.bound_key("entry"), self._seen)
            if not changed:
                yield self.finish(skipped_status(self) if self.NOT_UPDATED == "SKIPPED"
                                  else RUNNING)
                return
        yield from child.tick()
        yield self.finish(child.status)

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
