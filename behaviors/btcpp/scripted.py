"""What script-using nodes share: scripts compiled once against the tree's blackboard scope,
and how a SKIPPED outcome (BT.CPP 4) is told to a parent in navbt's four statuses."""

from __future__ import annotations

from typing import Any, Callable, ClassVar

import py_trees

from behaviors.base import FAILURE, RUNNING, SUCCESS, Status
from behaviors.btcpp.scripting import Program, compile_script, namespace_resolver

STORAGE = py_trees.blackboard.Blackboard.storage  # the process-wide key -> value dict
# Status names a tree may give (Precondition's else, a Loop's if_empty); None is SKIPPED.
STATUS_NAMES = {"SUCCESS": SUCCESS, "FAILURE": FAILURE, "RUNNING": RUNNING, "SKIPPED": None}


def skipped_status(node: py_trees.behaviour.Behaviour) -> Status:
    """BT.CPP's SKIPPED has no py_trees counterpart: a skipped node lets its parent move on,
    which is SUCCESS under a Sequence-like parent and FAILURE under a Fallback-like one (the
    parent then tries its next child, as BT.CPP does)."""
    parent = getattr(node, "parent", None)
    return FAILURE if parent is not None and "Fallback" in type(parent).__name__ else SUCCESS


class Scripted:
    """Mixin: ``SCRIPT_PORTS`` hold script text, ``KEY_PORTS`` hold blackboard entry names.
    The loader calls ``bind(resolve)`` with the tree's scope (SubTree remapping, ``@`` for
    mission-level); a node built by hand binds inside its own namespace on first use."""

    SCRIPT_PORTS: ClassVar[tuple[str, ...]] = ()
    KEY_PORTS: ClassVar[tuple[str, ...]] = ()

    def bind(self, resolve: Callable[[str], str]) -> None:
        """Compile the script ports and resolve the key ports (ScriptError if one is bad)."""
        self._programs: dict[str, Program] = {}
        self._bound: dict[str, str] = {}
        for port in self.SCRIPT_PORTS:
            text = self._literals.get(port)  # type: ignore[attr-defined]
            if isinstance(text, str) and text.strip():
                self._programs[port] = compile_script(text, resolve)
        for port in self.KEY_PORTS:
            name = self._literals.get(port)  # type: ignore[attr-defined]
            if isinstance(name, str) and name:
                key = name[1:-1] if name.startswith("{") and name.endswith("}") else name
                self._bound[port] = resolve(key)

    def _ensure_bound(self) -> None:
        if getattr(self, "_programs", None) is None:
            self.bind(namespace_resolver(self.namespace))  # type: ignore[attr-defined]

    def program(self, port: str) -> Program | None:
        self._ensure_bound()
        return self._programs.get(port)

    def bound_key(self, port: str) -> str | None:
        self._ensure_bound()
        return self._bound.get(port)

    def setup(self, **kwargs: Any) -> None:
        self.clock = kwargs.get("clock")
