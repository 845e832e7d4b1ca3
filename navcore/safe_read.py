"""One reading path for every file a user gives: bounded, decoded, safely parsed.

Trees (YAML and XML), robot configs, map descriptors and images, scenarios and ``SetParameters``
values all come through here, so one set of limits holds everywhere (docs/limits.md):

- only regular files are read (``/dev/zero``, FIFOs, directories are refused) and at most
  ``MAX_TEXT_BYTES`` (text) or ``MAX_IMAGE_BYTES`` (map images);
- text is strict UTF-8 (a BOM is dropped) without control characters other than tab, CR, LF;
- YAML is composed with the safe loader only, nesting at most ``MAX_YAML_DEPTH`` deep, aliases
  must point at finished nodes (no self reference) and the document expanded through its aliases
  holds at most ``MAX_YAML_NODES`` nodes (no alias bomb);
- integers beyond 64 bits and malformed tagged scalars (``!!float x``) are refused where written;
- a key written twice in one mapping is refused (PyYAML would keep the last without a word),
  naming both lines; ROS parameter files, which rosparam reads with that leniency, ask for the
  duplicates as findings instead (``duplicates=``). Keys merged in by ``<<`` may be overridden.

Every failure raises the caller's error type (``error=``) with ``file:line: what``; nothing else
escapes. navcore imports nothing of ours, so this lives here for ``navcore.maps`` and above.
"""

from __future__ import annotations

import os
import re
import stat
from xml.parsers import expat
from typing import Any, Callable

import yaml
from yaml.constructor import ConstructorError, SafeConstructor
from yaml.events import (AliasEvent, DocumentStartEvent, MappingEndEvent, MappingStartEvent,
                         ScalarEvent, SequenceEndEvent, SequenceStartEvent)

from navcore.errors import NavcoreError

MAX_TEXT_BYTES = 4 * 1024 * 1024      # a tree, config, scenario or map descriptor
MAX_IMAGE_BYTES = 128 * 1024 * 1024   # a map image (PGM/PNG)
MAX_YAML_DEPTH = 100                  # nested mappings/sequences
MAX_YAML_NODES = 200_000              # nodes of a document with every alias expanded
MAX_INT = 2 ** 63                     # |integer| a YAML file may hold
MAX_XML_DEPTH = 100                   # nested XML elements
MAX_INCLUDE_DEPTH = 16                # files including files (trees)
MAX_TREE_NODES = 10_000               # behaviours of a built tree, subtrees expanded
MAX_TREE_DEPTH = 64                   # nesting of a built tree, subtrees expanded

# libyaml's parser and composer when present (about 10x faster); same events, marks and safety.
_LOADER = getattr(yaml, "CSafeLoader", yaml.SafeLoader)
_STR_TAG = "tag:yaml.org,2002:str"
_CONTROL = re.compile("[\x00-\x08\x0b\x0c\x0e-\x1f\x7f\ufffe\uffff]")


class ReadError(NavcoreError, ValueError):
    """A user file cannot be read; used when the caller names no error type of its own."""


ErrorType = Callable[[str], Exception]


def read_bytes(path: str | os.PathLike, *, limit: int = MAX_TEXT_BYTES, what: str = "file",
               error: ErrorType = ReadError) -> bytes:
    """The bytes of a regular file of at most ``limit`` bytes (never blocks on a FIFO)."""
    file = os.fspath(path)
    try:
        fd = os.open(file, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    except FileNotFoundError:
        raise error(f"{file}: cannot read {what}: not found") from None
    except OSError as e:
        raise error(f"{file}: cannot read {what}: {e.strerror or e}") from None
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode):
            raise error(f"{file}: cannot read {what}: not a regular file")
        if st.st_size > limit:
            raise error(f"{file}: {what} is {st.st_size} bytes, more than the limit of {limit}")
        with os.fdopen(fd, "rb", closefd=False) as f:
            # read() allocates what it is asked for: ask for the file's size (plus one byte,
            # to notice a file that grew past the limit), not for the limit
            data = f.read(min(limit, st.st_size) + 1)
            while len(data) > st.st_size and len(data) <= limit:  # grew, or reports no size
                more = f.read(min(1 << 20, limit + 1 - len(data)))
                if not more:
                    break
                data += more
    except OSError as e:
        raise error(f"{file}: cannot read {what}: {e.strerror or e}") from None
    finally:
        os.close(fd)
    if len(data) > limit:  # grew while reading
        raise error(f"{file}: {what} is more than the limit of {limit} bytes")
    return data


def decode_text(data: bytes, file: str, *, what: str = "file", error: ErrorType = ReadError
                ) -> str:
    """Strict UTF-8 text without control characters; errors name the line and column."""
    if data.startswith(b"\xef\xbb\xbf"):
        data = data[3:]
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as e:
        line = data.count(b"\n", 0, e.start) + 1
        raise error(f"{file}:{line}: {what} is not UTF-8 text (byte 0x{data[e.start]:02x})"
                    ) from None
    check_characters(text, file, error=error)
    return text


def check_characters(text: str, file: str, *, error: ErrorType = ReadError) -> None:
    """Refuse control characters (other than tab, CR, LF), naming line and column."""
    m = _CONTROL.search(text)
    if m is not None:
        line = text.count("\n", 0, m.start()) + 1
        col = m.start() - (text.rfind("\n", 0, m.start()) + 1) + 1
        raise error(f"{file}:{line}: control character U+{ord(m.group()):04X} at column {col}")


def read_text(path: str | os.PathLike, *, what: str = "file", error: ErrorType = ReadError,
              limit: int = MAX_TEXT_BYTES) -> str:
    """``read_bytes`` then ``decode_text``."""
    return decode_text(read_bytes(path, limit=limit, what=what, error=error), os.fspath(path),
                       what=what, error=error)


def _yaml_error(e: yaml.YAMLError, file: str, error: ErrorType) -> Exception:
    mark = getattr(e, "problem_mark", None) or getattr(e, "context_mark", None)
    line = mark.line + 1 if mark is not None else 1
    problem = getattr(e, "problem", None) or str(e)
    if isinstance(e, _BadValue):  # a well-formed scalar whose value we refuse
        return error(f"{file}:{line}: bad value: {problem}")
    return error(f"{file}:{line}: not valid YAML: {problem}")


def _check_events(text: str, file: str, error: ErrorType, max_depth: int, max_nodes: int) -> None:
    """Refuse deep nesting, self-referencing aliases and alias bombs before composing."""
    check_characters(text, file, error=error)
    stack: list[list[Any]] = []      # open collections: [anchor, expanded node count]
    sizes: dict[str, int] = {}       # finished anchors -> expanded node count
    total = 0
    # one pass over libyaml's events, dispatched on the exact class (the parser makes no
    # subclasses); the line is worked out only for an error
    for ev in yaml.parse(text, Loader=_LOADER):
        kind = ev.__class__
        if kind is ScalarEvent:
            if ev.anchor is not None:
                sizes[ev.anchor] = 1
            n = 1
        elif kind is MappingStartEvent or kind is SequenceStartEvent:
            if len(stack) >= max_depth:
                raise error(f"{file}:{_line(ev)}: nested more than {max_depth} levels deep "
                            f"(limit)")
            stack.append([ev.anchor, 0])
            continue
        elif kind is MappingEndEvent or kind is SequenceEndEvent:
            anchor, n = stack.pop()
            if anchor is not None:
                sizes[anchor] = n + 1
            if stack:
                stack[-1][1] += n
            n = 1
        elif kind is AliasEvent:
            if ev.anchor not in sizes:
                if any(a == ev.anchor for a, _ in stack):
                    raise error(f"{file}:{_line(ev)}: alias *{ev.anchor} refers to a node that "
                                f"contains it")
                raise error(f"{file}:{_line(ev)}: alias *{ev.anchor} names no anchor before it")
            n = sizes[ev.anchor]
        else:
            if kind is DocumentStartEvent:
                stack.clear()
            continue
        total += n
        if total > max_nodes:
            raise error(f"{file}:{_line(ev)}: the document expands to more than {max_nodes} "
                        f"nodes through its aliases (limit)")
        if stack:
            stack[-1][1] += n


def _line(ev: yaml.Event) -> int:
    return ev.start_mark.line + 1 if ev.start_mark is not None else 1


Duplicate = tuple[int, int, str]  # a key written twice: (its line, the first's line, the key)


def duplicate_text(key: str, first: int) -> str:
    """What a duplicate key is called in errors and notes."""
    return f"'{key}' appears twice in the same mapping (first at line {first})"


def compose_yaml(text: str, file: str, *, error: ErrorType = ReadError,
                 max_depth: int = MAX_YAML_DEPTH, max_nodes: int = MAX_YAML_NODES,
                 duplicates: list[Duplicate] | None = None) -> yaml.Node | None:
    """The YAML node graph of ``text`` (one document; None when empty), within the limits.
    A key written twice in one mapping is an error, or, when a ``duplicates`` list is given,
    appended to it (the caller reports it; the constructor keeps the last, as PyYAML does)."""
    try:
        _check_events(text, file, error, max_depth, max_nodes)
        node = yaml.compose(text, Loader=_LOADER)
    except yaml.YAMLError as e:
        raise _yaml_error(e, file, error) from None
    except RecursionError:
        raise error(f"{file}:1: nested too deeply") from None
    if node is not None:
        found = _duplicate_keys(node, stop_at_first=duplicates is None)
        if duplicates is None and found:
            line, first, key = found[0]
            raise error(f"{file}:{line}: {duplicate_text(key, first)}")
        if duplicates is not None:
            duplicates.extend(found)
    return node


def _duplicate_keys(root: yaml.Node, stop_at_first: bool) -> list[Duplicate]:
    """Keys written twice in one mapping, in document order. Only the keys written in the
    mapping count (before ``<<`` merges are flattened: an explicit key overriding a merged one
    is legal YAML); keys compare by resolved tag and text, so ``1`` and ``"1"`` differ."""
    found: list[Duplicate] = []
    seen_nodes: set[int] = set()       # an aliased mapping is checked once
    stack = [root]
    while stack:
        node = stack.pop()
        if id(node) in seen_nodes or node.__class__ is yaml.ScalarNode:
            continue
        seen_nodes.add(id(node))
        if node.__class__ is yaml.MappingNode:
            first: dict[tuple[str, str], int] = {}
            for k, _ in node.value:
                if k.__class__ is yaml.ScalarNode:
                    key = (k.tag, k.value)
                    if key not in first:
                        first[key] = line_of(k)
                        continue
                    found.append((line_of(k), first[key], k.value))
                    if stop_at_first:
                        return found
            stack.extend(n for pair in reversed(node.value) for n in reversed(pair))
        else:
            stack.extend(reversed(node.value))
    return found


class _BadValue(NavcoreError, ConstructorError):
    """A scalar that parses as YAML but holds a value out of range or malformed for its tag."""


class _Constructor(SafeConstructor):
    """The safe constructor, refusing integers beyond 64 bits and malformed typed scalars."""

    def construct_yaml_int(self, node: yaml.ScalarNode) -> int:
        digits = str(node.value).replace("_", "").lstrip("+-")
        if len(digits) > 70:  # any base; int() itself refuses > 4300 digits with ValueError
            raise _BadValue(None, None, f"integer of {len(digits)} digits is out of range",
                                   node.start_mark)
        try:
            value = super().construct_yaml_int(node)
        except ValueError:
            raise _BadValue(None, None, f"{node.value!r} is not an integer",
                                   node.start_mark) from None
        if abs(value) >= MAX_INT:
            raise _BadValue(None, None, f"integer {node.value} is out of range "
                                   f"(|n| < 2**63)", node.start_mark)
        return value

    def construct_yaml_float(self, node: yaml.ScalarNode) -> float:
        try:
            return super().construct_yaml_float(node)
        except (ValueError, OverflowError):
            raise _BadValue(None, None, f"{node.value!r} is not a number",
                                   node.start_mark) from None

    def construct_yaml_timestamp(self, node: yaml.ScalarNode) -> Any:
        try:
            return super().construct_yaml_timestamp(node)
        except (ValueError, OverflowError, TypeError, AttributeError):  # AttributeError: no match
            raise _BadValue(None, None, f"{node.value!r} is not a timestamp",
                                   node.start_mark) from None

    def construct_yaml_binary(self, node: yaml.ScalarNode) -> bytes:
        try:
            return super().construct_yaml_binary(node)
        except (ValueError, TypeError):
            raise _BadValue(None, None, "bad !!binary data", node.start_mark) from None


for _tag, _name in (("int", "construct_yaml_int"), ("float", "construct_yaml_float"),
                    ("timestamp", "construct_yaml_timestamp"), ("binary", "construct_yaml_binary")):
    _Constructor.add_constructor(f"tag:yaml.org,2002:{_tag}", getattr(_Constructor, _name))


def node_value(node: yaml.Node, file: str, *, error: ErrorType = ReadError) -> Any:
    """Plain Python data of a composed node (safe types only), errors at the node's line."""
    if node.__class__ is yaml.ScalarNode and node.tag == _STR_TAG:
        return node.value  # what the constructor returns for a string, without making one
    try:
        return _Constructor().construct_document(node)
    except yaml.YAMLError as e:
        raise _yaml_error(e, file, error) from None
    except (ValueError, TypeError, OverflowError) as e:  # a hashable key that is not, etc.
        raise error(f"{file}:{node.start_mark.line + 1}: bad YAML value: {e}") from None
    except RecursionError:
        raise error(f"{file}:{node.start_mark.line + 1}: nested too deeply") from None


def parse_yaml(text: str, file: str, *, error: ErrorType = ReadError) -> Any:
    """Plain data of a YAML text (None when empty), within the limits."""
    node = compose_yaml(text, file, error=error)
    return None if node is None else node_value(node, file, error=error)


def load_yaml(path: str | os.PathLike, *, what: str = "file", error: ErrorType = ReadError,
              limit: int = MAX_TEXT_BYTES) -> Any:
    """Read, decode and parse a YAML file: the one way user YAML files are loaded."""
    file = os.fspath(path)
    return parse_yaml(read_text(file, what=what, error=error, limit=limit), file, error=error)


def load_yaml_keys(path: str | os.PathLike, *, what: str = "file", error: ErrorType = ReadError,
                   limit: int = MAX_TEXT_BYTES) -> tuple[Any, dict[str, int]]:
    """``load_yaml`` plus the 1-based line of each top-level key (for errors naming a field)."""
    file = os.fspath(path)
    node = compose_yaml(read_text(file, what=what, error=error, limit=limit), file, error=error)
    if node is None:
        return None, {}
    lines = {}
    if isinstance(node, yaml.MappingNode):
        lines = {k.value: line_of(k) for k, _ in node.value if isinstance(k, yaml.ScalarNode)}
    return node_value(node, file, error=error), lines


def line_of(node: yaml.Node | None) -> int:
    """1-based line of a composed node (1 when unknown)."""
    return node.start_mark.line + 1 if node is not None and node.start_mark is not None else 1


def parse_xml(parser: Any, data: bytes, file: str, *, error: ErrorType = ReadError) -> None:
    """Feed ``data`` to an expat ``parser`` whose element handlers the caller has set, refusing
    entity declarations (no entity can expand into a bomb); every failure is ``error`` naming
    the file and line."""
    def no_entities(name: str, *_: Any) -> None:
        raise error(f"{file}:{parser.CurrentLineNumber}: XML entity declarations are not "
                    f"allowed (entity '{name}')")

    parser.EntityDeclHandler = no_entities
    parser.SetParamEntityParsing(expat.XML_PARAM_ENTITY_PARSING_NEVER)
    try:
        parser.Parse(data, True)
    except expat.ExpatError as e:
        raise error(f"{file}:{e.lineno}: not valid XML: {expat.ErrorString(e.code)}") from None
    except LookupError as e:  # encoding="..." naming no codec Python knows
        raise error(f"{file}:1: not valid XML: {e}") from None
    except (ValueError, UnicodeError) as e:
        raise error(f"{file}:{parser.CurrentLineNumber}: not valid XML: {e}") from None
