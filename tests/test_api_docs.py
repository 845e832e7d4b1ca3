"""docs/api.md: every Python example on the page runs, in order, in one session."""

from __future__ import annotations

import os
import re

import py_trees.ports

HERE = os.path.dirname(os.path.abspath(__file__))
DOC = os.path.join(os.path.dirname(HERE), "docs", "api.md")


def python_blocks(text: str) -> list[tuple[int, str]]:
    """(line, code) of every ```python block."""
    out = []
    for m in re.finditer(r"^```python\n(.*?)^```", text, re.S | re.M):
        out.append((text.count("\n", 0, m.start()) + 2, m.group(1)))
    return out


def test_api_md_examples_run(capsys):
    with open(DOC, encoding="utf-8") as f:
        blocks = python_blocks(f.read())
    assert len(blocks) >= 5   # simulator, own robot, own node, goal replaced, cancel
    session: dict = {"__name__": "api_md"}
    try:
        for line, code in blocks:
            # compiled with the doc's name and line numbers: a failure points into docs/api.md
            exec(compile("\n" * (line - 1) + code, DOC, "exec"), session)
    finally:
        # the page's own nodes leave the process-wide node catalogue with the page (py_trees
        # has no unregister call): later tests list the shipped nodes only
        for tag, cls in py_trees.ports.get_ports_registry().items():
            if cls.__module__ == session["__name__"]:
                del py_trees.ports._REGISTRY[tag]
    printed = capsys.readouterr().out
    assert printed.count("succeeded") >= 3 and "canceled" in printed
