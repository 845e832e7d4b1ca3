"""Where the executive and the CLI meet the tree loader (``executive.tree_loader``).

Everything else loads trees through ``load_tree_file`` (or ``load_tree_text``) and catches
``TreeLoadError`` (the loader's own, from ``executive.tree_spec``): one error type for "this
tree cannot be used", whatever stage (reading, parsing, building) failed (``file:line: node:
what``, every problem of the file, one per line).
"""

from __future__ import annotations

import os

from executive import tree_loader
from executive.tree_loader import LoadedTree
from executive.tree_spec import TreeLoadError


def load_tree_file(path: str | os.PathLike, namespace: str = "/mission",
                   nav2_distro: str | None = None, port_defaults: dict | None = None
                   ) -> LoadedTree:
    """Load a YAML or BT.CPP XML tree with its blackboard keys under ``namespace``: the tree
    handle (py_trees root and manager, distribution, ignored attributes). ``port_defaults``
    (node type -> {port: value}) fills ports the tree leaves unset."""
    path = str(path)
    if not os.path.exists(path):
        raise TreeLoadError(f"{path}: no such tree file")
    try:
        return tree_loader.load_any(path, namespace=namespace, nav2_distro=nav2_distro,
                                    port_defaults=port_defaults)
    except (OSError, UnicodeDecodeError) as e:
        raise TreeLoadError(f"{path}: cannot read tree ({e})") from None


def load_tree_text(text: str, namespace: str = "/mission", name: str = "<text>") -> LoadedTree:
    """Load a tree from YAML or BT.CPP XML text (errors name ``name`` as the file)."""
    return tree_loader.load_text(text, namespace=namespace, name=name)


def convert_tree_file(src: str, dst_format: str, nav2_distro: str | None = None) -> str:
    """The text of ``src`` converted to ``xml`` (BT.CPP v4) or ``yaml``."""
    if not os.path.exists(src):
        raise TreeLoadError(f"{src}: no such tree file")
    loaded = tree_loader.load_any(src, namespace="/convert", nav2_distro=nav2_distro)
    return tree_loader.to_xml(loaded) if dst_format == "xml" else tree_loader.to_yaml(loaded)


def shipped_tree(name: str) -> str:
    """Path of a tree shipped in ``trees/`` (``move_base`` -> .../trees/move_base.yaml)."""
    return str(tree_loader.shipped_tree(name))
