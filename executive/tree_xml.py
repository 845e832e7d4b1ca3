"""BehaviorTree.CPP v4 XML (the Nav2 dialect) to and from ``TreeDoc``.

Reading uses expat directly so every element keeps its line number (errors say file:line).
Port values are strings, converted to the port type by the builder. Nav2 plumbing attributes
that mean nothing without ROS (``server_name``, ``server_timeout``, ...) are ignored, and the
clear-costmap ``service_name`` picks the costmap. Writing gives one self-contained file with a
``TreeNodesModel`` for every non-builtin node, which is what Groot2 needs to open it.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from typing import Any
from xml.parsers import expat
from xml.sax.saxutils import quoteattr

from behaviors.base import NavNode
from behaviors.registry import category
from executive.tree_spec import NodeSpec, PortValue, TreeDoc, TreeError, Where
from navcore.safe_read import MAX_INCLUDE_DEPTH, MAX_XML_DEPTH, read_bytes
from navcore.types import Pose2D

# Attributes of Nav2's BtActionNode/BtServiceNode and friends that have no meaning here.
NAV2_IGNORED = frozenset({"server_name", "server_timeout", "is_recovery", "goal_checker_id",
                          "progress_checker_id", "path_handler_id", "tracking_feedback",
                          "service_name", "ID"})

# Tags Groot2 knows without a model (BT.CPP built-ins).
BTCPP_BUILTINS = frozenset({"Sequence", "SequenceWithMemory", "ReactiveSequence", "Fallback",
                            "ReactiveFallback", "Parallel", "IfThenElse", "Inverter",
                            "RetryUntilSuccessful", "Repeat", "Timeout", "Delay", "ForceSuccess",
                            "ForceFailure", "SubTree"})


@dataclass
class _Elem:
    tag: str
    attrs: dict[str, str]
    line: int
    children: list["_Elem"] = field(default_factory=list)


def _parse(file: str) -> _Elem:
    data = read_bytes(file, what="tree file", error=TreeError)
    parser = expat.ParserCreate()
    stack: list[_Elem] = []
    root: list[_Elem] = []

    def start(tag: str, attrs: dict[str, str]) -> None:
        if len(stack) >= MAX_XML_DEPTH:
            raise TreeError(f"{file}:{parser.CurrentLineNumber}: elements nested more than "
                            f"{MAX_XML_DEPTH} deep (limit)")
        el = _Elem(tag, dict(attrs), parser.CurrentLineNumber)
        (stack[-1].children if stack else root).append(el)
        stack.append(el)

    def end(tag: str) -> None:
        stack.pop()

    def no_entities(name: str, *_: Any) -> None:  # no entity can expand into a bomb
        raise TreeError(f"{file}:{parser.CurrentLineNumber}: XML entity declarations are not "
                        f"allowed (entity '{name}')")

    parser.StartElementHandler = start
    parser.EndElementHandler = end
    parser.EntityDeclHandler = no_entities
    parser.SetParamEntityParsing(expat.XML_PARAM_ENTITY_PARSING_NEVER)
    try:
        parser.Parse(data, True)
    except expat.ExpatError as e:
        raise TreeError(f"{file}:{e.lineno}: not valid XML: {expat.ErrorString(e.code)}") from None
    except LookupError as e:  # encoding="..." naming no codec Python knows
        raise TreeError(f"{file}:1: not valid XML: {e}") from None
    except (ValueError, UnicodeError) as e:
        raise TreeError(f"{file}:{parser.CurrentLineNumber}: not valid XML: {e}") from None
    if not root:
        raise TreeError(f"{file}:1: not valid XML: no element")
    return root[0]


def _node(el: _Elem, file: str) -> NodeSpec:
    spec = NodeSpec(type=el.tag, where=Where(file, el.line))
    for k, v in el.attrs.items():
        if k == "name":
            spec.name = v
        else:
            spec.ports[k] = PortValue(v, spec.where)
    if el.tag == "SubTree":
        spec.take_subtree_fields("ID")
    elif el.tag.startswith("Clear") and "costmap" not in spec.ports and "service_name" in el.attrs:
        service = el.attrs["service_name"]
        which = "local" if "local" in service else "global" if "global" in service else None
        if which:
            spec.ports["costmap"] = PortValue(which, spec.where)
    for k in NAV2_IGNORED - {"ID"}:  # ROS plumbing: dropped, so exports stay clean
        spec.ports.pop(k, None)
    spec.children = [_node(c, file) for c in el.children]
    spec.has_children_key = bool(el.children)
    return spec


def read_xml(path: str | os.PathLike, _stack: tuple[str, ...] = ()) -> TreeDoc:
    """Parse a BT.CPP v4 XML file (and its ``<include path=.../>`` files) into a TreeDoc."""
    file = str(path)
    real = os.path.realpath(file)
    if real in _stack:
        raise TreeError(f"{file}:1: include cycle: "
                        + " -> ".join(os.path.basename(s) for s in (*_stack, real)))
    if len(_stack) >= MAX_INCLUDE_DEPTH:
        raise TreeError(f"{file}:1: includes nested more than {MAX_INCLUDE_DEPTH} files deep "
                        f"(limit)")
    root = _parse(file)
    if root.tag != "root":
        raise TreeError(f"{file}:{root.line}: the top element must be <root>, not <{root.tag}>")
    doc = TreeDoc(main_tree=root.attrs.get("main_tree_to_execute"), trees={}, tree_where={},
                  source=file, from_text=True)
    for el in root.children:
        where = Where(file, el.line)
        if el.tag == "BehaviorTree":
            tid = el.attrs.get("ID")
            if not tid:
                raise TreeError(f"{where}: <BehaviorTree> needs an ID")
            if len(el.children) != 1:
                raise TreeError(f"{where}: <BehaviorTree ID='{tid}'> must hold exactly one root "
                                f"node, has {len(el.children)}")
            doc.trees[tid] = _node(el.children[0], file)
            doc.tree_where[tid] = where
        elif el.tag.lower() in ("include", "import"):
            src = el.attrs.get("path") or el.attrs.get("file") or el.attrs.get("src")
            if not src:
                raise TreeError(f"{where}: <{el.tag}> needs a 'path' attribute")
            doc.include(src, where, lambda target: read_xml(target, (*_stack, real)))
        elif el.tag == "TreeNodesModel":
            continue
        else:
            raise TreeError(f"{where}: unexpected <{el.tag}> under <root>")
    return doc


# ---------------------------------------------------------------------------- writing

def format_value(value: Any) -> str:
    """A port value as BT.CPP text: references as-is, lists ';'-joined, booleans lower case."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return repr(value)
    if isinstance(value, Pose2D):
        return f"{value.x!r};{value.y!r};{value.theta!r}"
    if isinstance(value, dict):
        if set(value) <= {"x", "y", "theta"} and value:
            return ";".join(repr(float(value.get(k, 0.0))) for k in ("x", "y", "theta"))
        return "; ".join(f"{k}: {format_value(v)}" for k, v in value.items())
    if isinstance(value, (list, tuple)):
        return ";".join(format_value(v) for v in value)
    return str(value)


def _write_node(spec: NodeSpec, indent: int, out: list[str]) -> None:
    pad = "  " * indent
    attrs = []
    if spec.type == "SubTree":
        attrs.append(f"ID={quoteattr(spec.subtree_id or '')}")
    if spec.name:
        attrs.append(f"name={quoteattr(spec.name)}")
    if spec.type == "SubTree" and spec.autoremap:
        attrs.append('_autoremap="true"')
    for port, pv in spec.ports.items():
        attrs.append(f"{port}={quoteattr(format_value(pv.raw))}")
    head = f"{pad}<{spec.type}" + "".join(" " + a for a in attrs)
    if not spec.children:
        out.append(head + "/>")
        return
    out.append(head + ">")
    for c in spec.children:
        _write_node(c, indent + 1, out)
    out.append(f"{pad}</{spec.type}>")


def _used_types(doc: TreeDoc) -> list[str]:
    seen: list[str] = []

    def walk(s: NodeSpec) -> None:
        if s.type not in seen:
            seen.append(s.type)
        for c in s.children:
            walk(c)

    for spec in doc.trees.values():
        walk(spec)
    return seen


def write_xml(doc: TreeDoc, main_tree: str, classes: dict[str, type[NavNode]]) -> str:
    """BT.CPP v4 XML of every tree in ``doc`` plus a TreeNodesModel of the custom nodes."""
    out = ['<?xml version="1.0" encoding="UTF-8"?>',
           f'<root BTCPP_format="4" main_tree_to_execute={quoteattr(main_tree)}>']
    for tid, spec in doc.trees.items():
        out.append(f"  <BehaviorTree ID={quoteattr(tid)}>")
        _write_node(spec, 2, out)
        out.append("  </BehaviorTree>")
    out.append("  <TreeNodesModel>")
    for t in _used_types(doc):
        cls = classes.get(t)
        if t in BTCPP_BUILTINS or cls is None:
            continue
        out.append(f"    <{category(cls)} ID={quoteattr(t)}>")
        for direction, table in (("input_port", cls.input_ports()),
                                 ("output_port", cls.output_ports())):
            for pname, info in table.items():
                default = info.default_value
                if default is None and pname in cls.DEFAULT_KEYS:
                    default = "{" + cls.DEFAULT_KEYS[pname] + "}"
                dattr = "" if default is None else f" default={quoteattr(format_value(default))}"
                desc = info.description.replace("&", "&amp;").replace("<", "&lt;")
                out.append(f"      <{direction} name={quoteattr(pname)}{dattr}>{desc}</{direction}>")
        out.append(f"    </{category(cls)}>")
    out.append("  </TreeNodesModel>")
    out.append("</root>")
    return "\n".join(out) + "\n"
