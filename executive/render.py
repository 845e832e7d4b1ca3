"""Tree dumps: unicode text with statuses, DOT, and SVG/PNG through a ``dot``-compatible renderer.

The DOT is our own (not py_trees' ``dot_tree``, which draws every node as the same grey shape
titled with a default name): a shape and colour per node kind (control, decorator, action,
condition), subtrees as framed clusters (or one folder node when collapsed), the type above the
instance name when they differ, the ports on request, a legend and the tree's name as title.
A run's picture adds, per node, how often it ticked, succeeded and failed and how long it was
RUNNING, fades nodes that never ticked, and draws the path to the last failed leaf in red.

SVG/PNG use a system graphviz ``dot`` when present, else the ``graphviz-pure`` command that the
package depends on (a pip-installed renderer taking dot's ``-Tsvg``/``-Tpng``), so rendering works
after a plain ``pip install``.
"""

from __future__ import annotations

import html
import os
import re
import shutil
import subprocess
import sys
from dataclasses import dataclass
from typing import Any, Iterable, Mapping, Sequence

import py_trees

from executive.errors import ExecutiveError
from executive.recorder import walk

FORMATS = ("txt", "dot", "svg", "png")

_STATUS_MARK = {"SUCCESS": "\u2714", "FAILURE": "\u2718", "RUNNING": "*", "INVALID": "-"}
# Groot2's convention: running orange, success green, failure red
STATUS_COLOUR = {"SUCCESS": "#2e9d3a", "FAILURE": "#d62728", "RUNNING": "#f28e00"}


@dataclass(frozen=True)
class KindStyle:
    shape: str
    style: str
    fill: str
    border: str


# One look per node kind, so the kind reads at a glance (as in Groot2's palette).
KIND_STYLE: dict[str, KindStyle] = {
    "control": KindStyle("box", "rounded,filled", "#b7d3f2", "#2f5f98"),
    "decorator": KindStyle("hexagon", "filled", "#dcc6f3", "#6a3d9a"),
    "action": KindStyle("box", "filled", "#c9ecc1", "#2e7d32"),
    "condition": KindStyle("ellipse", "filled", "#fbe9a6", "#9a7b00"),
    "subtree": KindStyle("folder", "filled", "#e0e0e0", "#555555"),
}
_FADED_FILL = "#f4f4f4"

# control symbols: the shape of the semantics, as in BT.CPP's and Groot's pictures; the PNG
# renderer's font has no glyph for the arrows of circles, so PNG gets ASCII stand-ins
_CONTROL_SYMBOL = (("Parallel", "\u21c9", "||"), ("Sequence", "\u2192", "\u2192"),
                   ("Fallback", "?", "?"), ("Selector", "?", "?"),
                   ("RoundRobin", "\u21bb", "(o)"), ("Recovery", "\u21ba", "<-"))
_PRIVATE_KEY = re.compile(r"_[0-9a-f]{8}-[0-9a-f]{4}-")


@dataclass(frozen=True)
class NodeStats:
    """What one node did during a run (see ``recorder.NodeStatsVisitor``)."""

    ticks: int = 0
    successes: int = 0
    failures: int = 0
    running_s: float = 0.0


class RenderError(ExecutiveError, RuntimeError):
    """No renderer available, or the renderer rejected the graph."""


def tree_text(root: py_trees.behaviour.Behaviour, show_status: bool = True) -> str:
    """The tree as unicode text (py_trees' own layout), with each node's status."""
    return py_trees.display.unicode_tree(root, show_status=show_status)


def table_text(nodes: Sequence[Sequence], statuses: Sequence[str] | None = None) -> str:
    """Text of a recorded node table (``[name, type, depth]`` rows), e.g. for ``replay``."""
    lines = []
    for i, (name, kind, depth) in enumerate(nodes):
        mark = ""
        if statuses is not None:
            s = statuses[i]
            mark = f" [{_STATUS_MARK.get(s, '?')}] {s}" if s != "INVALID" else " [-]"
        label = name if name == kind else f"{name} ({kind})"
        lines.append("    " * depth + ("--> " if depth else "") + label + mark)
    return "\n".join(lines)


def node_kind(node: py_trees.behaviour.Behaviour) -> str:
    """``control``, ``decorator``, ``condition`` or ``action``."""
    if isinstance(node, py_trees.composites.Composite):
        return "control"
    if isinstance(node, py_trees.decorators.Decorator):
        return "decorator"
    category = getattr(type(node), "CATEGORY", "Action")
    return "condition" if category == "Condition" else "action"


def subtree_name(node: py_trees.behaviour.Behaviour,
                 parent: py_trees.behaviour.Behaviour | None) -> str | None:
    """The SubTree instance ``node`` is the root of, or None.

    The loader gives each SubTree instance its own blackboard scope (``<parent scope>/<name>``),
    so a node whose scope is one level below its parent's starts a subtree."""
    ns = getattr(node, "namespace", None)
    pns = getattr(parent, "namespace", None) if parent is not None else None
    if not ns or not pns or ns == pns:
        return None
    prefix = pns.rstrip("/") + "/"
    if not ns.startswith(prefix):
        return None
    return ns[len(prefix):].split("/", 1)[0]


def _short_key(key: str, root_ns: str) -> str:
    prefix = root_ns.rstrip("/") + "/"
    return key[len(prefix):] if key.startswith(prefix) else key


def _value_text(v: Any) -> str:
    if isinstance(v, float):
        return f"{v:g}"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{k}: {_value_text(x)}" for k, x in v.items()) + "}"
    text = str(v)
    return text if len(text) <= 40 else text[:37] + "..."


def port_lines(node: py_trees.behaviour.Behaviour, root_ns: str) -> list[str]:
    """``port: value`` (constants other than the declared default) and ``port: {key}`` /
    ``port -> {key}`` (blackboard inputs / outputs) of a navbt node."""
    literals = getattr(node, "_literals", None)
    keys = getattr(node, "_keys", None)
    if literals is None or keys is None:
        return []
    inputs = node.input_ports()
    outputs = node.output_ports()
    lines = []
    for port, value in literals.items():
        info = inputs.get(port)
        if info is not None and info.has_default and info.default_value == value:
            continue
        lines.append(f"{port}: {_value_text(value)}")
    for port, key in keys.items():
        if _PRIVATE_KEY.search(key):
            continue  # unwired and private: nothing else can read or write it
        arrow = " \u2192 " if port in outputs and port not in inputs else ": "
        lines.append(f"{port}{arrow}{{{_short_key(key, root_ns)}}}")
    return lines


def _symbol(type_name: str, ascii_only: bool) -> str:
    for word, sym, plain in _CONTROL_SYMBOL:
        if word in type_name:
            return (plain if ascii_only else sym) + " "
    return ""


def _stats_text(s: NodeStats) -> str:
    parts = [f"{s.ticks} tick" + ("" if s.ticks == 1 else "s")]
    if s.successes:
        parts.append(f"{s.successes} ok")
    if s.failures:
        parts.append(f"{s.failures} failed")
    if s.running_s > 0:
        parts.append(f"{s.running_s:.1f} s running")
    return ", ".join(parts)


def _label(node: py_trees.behaviour.Behaviour, kind: str, ports: list[str],
           stats: NodeStats | None, ascii_only: bool) -> str:
    type_name = type(node).__name__
    head = _symbol(type_name, ascii_only) if kind == "control" else ""
    rows = [f'<tr><td><b>{html.escape(head + type_name)}</b></td></tr>']
    if node.name != type_name:
        rows.append(f'<tr><td><font point-size="9">{html.escape(node.name)}</font></td></tr>')
    for line in ports:
        rows.append(f'<tr><td align="left"><font point-size="8" color="#333333">'
                    f'{html.escape(line)}</font></td></tr>')
    if stats is not None:
        rows.append(f'<tr><td><font point-size="8" color="#000066">'
                    f'{html.escape(_stats_text(stats))}</font></td></tr>')
    return ('<<table border="0" cellborder="0" cellspacing="0" cellpadding="1">'
            + "".join(rows) + "</table>>")


def _legend(title: str, with_status: bool, annotated: bool) -> str:
    cells = []
    for kind, st in KIND_STYLE.items():
        cells.append(f'<td bgcolor="{st.fill}" border="1" color="{st.border}">'
                     f'<font point-size="9">{kind}</font></td>')
    rows = [f'<tr><td colspan="{len(cells)}"><font point-size="16"><b>'
            f'{html.escape(title)}</b></font></td></tr>' if title else "",
            "<tr>" + "".join(cells) + "</tr>"]
    if with_status or annotated:
        st_cells = [f'<td border="1" color="{c}"><font point-size="9" color="{c}">{s}</font></td>'
                    for s, c in STATUS_COLOUR.items()]
        extra = []
        if annotated:
            extra = ['<td><font point-size="9" color="#d62728">red: last failure'
                     '</font></td>',
                     f'<td bgcolor="{_FADED_FILL}" border="1" color="#aaaaaa">'
                     '<font point-size="9" color="#888888">never ticked</font></td>']
        rows.append("<tr>" + "".join(st_cells + extra) + "</tr>")
    return ('<<table border="0" cellborder="0" cellspacing="3">' + "".join(rows) + "</table>>")


def tree_dot(root: py_trees.behaviour.Behaviour, with_status: bool = False, *,
             ports: bool = False, title: str = "", collapse: Iterable[str] = (),
             stats: Sequence[NodeStats] | None = None,
             last_failure: Sequence[int] | None = None,
             legend: bool = True, ascii_only: bool = False) -> str:
    """DOT source of the tree.

    ``collapse``: SubTree instance names drawn as one node (``"*"``: every subtree).
    ``stats``: per node in pre-order (``recorder.walk``), from a run; ``last_failure``: the
    pre-order indices of the last failure that propagated (from where it was caught down to the
    failed leaf), drawn in red. ``ascii_only``: no symbols the PNG renderer's font lacks."""
    collapse = set(collapse)
    root_ns = getattr(root, "namespace", "/") or "/"
    red = set(last_failure or ())
    out = ["digraph tree {",
           '  graph [rankdir=TB ordering=out nodesep=0.25 ranksep=0.45 fontname="Helvetica" '
           'labelloc=t labeljust=l];',
           '  node [fontname="Helvetica" fontsize=11 margin="0.08,0.04"];',
           '  edge [arrowhead=none color="#555555"];']
    if legend or title:
        out.append(f"  label={_legend(title, with_status, stats is not None)};")
    edges: list[str] = []
    index = {id(n): i for i, (n, _) in enumerate(walk(root))}
    cluster_n = [0]

    def emit(node: py_trees.behaviour.Behaviour, indent: str) -> None:
        i = index[id(node)]
        kind = node_kind(node)
        st = KIND_STYLE[kind]
        s = stats[i] if stats is not None and i < len(stats) else None
        attrs = [f"shape={st.shape}", f'style="{st.style}"', f'fillcolor="{st.fill}"',
                 f'color="{st.border}"']
        if s is not None and s.ticks == 0:
            attrs[1:4] = ['style="%s,dashed"' % st.style, f'fillcolor="{_FADED_FILL}"',
                          'color="#aaaaaa"']
            attrs.append('fontcolor="#888888"')
        status = node.status.name
        if with_status and status in STATUS_COLOUR:
            attrs[3] = f'color="{STATUS_COLOUR[status]}"'
            attrs.append("penwidth=3")
        if i in red:
            attrs[3] = f'color="{STATUS_COLOUR["FAILURE"]}"'
            attrs.append("penwidth=3")
        lines = port_lines(node, root_ns) if ports else []
        out.append(f"{indent}n{i} [{' '.join(attrs)} label={_label(node, kind, lines, s, ascii_only)}];")
        for child in getattr(node, "children", []) or []:
            j = index[id(child)]
            edge = f"  n{i} -> n{j}"
            if i in red and j in red:
                edge += f' [color="{STATUS_COLOUR["FAILURE"]}" penwidth=2.5]'
            edges.append(edge + ";")
            sub = subtree_name(child, node)
            if sub is None:
                emit(child, indent)
            elif sub in collapse or "*" in collapse:
                size = sum(1 for _ in walk(child))
                cst = KIND_STYLE["subtree"]
                out.append(f'{indent}n{j} [shape={cst.shape} style="{cst.style}" '
                           f'fillcolor="{cst.fill}" color="{cst.border}" label=<<b>SubTree</b>'
                           f'<br/>{html.escape(sub)}<br/><font point-size="8">{size} nodes'
                           f'</font>>];')
            else:
                cluster_n[0] += 1
                out.append(f"{indent}subgraph cluster_{cluster_n[0]} {{")
                out.append(f'{indent}  label=<<font point-size="10"><b>SubTree</b> '
                           f'{html.escape(sub)}</font>>; style="dashed,rounded"; '
                           f'color="#777777"; labeljust=l;')
                emit(child, indent + "  ")
                out.append(f"{indent}}}")

    emit(root, "  ")
    out.extend(edges)
    out.append("}")
    return "\n".join(out) + "\n"


def find_dot() -> list[str]:
    """The renderer command: system ``dot`` first, then ``graphviz-pure`` (also beside python)."""
    exe = shutil.which("dot")
    if exe:
        return [exe]
    exe = shutil.which("graphviz-pure")
    if exe:
        return [exe]
    beside = os.path.join(os.path.dirname(sys.executable), "graphviz-pure")
    if os.path.exists(beside):
        return [beside]
    raise RenderError("no graphviz renderer: install graphviz (dot) or `pip install graphviz-pure`")


def render_dot(dot_source: str, fmt: str) -> bytes:
    """Render DOT source to ``svg`` or ``png`` bytes."""
    if fmt not in ("svg", "png"):
        raise RenderError(f"render: unsupported format {fmt!r} (svg or png)")
    cmd = find_dot() + [f"-T{fmt}"]
    proc = subprocess.run(cmd, input=dot_source.encode("utf-8"), capture_output=True,
                          timeout=60)
    if proc.returncode != 0 or not proc.stdout:
        err = proc.stderr.decode("utf-8", "replace").strip().splitlines()
        raise RenderError(f"{os.path.basename(cmd[0])} -T{fmt} failed: "
                          f"{err[-1] if err else 'no output'}")
    return proc.stdout


def render_tree(root: py_trees.behaviour.Behaviour, fmt: str, with_status: bool = False,
                **options: Any) -> bytes:
    """The tree in one of ``FORMATS`` as bytes (text formats UTF-8 encoded); ``options`` go to
    ``tree_dot`` (ports, title, collapse, stats, last_failure)."""
    if fmt == "txt":
        return (tree_text(root, show_status=with_status) + "\n").encode("utf-8")
    if fmt == "dot":
        return tree_dot(root, with_status, **options).encode("utf-8")
    if fmt in ("svg", "png"):
        return render_dot(tree_dot(root, with_status, ascii_only=fmt == "png", **options), fmt)
    raise RenderError(f"render: unknown format {fmt!r}; choose one of {', '.join(FORMATS)}")


def stats_from_footer(footer: Mapping[str, Any] | None
                      ) -> tuple[list[NodeStats] | None, list[int] | None]:
    """Node statistics and the last failure chain as the recorder wrote them in the footer."""
    if not footer or "node_stats" not in footer:
        return None, None
    stats = [NodeStats(int(a), int(b), int(c), float(d)) for a, b, c, d in footer["node_stats"]]
    return stats, footer.get("last_failure")
