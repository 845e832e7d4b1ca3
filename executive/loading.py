"""One place where the executive meets the tree engineer's loader (``executive.tree_loader``).

Everything else in the executive and the CLI loads trees through ``load_tree_file`` and catches
``TreeLoadError``, so an API change in the loader is absorbed here.
"""

from __future__ import annotations

import os
from typing import Any

import py_trees


class TreeLoadError(ValueError):
    """A tree file could not be loaded; the message names the file, line and node."""


def _loader() -> Any:
    from executive import tree_loader  # the tree engineer's module
    return tree_loader


def _error_types() -> tuple[type[BaseException], ...]:
    mod = _loader()
    types: list[type[BaseException]] = [TreeLoadError]
    for name in ("TreeError", "TreeLoadError", "LoadError"):
        t = getattr(mod, name, None)
        if isinstance(t, type) and issubclass(t, BaseException):
            types.append(t)
    return tuple(types)


def load_tree_file(path: str | os.PathLike, namespace: str = "/mission"
                   ) -> py_trees.trees.BehaviourTree:
    """Load a YAML or BT.CPP XML tree with its blackboard keys under ``namespace``."""
    path = str(path)
    if not os.path.exists(path):
        raise TreeLoadError(f"{path}: no such tree file")
    mod = _loader()
    try:
        loaded = mod.load_any(path, namespace=namespace)
    except _error_types() as e:
        raise TreeLoadError(str(e)) from None
    except (OSError, UnicodeDecodeError) as e:
        raise TreeLoadError(f"{path}: cannot read tree ({e})") from None
    tree = loaded.tree if hasattr(loaded, "tree") else loaded
    if isinstance(tree, py_trees.behaviour.Behaviour):
        tree = py_trees.trees.BehaviourTree(tree)
    return tree


def convert_tree_file(src: str, dst_format: str) -> str:
    """The text of ``src`` converted to ``xml`` (BT.CPP v4) or ``yaml``."""
    mod = _loader()
    if not os.path.exists(src):
        raise TreeLoadError(f"{src}: no such tree file")
    try:
        loaded = mod.load_any(src, namespace="/convert")
        if dst_format == "xml":
            return mod.to_xml(loaded)
        to_yaml = getattr(mod, "to_yaml", None)
        if to_yaml is None:
            raise TreeLoadError(f"{src}: conversion to YAML is not supported by the tree loader")
        return to_yaml(loaded)
    except _error_types() as e:
        raise TreeLoadError(str(e)) from None


def shipped_tree(name: str) -> str:
    """Path of a tree shipped in ``trees/`` (``move_base`` -> .../trees/move_base.yaml)."""
    import trees
    base = os.path.dirname(os.path.abspath(trees.__file__))
    return os.path.join(base, name if name.endswith((".yaml", ".xml")) else name + ".yaml")
