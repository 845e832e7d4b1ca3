"""Where the executive and the CLI meet the tree loader (``executive.tree_loader``).

Everything else loads trees through ``load_tree_file`` and catches ``TreeLoadError``: one error
type for "this tree file cannot be used", whatever stage (reading, parsing, building) failed.
"""

from __future__ import annotations

import os

import py_trees

from executive import tree_loader
from executive.tree_spec import TreeError


class TreeLoadError(ValueError):
    """A tree file could not be loaded; the message names the file, line and node."""


def load_tree_file(path: str | os.PathLike, namespace: str = "/mission",
                   nav2_distro: str | None = None, port_defaults: dict | None = None
                   ) -> py_trees.trees.BehaviourTree:
    """Load a YAML or BT.CPP XML tree with its blackboard keys under ``namespace``;
    ``port_defaults`` (node type -> {port: value}) fills ports the tree leaves unset."""
    return load_loaded(path, namespace, nav2_distro, port_defaults).tree


def load_loaded(path: str | os.PathLike, namespace: str = "/mission",
                nav2_distro: str | None = None, port_defaults: dict | None = None
                ) -> tree_loader.LoadedTree:
    """Like ``load_tree_file`` but the whole ``LoadedTree`` (distribution, ignored attributes);
    a TreeLoadError lists every problem of the file, one per line."""
    path = str(path)
    if not os.path.exists(path):
        raise TreeLoadError(f"{path}: no such tree file")
    try:
        return tree_loader.load_any(path, namespace=namespace, nav2_distro=nav2_distro,
                                    port_defaults=port_defaults)
    except TreeError as e:
        raise TreeLoadError(str(e)) from None
    except (OSError, UnicodeDecodeError) as e:
        raise TreeLoadError(f"{path}: cannot read tree ({e})") from None


def convert_tree_file(src: str, dst_format: str, nav2_distro: str | None = None) -> str:
    """The text of ``src`` converted to ``xml`` (BT.CPP v4) or ``yaml``."""
    if not os.path.exists(src):
        raise TreeLoadError(f"{src}: no such tree file")
    try:
        loaded = tree_loader.load_any(src, namespace="/convert", nav2_distro=nav2_distro)
        return tree_loader.to_xml(loaded) if dst_format == "xml" else tree_loader.to_yaml(loaded)
    except TreeError as e:
        raise TreeLoadError(str(e)) from None


def shipped_tree(name: str) -> str:
    """Path of a tree shipped in ``trees/`` (``move_base`` -> .../trees/move_base.yaml)."""
    try:
        return str(tree_loader.shipped_tree(name))
    except TreeError as e:
        raise TreeLoadError(str(e)) from None
