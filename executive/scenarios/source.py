"""A scenario file as data plus the line of every value, and an error collector that says where.

``read_source`` parses YAML with the safe loader's composer and builds plain Python values while
remembering the line of each mapping key and list item, so that every problem can be reported as
``file:line: field: what``. ``Problems`` collects them all (a file is checked completely, not
up to its first error) and raises one ``ScenarioError`` carrying the list.
"""

from __future__ import annotations

import os
from typing import Any

import yaml
from yaml.constructor import SafeConstructor

from navcore.safe_read import MAX_YAML_NODES, compose_yaml, node_value, read_text
from executive.errors import ExecutiveError

MAX_NODES = MAX_YAML_NODES   # values with aliases expanded: no alias bomb

Path_ = tuple[Any, ...]       # a field path: ("expect", "recoveries", "at_most")


class ScenarioError(ExecutiveError, ValueError):
    """A scenario file is unreadable or malformed. ``errors`` lists every problem found, each as
    ``file:line: field: what``; the message is all of them, one a line."""

    def __init__(self, message: str, errors: list[str] | None = None) -> None:
        self.errors = list(errors) if errors else [message]
        super().__init__(message)


def dotted(path: Path_) -> str:
    out = ""
    for p in path:
        if isinstance(p, int):
            out += f"[{p}]"
        else:
            out += ("." if out else "") + str(p)
    return out


class Source:
    """A parsed document (``doc``) with line numbers by field path (``lines``)."""

    def __init__(self, name: str, doc: Any, lines: dict[Path_, int] | None = None) -> None:
        self.name = name
        self.doc = doc
        self.lines = lines or {}

    def line(self, path: Path_) -> int | None:
        path = tuple(path)
        while path:
            if path in self.lines:
                return self.lines[path]
            path = path[:-1]
        return self.lines.get(())

    def where(self, path: Path_) -> str:
        line = self.line(path)
        loc = f"{self.name}:{line}" if line is not None else self.name
        field = dotted(path)
        return f"{loc}: {field}" if field else loc


class Problems:
    """Collects every problem of one file; ``raise_if_any`` raises them as one ScenarioError."""

    def __init__(self, src: Source) -> None:
        self.src = src
        self.errors: list[str] = []

    def add(self, path: Path_, what: str) -> None:
        self.errors.append(f"{self.src.where(path)}: {what}")

    def raise_if_any(self) -> None:
        if self.errors:
            raise ScenarioError("\n".join(self.errors), self.errors)


def _build(node: yaml.Node, path: Path_, lines: dict[Path_, int], count: list[int],
           src: str) -> Any:
    count[0] += 1
    if count[0] > MAX_NODES:
        raise ScenarioError(f"{src}:{node.start_mark.line + 1}: more than {MAX_NODES} values "
                            "(aliases expanded)")
    lines.setdefault(path, node.start_mark.line + 1)
    if isinstance(node, yaml.MappingNode):
        _FLATTEN.flatten_mapping(node)          # '<<' merge keys, as the safe loader does
        pairs = []
        for knode, vnode in node.value:
            if not isinstance(knode, yaml.ScalarNode):
                raise ScenarioError(f"{src}:{knode.start_mark.line + 1}: a mapping key must be "
                                    "a plain value")
            key = node_value(knode, src, error=ScenarioError)
            if not isinstance(key, (str, int, float, bool)) and key is not None:
                raise ScenarioError(f"{src}:{knode.start_mark.line + 1}: bad key {key!r}")
            pairs.append((key, knode, vnode))
        # a key written twice was refused when composing; one met again here was merged in by
        # '<<' and is overridden by the later entry (the mapping's own key), as YAML says
        final = {key: i for i, (key, _, _) in enumerate(pairs)}
        out: dict[Any, Any] = {}
        for i, (key, knode, vnode) in enumerate(pairs):
            if final[key] == i:
                lines[path + (key,)] = knode.start_mark.line + 1
                out[key] = _build(vnode, path + (key,), lines, count, src)
        return out
    if isinstance(node, yaml.SequenceNode):
        return [_build(v, path + (i,), lines, count, src) for i, v in enumerate(node.value)]
    return node_value(node, src, error=ScenarioError)


_FLATTEN = SafeConstructor()


def parse_source(text: str, name: str) -> Source:
    """Parse YAML text (the project's safe reader: safe loader, depth and alias limits) into a
    Source; ScenarioError with file:line if it is not valid."""
    node = compose_yaml(text, name, error=ScenarioError)
    lines: dict[Path_, int] = {}
    try:
        doc = None if node is None else _build(node, (), lines, [0], name)
    except yaml.YAMLError as e:
        mark = getattr(e, "problem_mark", None)
        line = f":{mark.line + 1}" if mark is not None else ""
        raise ScenarioError(f"{name}{line}: not valid YAML "
                            f"({getattr(e, 'problem', None) or e})") from None
    except RecursionError:
        raise ScenarioError(f"{name}:1: nested too deeply") from None
    lines.setdefault((), 1)      # an empty document: its problems are on line 1
    return Source(name, doc, lines)


def read_source(path: str | os.PathLike) -> Source:
    """Read (regular files only, size-capped, strict UTF-8) and parse one scenario or profile
    file."""
    path = str(path)
    return parse_source(read_text(path, what="scenario", error=ScenarioError), path)
