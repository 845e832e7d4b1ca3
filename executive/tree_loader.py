"""Load behaviour trees from YAML (native) or BehaviorTree.CPP v4 XML, and export to XML.

>>> loaded = load_tree_file("trees/move_base.yaml", namespace="/mission_1")   # doctest: +SKIP
>>> loaded.setup(clock=clock, robot=robot, planners=..., controllers=..., ...)
>>> loaded.set("goal", Pose2D(5.0, 2.0, 0.0))
>>> cmd = loaded.tick()          # one control period; zero Twist if nothing wrote cmd_vel

Every blackboard key of the tree lives under ``namespace`` (two missions never share keys).
Errors are ``TreeLoadError`` with ``file:line: NodeType: what is wrong (did you mean 'x'?)``.
"""

from __future__ import annotations

import os
import re
from collections import deque
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import py_trees
from py_trees.common import Access, Status

from behaviors.base import namespaced, node_classes
from executive.tree_build import Builder
from executive.tree_spec import TreeDoc, TreeLoadError
from executive.tree_xml import NAV2_IGNORED, read_xml, write_xml
from executive.tree_yaml import read_yaml, write_yaml
from navcore.types import Twist

__all__ = ["LoadedTree", "TreeLoadError", "load_tree_file", "load_tree_text", "to_xml", "to_yaml",
           "shipped_tree", "SHIPPED_TREES", "TREES_DIR"]

_BLACKBOARD = py_trees.blackboard.Blackboard  # its class-level ``storage`` holds every key
TREES_DIR = Path(__file__).resolve().parent.parent / "trees"
SHIPPED_TREES = ("move_base", "nav2", "smach_recovery", "near_goal_reconfigure")

# Keys the shipped trees read or write; the executive may touch them through LoadedTree.
MISSION_KEYS = ("goal", "goals", "goal_update", "path", "cmd_vel", "compute_path_error_code",
                "compute_path_error_msg", "follow_path_error_code", "follow_path_error_msg",
                "spin_error_code", "backup_error_code", "drive_on_heading_error_code",
                "temporary_goal_error_code", "temporary_goal", "back_off_error_code",
                "pose_history", "set_parameters_error_msg")


@dataclass
class LoadedTree:
    """The tree handle: the py_trees root and manager, its blackboard namespace and where it
    came from (``doc`` None for a tree built in Python, see ``of``). The Executive drives a
    mission through this same handle."""

    root: py_trees.behaviour.Behaviour
    tree: py_trees.trees.BehaviourTree
    namespace: str
    source: str = "<python>"
    main_tree: str = ""
    doc: TreeDoc | None = None
    distro: str | None = None  # the Nav2 distribution whose semantics the tree follows
    ignored: tuple[str, ...] = ()  # Nav2 attributes kept as written but meaning nothing here

    @classmethod
    def of(cls, tree: py_trees.trees.BehaviourTree, namespace: str) -> LoadedTree:
        """The handle of a py_trees tree built in Python, its keys under ``namespace``."""
        return cls(root=tree.root, tree=tree, namespace=namespace.rstrip("/"),
                   main_tree=tree.root.name)

    def key(self, name: str) -> str:
        """Absolute blackboard key of a mission-level key (e.g. ``goal``)."""
        return namespaced(self.namespace, name)

    def _client(self) -> py_trees.blackboard.Client:
        client = getattr(self, "_bb", None)
        if client is None:
            client = py_trees.blackboard.Client(name=f"executive{self.namespace}",
                                                namespace=self.namespace)
            for k in MISSION_KEYS:
                client.register_key(key=k, access=Access.WRITE)
            self._bb = client
        return client

    def set(self, name: str, value: Any) -> None:
        """Write a mission-level blackboard key (``goal``, ``goals``, ...)."""
        self._register(name).set(name, value)

    def get(self, name: str, default: Any = None) -> Any:
        """Read a mission-level blackboard key, ``default`` if unset."""
        client = self._register(name)
        return client.get(name) if client.exists(name) else default

    def unset(self, name: str) -> None:
        self._register(name).unset(name)

    def _register(self, name: str) -> py_trees.blackboard.Client:
        client = self._client()
        if not client.is_registered(name):
            client.register_key(key=name, access=Access.WRITE)
        return client

    def setup(self, **components: Any) -> None:
        """``tree.setup(**components)``: the keys of behaviors/components.py."""
        self.tree.setup(**components)

    def restart(self) -> None:
        """Halt everything and forget per-navigation memory: call before a new goal."""
        self.tree.interrupt()

    def __post_init__(self) -> None:
        self._cmd_key = self.namespace + "/cmd_vel"

    def tick(self) -> Twist:
        """Tick once and return the ``cmd_vel`` written during this tick (zero if none)."""
        cmd = self.tick_command()
        return cmd if cmd is not None else Twist.zero()

    def tick_command(self) -> Twist | None:
        """Tick once; the ``cmd_vel`` written during this tick, None if nothing was (the
        executive's safety gate tells "no command" from a zero one)."""
        storage = _BLACKBOARD.storage
        key = self._cmd_key
        storage[key] = None   # direct: a client's access checks cost more than a small tick
        self.tree.tick()
        cmd = storage.get(key)
        return cmd if isinstance(cmd, Twist) else None

    @property
    def status(self) -> Status:
        return self.root.status

    def nodes(self) -> list[py_trees.behaviour.Behaviour]:
        return list(self.root.iterate())

    def to_xml(self) -> str:
        return to_xml(self)


# Runs a tick generator to its end without looking at what it yields (in C, keeping nothing).
_drain = deque(maxlen=0).extend


class LeanBehaviourTree(py_trees.trees.BehaviourTree):
    """py_trees' tree manager without its second whole-tree walk when no visitor needs it.

    ``BehaviourTree.tick`` iterates every node after the tick for "full" visitors even when
    there are none; at 20 Hz that walk is a large part of the tick overhead. Without visitors
    the root's tick generator is drained in C (``deque(maxlen=0)``); visitors see each node as
    it finishes its tick, with the status it has then, as in py_trees.
    """

    def tick(self, pre_tick_handler: Any = None, post_tick_handler: Any = None) -> None:
        if (pre_tick_handler is None and post_tick_handler is None and not self.visitors
                and not self.pre_tick_handlers and not self.post_tick_handlers):  # the usual
            _drain(self.root.tick())
            self.count += 1
            return
        if pre_tick_handler is not None:
            pre_tick_handler(self)
        for handler in self.pre_tick_handlers:
            handler(self)
        visitors = self.visitors
        if visitors:
            for visitor in visitors:
                visitor.initialise()
            ticking = [v for v in visitors if not v.full]
            for node in self.root.tick():
                for visitor in ticking:
                    node.visit(visitor)
            full = [v for v in visitors if v.full]
            if full:
                for node in self.root.iterate():
                    for visitor in full:
                        node.visit(visitor)
            for visitor in visitors:
                visitor.finalise()
        else:
            _drain(self.root.tick())
        for handler in self.post_tick_handlers:
            handler(self)
        if post_tick_handler is not None:
            post_tick_handler(self)
        self.count += 1

    def interrupt(self) -> None:
        """Halt the whole tree (py_trees' own ``interrupt`` only stops ``tick_tock``) and forget
        per-navigation memory (recovery list positions), as Nav2 does when a navigation ends:
        the next tick starts afresh."""
        super().interrupt()
        self.root.stop(Status.INVALID)
        for node in self.root.iterate():
            new_run = getattr(node, "new_run", None)
            if callable(new_run):
                new_run()


def _build(doc: TreeDoc, namespace: str, xml: bool, nav2_distro: str | None = None,
           port_defaults: dict | None = None) -> LoadedTree:
    if not re.fullmatch(r"(/[A-Za-z0-9_]+)+/?", namespace):
        raise TreeLoadError(f"{doc.source}:1: namespace must be an absolute name like '/mission_1' "
                        f"(letters, digits, '_'; a '.' would nest keys), got {namespace!r}")
    try:
        distro = doc.effective_distro(nav2_distro)
    except ValueError as e:
        raise TreeLoadError(f"{doc.source}:1: {e}") from None
    builder = Builder(doc, namespace.rstrip("/"), from_text=xml, ignored_ports=NAV2_IGNORED,
                      distro=distro, port_defaults=dict(port_defaults or {}))
    tid = builder.main_tree()
    root = builder.build(tid)
    return LoadedTree(root=root, tree=LeanBehaviourTree(root),
                      namespace=namespace.rstrip("/"), source=doc.source, main_tree=tid, doc=doc,
                      distro=distro, ignored=tuple(builder.ignored))


def load_tree_file(path: str | os.PathLike, namespace: str = "/mission",
                   nav2_distro: str | None = None, port_defaults: dict | None = None
                   ) -> LoadedTree:
    """Load a tree file (with its includes), validate it and build it under ``namespace``:
    BehaviorTree.CPP XML (Nav2 dialect) for a ``.xml`` file, navbt YAML otherwise.

    ``nav2_distro`` (humble, jazzy, kilted, main) overrides the distribution whose semantics
    apply (else the file's own ``nav2_distro``; else navbt's semantics for YAML, jazzy for XML,
    humble for a BT.CPP 3 file, one without ``BTCPP_format``). ``port_defaults`` (node type ->
    {port: value}) fills ports the tree leaves unset."""
    path = str(path)
    if not os.path.exists(path):
        raise TreeLoadError(f"{path}: no such tree file")
    xml = path.lower().endswith(".xml")
    try:
        doc = read_xml(path) if xml else read_yaml(path)
    except (OSError, UnicodeDecodeError) as e:
        raise TreeLoadError(f"{path}: cannot read tree ({e})") from None
    return _build(doc, namespace, xml, nav2_distro=nav2_distro, port_defaults=port_defaults)


def _doc_and_main(tree: LoadedTree | TreeDoc, main_tree: str | None
                  ) -> tuple[TreeDoc, str, str | None]:
    if isinstance(tree, LoadedTree):
        return _doc_of(tree), main_tree or tree.main_tree, tree.distro
    main = main_tree or tree.main_tree or next(iter(tree.trees))
    return tree, main, tree.effective_distro()


def load_tree_text(text: str, namespace: str = "/mission", name: str = "<text>") -> LoadedTree:
    """A tree from YAML or BT.CPP XML text (XML when it starts with ``<``); errors and relative
    includes name ``name`` as the file."""
    xml = text.lstrip().startswith("<")
    doc = read_xml(name, text=text) if xml else read_yaml(name, text=text)
    return _build(doc, namespace, xml)


def to_xml(tree: LoadedTree | TreeDoc, main_tree: str | None = None) -> str:
    """BehaviorTree.CPP v4 XML (one file, with TreeNodesModel) that Groot2 opens; every
    attribute and comment as written, and ``nav2_distro`` when the tree follows one."""
    doc, main, distro = _doc_and_main(tree, main_tree)
    return write_xml(doc, main, node_classes(), distro)


def to_yaml(tree: LoadedTree | TreeDoc, main_tree: str | None = None) -> str:
    """navbt YAML of a loaded tree (e.g. one read from Nav2 XML): every attribute as written,
    comments as YAML comments, and ``nav2_distro`` when the tree follows one."""
    doc, main, distro = _doc_and_main(tree, main_tree)
    return write_yaml(doc, main, node_classes(), distro)


def _doc_of(tree: LoadedTree) -> TreeDoc:
    if tree.doc is None:
        raise TreeLoadError(f"{tree.source}:1: a tree built in Python has no document to export")
    return tree.doc


def shipped_tree(name: str) -> str:
    """Path of a tree shipped in ``trees/`` (``move_base`` -> .../trees/move_base.yaml)."""
    path = TREES_DIR / (name if name.endswith((".yaml", ".xml")) else f"{name}.yaml")
    if not path.exists():
        from executive.tree_spec import did_you_mean
        raise TreeLoadError(f"{path}:1: no shipped tree '{name}'{did_you_mean(name, SHIPPED_TREES)}")
    return str(path)
