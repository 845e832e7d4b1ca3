"""Parameter files as read: YAML with the line of every key, the findings of a load (``Note``)
and the error of a file that cannot be read at all (``ParamsError``).

Shared by the navbt robot config (executive.config) and the ROS readers (ros_params, ros_launch,
nav2_params), below all of them.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from typing import Any, Mapping

import yaml

from navcore.safe_read import Duplicate, compose_yaml, duplicate_text, node_value, read_text
from executive.errors import ExecutiveError

Path_ = tuple[str, ...]


@dataclass(frozen=True)
class Note:
    """One finding about a config: ``level`` is "error", "warning", "note" or "ignored"."""

    level: str
    where: str
    text: str
    # the key path in the config document (("DWAPlannerROS", "sim_time")) when the finding is
    # about one value: callers match findings to keys by it, not by their text
    path: tuple = ()

    def __str__(self) -> str:
        prefix = f"{self.where}: " if self.where else ""
        return prefix + (self.text if self.level == "error" else f"{self.level}: {self.text}")


def nearest(by_path: Mapping[tuple, Any], path: tuple) -> Any:
    """The entry of ``path`` or of its nearest parent in ``by_path`` (None when neither is):
    where a value came from when only its namespace is recorded."""
    for n in range(len(path), 0, -1):
        if path[:n] in by_path:
            return by_path[path[:n]]
    return None


class Findings:
    """The findings of one load, as Notes: each names the ``file:line`` of its value when
    ``origins`` (key path -> ``file:line``) knows it, else ``source``."""

    def __init__(self, source: str, origins: Mapping[tuple, str], notes: list[Note]) -> None:
        self.source = source
        self.origins = dict(origins)
        self.notes = notes

    def where(self, path: tuple) -> str:
        found = nearest(self.origins, path)
        return self.source if found is None else found

    def add(self, level: str, path: tuple, text: str) -> None:
        self.notes.append(Note(level, self.where(path), text, path))

    def errors(self) -> list[Note]:
        return [n for n in self.notes if n.level == "error"]


class ParamsError(ExecutiveError, ValueError):
    """A parameter or launch file cannot be read at all (the message names file and line)."""


def _key_lines(node: Any, path: Path_, lines: dict[Path_, int]) -> None:
    if isinstance(node, yaml.MappingNode):
        for k, v in node.value:
            if isinstance(k, yaml.ScalarNode):
                p = path + (str(k.value),)
                lines.setdefault(p, k.start_mark.line + 1)
                _key_lines(v, p, lines)
    elif isinstance(node, yaml.SequenceNode):   # list items by index: ("points", 2, "key")
        for i, v in enumerate(node.value):
            lines.setdefault(path + (i,), v.start_mark.line + 1)
            _key_lines(v, path + (i,), lines)


def parse_yaml_lines(text: str, file: str, error: Any = None,
                     duplicates: list[Duplicate] | None = None) -> tuple[Any, dict[Path_, int]]:
    """Safe-parse YAML text (navcore.safe_read's limits): the data and the 1-based line of every
    mapping key and list item, by key path (indices for list items). A key written twice is an
    error, or appended to ``duplicates`` when given (ROS files: the last one is kept)."""
    error = error or ParamsError
    node = compose_yaml(text, file, error=error, duplicates=duplicates)
    if node is None:
        return None, {}
    lines: dict[Path_, int] = {}
    _key_lines(node, (), lines)
    return node_value(node, file, error=error), lines


def read_yaml(path: str | os.PathLike, text: str | None = None, *, what: str = "parameter file",
              error: Any = None, duplicates: list[Duplicate] | None = None
              ) -> tuple[Any, dict[Path_, int]]:
    """Read (bounded, strict UTF-8) and safe-parse a YAML file, or ``text`` read from it; errors
    (``error``, default ParamsError) name file and line."""
    file = os.fspath(path)
    error = error or ParamsError
    if text is None:
        text = read_text(file, what=what, error=error)
    return parse_yaml_lines(text, file, error, duplicates)


def read_ros_yaml(path: str | os.PathLike, notes: list[Note], text: str | None = None
                  ) -> tuple[Any, dict[Path_, int]]:
    """``read_yaml`` for a ROS parameter file: rosparam (PyYAML) keeps the last of two equal
    keys, and real files must load unedited, so a duplicate is a "note" in ``notes``, not an
    error."""
    file = os.fspath(path)
    found: list[Duplicate] = []
    doc, lines = read_yaml(file, text, duplicates=found)
    notes.extend(duplicate_notes(file, found))
    return doc, lines


def duplicate_notes(file: str, found: list[Duplicate], offset: int = 0) -> list[Note]:
    """One note per key written twice (``offset``: lines before the text, for inline YAML)."""
    return [Note("note", f"{file}:{line + offset}", f"{duplicate_text(key, first + offset)}; "
                 "the last one is used, as rosparam does") for line, first, key in found]
