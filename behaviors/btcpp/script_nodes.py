"""Script, ScriptCondition, SetBlackboard, UnsetBlackboard, Sleep, WasEntryUpdated
(BehaviorTree.CPP 4 actions and conditions)."""

from __future__ import annotations

from typing import Any

from behaviors.base import FAILURE, RUNNING, SUCCESS, Leaf, Port, PortInformation, Status
from behaviors.btcpp.scripted import STORAGE, Scripted


class Script(Scripted, Leaf):
    """Run ``code`` (the scripting subset: assignments to blackboard entries, arithmetic,
    comparisons, enums) and SUCCEED. A statement that fails (an entry that does not exist) is
    an error of the tree, raised as BT.CPP does. (BT.CPP ``Script``.)"""

    INPUT_PORTS = {"code": PortInformation(str, True, "the script, e.g. \"count := count + 1\"")}
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    SCRIPT_PORTS = ("code",)

    def update(self) -> Status:
        program = self.program("code")
        if program is not None:
            program.run(STORAGE)
        return SUCCESS


class ScriptCondition(Scripted, Leaf):
    """SUCCESS when ``code`` evaluates to true, else FAILURE (BT.CPP ``ScriptCondition``)."""

    CATEGORY = "Condition"
    INPUT_PORTS = {"code": PortInformation(str, True, "an expression, e.g. \"battery > 0.2\"")}
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    SCRIPT_PORTS = ("code",)

    def update(self) -> Status:
        program = self.program("code")
        return SUCCESS if program is not None and program.true(STORAGE) else FAILURE


class SetBlackboard(Leaf):
    """Write ``value`` (a literal, or ``{key}`` to copy another entry) to the entry that
    ``output_key`` names (``"{key}"``); SUCCESS (BT.CPP ``SetBlackboard``)."""

    INPUT_PORTS = {"value": PortInformation(object, True, "value to write, or {key} to copy")}
    OUTPUT_PORTS = {"output_key": PortInformation(object, True, "the entry to write, {key}")}

    def setup(self, **kwargs: Any) -> None:
        pass

    def update(self) -> Status:
        value = self.read("value")
        if value is None:
            self.say("nothing to copy: value's entry is empty")
            return FAILURE
        self.write("output_key", value)
        return SUCCESS


class UnsetBlackboard(Scripted, Leaf):
    """Remove the entry named by ``key`` (a plain name); SUCCESS, also when it was not there
    (BT.CPP ``UnsetBlackboard``)."""

    INPUT_PORTS = {"key": PortInformation(str, True, "name of the entry to remove")}
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    KEY_PORTS = ("key",)

    def update(self) -> Status:
        key = self.bound_key("key")
        if key is not None:
            STORAGE.pop(key, None)
        return SUCCESS


class Sleep(Leaf):
    """RUNNING for ``msec`` milliseconds of the injected clock, then SUCCESS; a halt ends it
    (BT.CPP ``Sleep``)."""

    INPUT_PORTS = {"msec": Port(int, True, "how long, ms", low=0)}
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def setup(self, **kwargs: Any) -> None:
        self.clock = self.component(kwargs, "clock")

    def initialise(self) -> None:
        msec = self.read("msec")
        self._until = self.clock.now() + (msec or 0) / 1000.0

    def update(self) -> Status:
        left = self._until - self.clock.now()
        if left <= 1e-9:
            return SUCCESS
        self.say("{:.2f} s left", left)
        return RUNNING


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
        return SUCCESS if entry_changed(self, "entry") else FAILURE


_NEVER = object()


def entry_changed(node: Any, port: str) -> bool:
    """Has the entry behind ``port`` changed since ``node`` last looked (first look: it has,
    if it exists)? Remembers the value seen."""
    key = node.bound_key(port)
    value = STORAGE.get(key, _NEVER) if key is not None else _NEVER
    before, node._seen = node._seen, value
    if value is _NEVER or value is None:
        return False
    return before is not value and (before is _NEVER or _differs(before, value))


def _differs(a: Any, b: Any) -> bool:
    try:
        return bool(a != b)
    except (TypeError, ValueError):  # arrays and the like: a new object counts as an update
        return True
