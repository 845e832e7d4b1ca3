"""The catalogue of node types: name, category, ports (type, default, description), contract.

Generated from the port declarations (one source of truth), for ``mission nodes``, the docs'
node table and the Groot2 ``TreeNodesModel``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from behaviors.base import Control, DecoratorNode, NavNode, node_classes


@dataclass(frozen=True)
class PortDoc:
    name: str
    direction: str  # "input" | "output"
    type_name: str
    required: bool
    default: Any
    description: str
    default_key: str | None  # blackboard key used when the tree leaves the port unwired


@dataclass(frozen=True)
class NodeDoc:
    name: str
    category: str  # Action | Condition | Control | Decorator
    summary: str
    doc: str
    ports: tuple[PortDoc, ...]
    min_children: int
    max_children: int | None


def type_name(t: Any) -> str:
    return getattr(t, "__name__", str(t))


def category(cls: type[NavNode]) -> str:
    if issubclass(cls, Control):
        return "Control"
    if issubclass(cls, DecoratorNode):
        return "Decorator"
    return cls.CATEGORY


def describe(cls: type[NavNode]) -> NodeDoc:
    ports = []
    for direction, table in (("input", cls.input_ports()), ("output", cls.output_ports())):
        for pname, info in table.items():
            ports.append(PortDoc(pname, direction, type_name(info.data_type), info.required,
                                 info.default_value, info.description,
                                 cls.DEFAULT_KEYS.get(pname)))
    if issubclass(cls, Control):
        lo, hi = cls.MIN_CHILDREN, cls.MAX_CHILDREN
    elif issubclass(cls, DecoratorNode):
        lo, hi = 1, 1
    else:
        lo, hi = 0, 0
    doc = (cls.__doc__ or "").strip()
    summary = " ".join(doc.split("\n\n")[0].split()) if doc else ""
    return NodeDoc(cls.__name__, category(cls), summary, doc,
                   tuple(ports), lo, hi)


def catalogue() -> dict[str, NodeDoc]:
    """Every node type by name, sorted by category then name."""
    docs = [describe(cls) for cls in node_classes().values()]
    docs.sort(key=lambda d: (d.category, d.name))
    return {d.name: d for d in docs}


def format_catalogue(verbose: bool = False) -> str:
    """Plain-text listing for ``mission nodes``."""
    lines = []
    current = None
    for d in catalogue().values():
        if d.category != current:
            current = d.category
            lines.append(f"{current}s:")
        lines.append(f"  {d.name:28s} {d.summary}")
        if verbose:
            for p in d.ports:
                default = "" if p.default is None else f" = {p.default!r}"
                key = f" [{{{p.default_key}}}]" if p.default_key else ""
                lines.append(f"      {p.direction[:2]} {p.name}: {p.type_name}{default}{key}  "
                             f"{p.description}")
    return "\n".join(lines)


def _md(text: str) -> str:
    return text.replace("|", "\\|")


def markdown_catalogue() -> str:
    """The node reference of docs/trees.md (a test keeps the checked-in copy in step)."""
    out = []
    current = None
    for d in catalogue().values():
        if d.category != current:
            current = d.category
            out += [f"### {current}s", ""]
        out.append(f"**{d.name}**: {_md(d.summary)}")
        out.append("")
        if d.ports:
            out.append("| port | dir | type | default | meaning |")
            out.append("|---|---|---|---|---|")
            for p in d.ports:
                default = (f"`{{{p.default_key}}}`" if p.default_key else
                           "required" if p.required and p.default is None and p.direction == "input"
                           else "" if p.default is None else f"`{p.default!r}`")
                out.append(f"| `{p.name}` | {p.direction[:-3] if p.direction == 'output' else 'in'} "
                           f"| {p.type_name} | {default} | {_md(p.description)} |")
            out.append("")
    return "\n".join(out).rstrip() + "\n"


def update_docs(path: str = "docs/trees.md") -> bool:
    """Rewrite the node reference between the markers of ``path``; True if it changed."""
    start, end = "<!-- nodes:start -->\n", "<!-- nodes:end -->"
    with open(path, encoding="utf-8") as f:
        text = f.read()
    a, b = text.index(start) + len(start), text.index(end)
    new = text[:a] + markdown_catalogue() + text[b:]
    if new != text:
        with open(path, "w", encoding="utf-8") as f:
            f.write(new)
    return new != text


if __name__ == "__main__":  # python -m behaviors.registry [docs/trees.md]
    import sys
    print("updated" if update_docs(*sys.argv[1:2]) else "already in step")
