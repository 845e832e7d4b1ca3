"""BehaviorTree.CPP v4 XML (the Nav2 dialect) to and from ``TreeDoc``.

Reading uses expat directly so every element keeps its line number (errors say file:line),
and comments stay attached to the node they precede. Every attribute is kept as written (Nav2's
``server_timeout``, ``service_name`` ...): the builder decides what it means, so a round trip
loses nothing. ``<Action ID="Spin"/>`` (BT.CPP's explicit form) reads as ``<Spin/>`` and is
written back the same way. Writing gives one self-contained file with a ``TreeNodesModel`` for
every non-builtin node, which is what Groot2 needs to open it; a Nav2 node type is described by
Nav2's own ports so that BehaviorTree.CPP with Nav2's plugins accepts the file.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from typing import Any
from xml.parsers import expat
from xml.sax.saxutils import quoteattr

from behaviors.base import NavNode
from behaviors.registry import category
from executive import nav2_model
from executive.tree_spec import NodeSpec, PortValue, TreeDoc, TreeLoadError, TreeErrors, Where
from navcore.safe_read import MAX_INCLUDE_DEPTH, MAX_XML_DEPTH, parse_xml, read_bytes
from navcore.types import Pose2D

# Attributes of Nav2's BtActionNode/BtServiceNode and friends that have no meaning here; the
# builder accepts them on any node (kept as written, listed as ignored).
NAV2_IGNORED = frozenset({"server_name", "server_timeout", "is_recovery"})

# Tags Groot2 knows without a model (BT.CPP built-ins).
BTCPP_BUILTINS = frozenset(nav2_model.BTCPP_BUILTINS)
EXPLICIT_FORMS = ("Action", "Condition", "Control", "Decorator")


@dataclass
class _Elem:
    tag: str
    attrs: dict[str, str]
    line: int
    children: list["_Elem"] = field(default_factory=list)
    comments: list[str] = field(default_factory=list)


def _parse(file: str, text: str | None = None) -> _Elem:
    data = (read_bytes(file, what="tree file", error=TreeLoadError) if text is None
            else text.encode("utf-8"))
    parser = expat.ParserCreate()
    stack: list[_Elem] = []
    root: list[_Elem] = []
    pending: list[str] = []  # comments waiting for the element they precede

    def start(tag: str, attrs: dict[str, str]) -> None:
        if len(stack) >= MAX_XML_DEPTH:
            raise TreeLoadError(f"{file}:{parser.CurrentLineNumber}: elements nested more than "
                            f"{MAX_XML_DEPTH} deep (limit)")
        el = _Elem(tag, dict(attrs), parser.CurrentLineNumber, comments=list(pending))
        pending.clear()
        (stack[-1].children if stack else root).append(el)
        stack.append(el)

    def end(tag: str) -> None:
        stack.pop()

    def comment(text: str) -> None:
        pending.append(text.strip())

    parser.StartElementHandler = start
    parser.CommentHandler = comment
    parser.EndElementHandler = end
    parse_xml(parser, data, file, error=TreeLoadError)
    if not root:
        raise TreeLoadError(f"{file}:1: not valid XML: no element")
    return root[0]


def _node(el: _Elem, file: str) -> NodeSpec:
    attrs = dict(el.attrs)
    tag, form = el.tag, None
    if tag in EXPLICIT_FORMS and attrs.get("ID"):
        tag, form = attrs.pop("ID"), el.tag
    spec = NodeSpec(type=tag, where=Where(file, el.line), form=form, comments=el.comments)
    for k, v in attrs.items():
        if k == "name":
            spec.name = v
        else:
            spec.ports[k] = PortValue(v, spec.where)
    if tag in ("SubTree", "SubTreePlus"):  # SubTreePlus: BT.CPP 3's remapping SubTree (Humble)
        spec.type = "SubTree"
        spec.form = "SubTreePlus" if tag == "SubTreePlus" else form
        spec.take_subtree_fields("ID")
    spec.children = [_node(c, file) for c in el.children]
    spec.has_children_key = bool(el.children)
    return spec


def read_xml(path: str | os.PathLike, _stack: tuple[str, ...] = (),
             text: str | None = None) -> TreeDoc:
    """Parse a BT.CPP v4 XML file or ``text`` (and its ``<include path=.../>`` files) into a
    TreeDoc."""
    file = str(path)
    real = os.path.realpath(file)
    if real in _stack:
        raise TreeLoadError(f"{file}:1: include cycle: "
                        + " -> ".join(os.path.basename(s) for s in (*_stack, real)))
    if len(_stack) >= MAX_INCLUDE_DEPTH:
        raise TreeLoadError(f"{file}:1: includes nested more than {MAX_INCLUDE_DEPTH} files deep "
                        f"(limit)")
    root = _parse(file, text)
    if root.tag != "root":
        raise TreeLoadError(f"{file}:{root.line}: the top element must be <root>, not <{root.tag}>")
    distro = root.attrs.get("nav2_distro")
    if distro is not None:
        try:
            distro = nav2_model.check_distro(distro)
        except ValueError as e:
            raise TreeLoadError(f"{file}:{root.line}: <root nav2_distro>: {e}") from None
    doc = TreeDoc(main_tree=root.attrs.get("main_tree_to_execute"), trees={}, tree_where={},
                  source=file, from_text=True, nav2_distro=distro,
                  main_key="main_tree_to_execute", comments=root.comments)
    doc.btcpp_format = root.attrs.get("BTCPP_format")
    errors: list[TreeLoadError] = []  # reported together, as the builder's
    for el in root.children:
        where = Where(file, el.line)
        if el.tag == "BehaviorTree":
            tid = el.attrs.get("ID")
            if not tid:
                errors.append(TreeLoadError(f"{where}: <BehaviorTree> needs an ID"))
            elif len(el.children) != 1:
                errors.append(TreeLoadError(f"{where}: <BehaviorTree ID='{tid}'> must hold exactly "
                                        f"one root node, has {len(el.children)}"))
            elif tid in doc.trees:
                errors.append(TreeLoadError(f"{where}: tree '{tid}' is also defined at "
                                        f"{doc.tree_where[tid]}"))
            else:
                doc.trees[tid] = _node(el.children[0], file)
                doc.trees[tid].comments[:0] = el.comments
                doc.tree_where[tid] = where
        elif el.tag.lower() in ("include", "import"):
            src = el.attrs.get("path") or el.attrs.get("file") or el.attrs.get("src")
            if not src:
                errors.append(TreeLoadError(f"{where}: <{el.tag}> needs a 'path' attribute"))
                continue
            doc.include(src, where, lambda target: read_xml(target, (*_stack, real)))
        elif el.tag == "TreeNodesModel":
            continue
        else:
            errors.append(TreeLoadError(f"{where}: unexpected <{el.tag}> under <root>"))
    if errors:
        raise TreeErrors(errors) if len(errors) > 1 else errors[0]
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


def _comment(text: str) -> str:
    return "<!-- " + text.replace("--", "- -") + " -->"


def _write_node(spec: NodeSpec, indent: int, out: list[str]) -> None:
    pad = "  " * indent
    out.extend(pad + _comment(c) for c in spec.comments)
    attrs = []
    tag = spec.type
    if spec.type == "SubTree":
        attrs.append(f"ID={quoteattr(spec.subtree_id or '')}")
    elif spec.form in EXPLICIT_FORMS:
        tag = spec.form
        attrs.append(f"ID={quoteattr(spec.type)}")
    if spec.name:
        attrs.append(f"name={quoteattr(spec.name)}")
    if spec.type == "SubTree" and spec.autoremap:
        attrs.append('_autoremap="true"')
    for port, pv in spec.ports.items():
        text = pv.text if pv.text is not None else format_value(pv.raw)
        attrs.append(f"{port}={quoteattr(text)}")
    head = f"{pad}<{tag}" + "".join(" " + a for a in attrs)
    if not spec.children:
        out.append(head + "/>")
        return
    out.append(head + ">")
    for c in spec.children:
        _write_node(c, indent + 1, out)
    out.append(f"{pad}</{tag}>")


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


def _nav2_model_entry(node_type: str, distro: str | None) -> list[str] | None:
    """TreeNodesModel lines of a Nav2 node type with Nav2's own ports, None if not Nav2's."""
    cat = nav2_model.category(node_type)
    ports = nav2_model.ports(node_type, distro or nav2_model.DISTROS[-1])
    if cat is None or ports is None:
        return None
    lines = [f"    <{cat} ID={quoteattr(node_type)}>"]
    names = {"in": "input_port", "ou": "output_port", "io": "inout_port"}
    for pname, (direction, ptype, default) in ports.items():
        extra = (f" type={quoteattr(ptype)}" if ptype else "") + \
            (f" default={quoteattr(default)}" if default is not None else "")
        lines.append(f"      <{names[direction]} name={quoteattr(pname)}{extra}/>")
    lines.append(f"    </{cat}>")
    return lines


def write_xml(doc: TreeDoc, main_tree: str, classes: dict[str, type[NavNode]],
              distro: str | None = None) -> str:
    """BT.CPP v4 XML of every tree in ``doc`` plus a TreeNodesModel of the custom nodes.

    ``distro`` (the Nav2 distribution the tree follows; None: navbt's own) is written as
    ``nav2_distro`` so that the file keeps its semantics when read back (BT.CPP ignores the
    attribute); Nav2 node types are modelled with that distribution's ports.
    """
    root_attrs = f'BTCPP_format="4" main_tree_to_execute={quoteattr(main_tree)}'
    root_attrs += f" nav2_distro={quoteattr(distro or nav2_model.NAVBT)}"
    out = ['<?xml version="1.0" encoding="UTF-8"?>']
    out.extend(_comment(c) for c in doc.comments)
    out.append(f"<root {root_attrs}>")
    for tid, spec in doc.trees.items():
        out.append(f"  <BehaviorTree ID={quoteattr(tid)}>")
        _write_node(spec, 2, out)
        out.append("  </BehaviorTree>")
    out.append("  <TreeNodesModel>")
    for t in _used_types(doc):
        cls = classes.get(t)
        if t in BTCPP_BUILTINS:
            continue
        nav2 = _nav2_model_entry(t, distro)
        if nav2 is not None:
            out.extend(nav2)
            continue
        if cls is None:
            continue
        out.extend(model_entry(cls))
    out.append("  </TreeNodesModel>")
    out.append("</root>")
    return "\n".join(out) + "\n"


def model_entry(cls: type[NavNode]) -> list[str]:
    """TreeNodesModel lines of a navbt node class (its ports, defaults and descriptions)."""
    t = cls.__name__
    out = [f"    <{category(cls)} ID={quoteattr(t)}>"]
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
    return out


def groot_palette(classes: dict[str, type[NavNode]]) -> str:
    """A Groot2 palette: a BT.CPP 4 file with only a TreeNodesModel of every navbt node type
    (BT.CPP built-ins excluded: Groot2 knows them)."""
    out = ['<?xml version="1.0" encoding="UTF-8"?>', '<root BTCPP_format="4">',
           "  <TreeNodesModel>"]
    for t in sorted(classes):
        if t not in BTCPP_BUILTINS:
            out.extend(model_entry(classes[t]))
    out += ["  </TreeNodesModel>", "</root>"]
    return "\n".join(out) + "\n"
