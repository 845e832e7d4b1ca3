"""Tree dumps: unicode text with statuses, DOT, and SVG/PNG through a ``dot``-compatible renderer.

SVG/PNG use a system graphviz ``dot`` when present, else the ``graphviz-pure`` command that the
package depends on (a pip-installed renderer taking dot's ``-Tsvg``/``-Tpng``), so rendering works
after a plain ``pip install``.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from typing import Sequence

import py_trees

FORMATS = ("txt", "dot", "svg", "png")

_STATUS_MARK = {"SUCCESS": "\u2714", "FAILURE": "\u2718", "RUNNING": "*", "INVALID": "-"}
_STATUS_COLOUR = {"SUCCESS": "green", "FAILURE": "red", "RUNNING": "blue"}


class RenderError(RuntimeError):
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


def tree_dot(root: py_trees.behaviour.Behaviour, with_status: bool = False) -> str:
    """DOT source of the tree (py_trees' ``dot_tree`` shapes; statuses as coloured outlines)."""
    graph = py_trees.display.dot_tree(root, with_blackboard_variables=False)
    if with_status:
        by_name = {n.name: n for n in root.iterate()}
        for gnode in graph.get_nodes():
            name = gnode.get_name().strip('"')
            node = by_name.get(name)
            if node is not None and node.status.name in _STATUS_COLOUR:
                gnode.set("color", _STATUS_COLOUR[node.status.name])
                gnode.set("penwidth", "3")
    return graph.to_string()


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


def render_tree(root: py_trees.behaviour.Behaviour, fmt: str, with_status: bool = False) -> bytes:
    """The tree in one of ``FORMATS`` as bytes (text formats UTF-8 encoded)."""
    if fmt == "txt":
        return (tree_text(root, show_status=with_status) + "\n").encode("utf-8")
    if fmt == "dot":
        return tree_dot(root, with_status).encode("utf-8")
    if fmt in ("svg", "png"):
        return render_dot(tree_dot(root, with_status), fmt)
    raise RenderError(f"render: unknown format {fmt!r}; choose one of {', '.join(FORMATS)}")
