"""The parsed, not yet built form of a tree file (YAML or XML), and the loader's error type.

Both readers produce a ``TreeDoc``; one builder turns it into py_trees objects, and ``to_xml``
writes it back out. Every ``NodeSpec`` remembers ``file:line`` so that errors point at the spot.
"""

from __future__ import annotations

import difflib
import os
import re
from dataclasses import dataclass, field
from typing import Any, Callable, Iterable

from executive.errors import ExecutiveError

KEY_REF = re.compile(r"^\{(@?[A-Za-z_][A-Za-z0-9_]*)\}$")


class TreeLoadError(ExecutiveError, ValueError):
    """A tree file is not acceptable. The message reads ``file:line: Name (Type): what is wrong``
    (``file:line: Type: ...`` for a node without a name of its own).

    ``file`` and ``line`` are also attributes, and ``excerpt()`` gives the offending line of the
    file (for a CLI that shows the spot).
    """

    def __init__(self, message: str) -> None:
        super().__init__(message)
        m = re.match(r"^(.*?):(\d+): ", message)
        self.file: str | None = m.group(1) if m else None
        self.line: int | None = int(m.group(2)) if m else None

    def excerpt(self) -> str:
        """The line of the file the error points at, or "" when it cannot be read."""
        if self.file is None or self.line is None:
            return ""
        try:
            with open(self.file, encoding="utf-8") as f:
                lines = f.read().splitlines()
        except OSError:
            return ""
        return lines[self.line - 1] if 0 < self.line <= len(lines) else ""


class TreeErrors(TreeLoadError):
    """Every problem found in one tree (``mission validate`` reports them all at once).

    ``errors`` holds each as a TreeLoadError, in file order; ``file``/``line`` are the first one's.
    """

    def __init__(self, errors: list[TreeLoadError]) -> None:
        ordered = sorted(errors, key=lambda e: (e.file or "", e.line or 0))
        super().__init__("\n".join(str(e) for e in ordered))
        self.errors = ordered
        self.file, self.line = ordered[0].file, ordered[0].line


def did_you_mean(name: str, known: Iterable[str]) -> str:
    close = difflib.get_close_matches(name, list(known), n=1, cutoff=0.6)
    return f" (did you mean '{close[0]}'?)" if close else ""


@dataclass
class Where:
    file: str
    line: int

    def __str__(self) -> str:
        return f"{self.file}:{self.line}"


@dataclass
class PortValue:
    """A port as written: a ``{key}`` reference or a literal (typed from YAML, text from XML)."""

    raw: Any
    where: Where
    text: str | None = None  # a YAML number as written ("0.30"), so XML gets the same text

    @property
    def ref(self) -> str | None:
        """The key name if this is a ``{key}`` reference, else None."""
        if isinstance(self.raw, str):
            m = KEY_REF.match(self.raw.strip())
            if m:
                return m.group(1)
        return None

    def looks_like_ref(self) -> bool:
        return isinstance(self.raw, str) and ("{" in self.raw or "}" in self.raw)


@dataclass
class NodeSpec:
    type: str
    where: Where
    name: str | None = None
    ports: dict[str, PortValue] = field(default_factory=dict)
    children: list["NodeSpec"] = field(default_factory=list)
    has_children_key: bool = False  # 'children:' or 'child:' was written
    subtree_id: str | None = None
    autoremap: bool = False
    form: str | None = None  # XML written as <Action ID="Type">: that element name
    comments: list[str] = field(default_factory=list)  # comments written just before the node

    @property
    def label(self) -> str:
        """``Name (Type)`` for a named node, else ``Type``: how messages name it."""
        return f"{self.name} ({self.type})" if self.name and self.name != self.type else self.type

    def error(self, message: str, where: Where | None = None) -> TreeLoadError:
        return TreeLoadError(f"{where or self.where}: {self.label}: {message}")

    def take_subtree_fields(self, id_key: str = "id") -> None:
        """For a SubTree: move ``id`` and ``_autoremap`` out of the ports."""
        pv = self.ports.pop(id_key, None)
        if pv is not None:
            self.subtree_id = str(pv.raw)
        auto = self.ports.pop("_autoremap", None)
        if auto is not None:
            raw = auto.raw
            if isinstance(raw, str):
                if raw.lower() not in ("true", "false"):
                    raise self.error(f"'_autoremap' must be true or false, got {raw!r}", auto.where)
                raw = raw.lower() == "true"
            if not isinstance(raw, bool):
                raise self.error(f"'_autoremap' must be true or false, got {raw!r}", auto.where)
            self.autoremap = raw


@dataclass
class TreeDoc:
    main_tree: str | None
    trees: dict[str, NodeSpec]
    tree_where: dict[str, Where]
    source: str
    from_text: bool = False  # XML: literal port values are strings still to be typed
    nav2_distro: str | None = None  # the Nav2 distribution the file says it was written for
    main_key: str = "main_tree"  # how the file names its main tree (XML: main_tree_to_execute)
    comments: list[str] = field(default_factory=list)  # file-level comments (before the trees)
    btcpp_format: str | None = None  # XML: <root BTCPP_format>; absent means BT.CPP 3 (Humble)

    def effective_distro(self, override: str | None = None) -> str | None:
        """The Nav2 distribution whose semantics apply: ``override`` (``--nav2-distro``), else
        what the file says, else jazzy for BT.CPP 4 XML, humble for BT.CPP 3 XML (no
        ``BTCPP_format``), and None (navbt's own semantics) for YAML."""
        from executive import nav2_model
        chosen = nav2_model.check_distro(override) if override else self.nav2_distro
        if chosen:
            return None if chosen == nav2_model.NAVBT else chosen
        if not self.from_text:
            return nav2_model.DEFAULT_YAML_DISTRO
        return nav2_model.DEFAULT_XML_DISTRO if self.btcpp_format else nav2_model.BTCPP3_DISTRO

    def include(self, src: str, where: Where | str, read: Callable[[str], TreeDoc]) -> None:
        """Merge the trees of the file ``src`` (relative to this document) read with ``read``;
        a missing file or a tree id defined twice is a TreeLoadError naming both places."""
        target = src if os.path.isabs(src) else os.path.join(os.path.dirname(self.source), src)
        if not os.path.exists(target):
            raise TreeLoadError(f"{where}: include '{src}' not found (looked for {target})")
        sub = read(target)
        for tid, spec in sub.trees.items():
            if tid in self.trees:
                raise TreeLoadError(f"{sub.tree_where[tid]}: tree '{tid}' is also defined in "
                                f"{self.tree_where[tid]}")
            self.trees[tid] = spec
            self.tree_where[tid] = sub.tree_where[tid]
