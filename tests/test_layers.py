"""Imports only point downward: executive -> behaviors -> navcore; executive -> hw -> navcore.

Every module of navcore/, hw/ and behaviors/ is parsed (not imported) and every import in it is
checked, at module level and inside functions and classes alike, as is an
``importlib.import_module`` / ``__import__`` whose name starts with a literal.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
OURS = ("navcore", "hw", "behaviors", "executive")
# What each layer must not import: the layers above it, and a sibling it does not sit on.
FORBIDDEN = {
    "navcore": {"hw", "behaviors", "executive"},
    "behaviors": {"hw", "executive"},
    "hw": {"behaviors", "executive"},
}


def _module_name(path: Path) -> str:
    parts = list(path.relative_to(ROOT).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def _resolve_relative(module: str | None, level: int, importer: str, is_package: bool) -> str:
    base = importer.split(".")
    # In a package's __init__ a level-1 import is relative to the package itself.
    drop = level - 1 if is_package else level
    base = base[: len(base) - drop] if drop else base
    return ".".join(base + ([module] if module else []))


def _literal_prefix(node: ast.expr) -> str | None:
    """The leading literal text of a string or f-string argument (the dotted module name)."""
    if isinstance(node, ast.Constant) and isinstance(node.value, str):
        return node.value
    if isinstance(node, ast.JoinedStr) and node.values and isinstance(node.values[0], ast.Constant):
        return str(node.values[0].value)
    return None


def imported_modules(source: str, importer: str, is_package: bool = False) -> list[tuple[int, str]]:
    """(line, dotted name) of every import in ``source``, wherever it sits in the module."""
    found: list[tuple[int, str]] = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import):
            found += [(node.lineno, alias.name) for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                found.append((node.lineno, _resolve_relative(node.module, node.level, importer,
                                                             is_package)))
            elif node.module:
                found.append((node.lineno, node.module))
        elif isinstance(node, ast.Call) and node.args:
            func = node.func
            name = func.attr if isinstance(func, ast.Attribute) else getattr(func, "id", None)
            if name in ("import_module", "__import__"):
                prefix = _literal_prefix(node.args[0])
                if prefix:
                    found.append((node.lineno, prefix))
    return found


def layer_violations(layer: str) -> list[str]:
    bad = FORBIDDEN[layer]
    out = []
    for path in sorted((ROOT / layer).rglob("*.py")):
        importer = _module_name(path)
        for line, name in imported_modules(path.read_text(encoding="utf-8"), importer,
                                           path.name == "__init__.py"):
            top = name.split(".")[0]
            if top in bad:
                out.append(f"{path.relative_to(ROOT)}:{line}: imports {name}")
    return out


@pytest.mark.parametrize("layer", sorted(FORBIDDEN))
def test_layer_imports_only_point_downward(layer: str) -> None:
    files = list((ROOT / layer).rglob("*.py"))
    assert len(files) > 3, f"no modules found under {ROOT / layer}"
    assert layer_violations(layer) == []


def test_checker_sees_imports_at_every_level() -> None:
    source = (
        "import numpy as np\n"
        "from hw.interfaces import BaseEvents\n"
        "def f():\n"
        "    import executive.api\n"
        "    from .. import world\n"
        "class C:\n"
        "    def m(self):\n"
        "        importlib.import_module(f'hw.sim.{name}')\n"
    )
    found = imported_modules(source, "behaviors.actions.spin")
    assert found == [(1, "numpy"), (2, "hw.interfaces"), (4, "executive.api"),
                     (5, "behaviors"), (8, "hw.sim.")]


def test_relative_imports_resolve_from_package_and_module() -> None:
    assert imported_modules("from . import x", "navcore.costmap", is_package=True) == [
        (1, "navcore.costmap")]
    assert imported_modules("from .grid import x", "navcore.costmap.layers") == [
        (1, "navcore.costmap.grid")]
    assert imported_modules("from ..types import x", "navcore.costmap.layers") == [
        (1, "navcore.types")]


def test_hw_interfaces_reexports_the_messages_of_navcore() -> None:
    import hw.interfaces
    import navcore.types

    assert hw.interfaces.BaseEvents is navcore.types.BaseEvents
    assert hw.interfaces.BatteryState is navcore.types.BatteryState
    assert hw.interfaces.BatteryState(voltage=12.1, percentage=0.5).charging is False
