"""Turn a ``TreeDoc`` into py_trees objects, validating everything first-hand.

Checks (each a ``TreeLoadError`` naming file, line and node, with close-match suggestions): unknown
node types and ports, literals of the wrong type or outside a port's choices, outputs given a
literal, missing required ports, malformed ``{key}`` references, child counts, unknown and
recursive subtrees.

Blackboard keys: the tree is built under a mission ``namespace``. ``{key}`` means
``<namespace>/key`` in the main tree; inside a SubTree it is private to that instance unless the
SubTree remaps it (``key: "{outer}"``) or sets ``_autoremap: true``; ``{@key}`` always means the
mission-level key. Ports left unwired that have a well-known default key (``goal``, ``path``,
``cmd_vel``, error codes, ...) use the mission-level key unless a SubTree remapped that name.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Callable, Iterable

import py_trees

from behaviors.base import Control, DecoratorNode, NavNode, namespaced, node_classes, port_problem
from behaviors.btcpp.prepost import ATTRIBUTES as PREPOST_ATTRIBUTES
from behaviors.btcpp.prepost import PrePostConditions
from behaviors.btcpp.scripted import Scripted
from behaviors.btcpp.scripting import Program, ScriptError, compile_script
from behaviors.decorators.set_parameters import parse_values
from executive import nav2_model
from executive.tree_spec import (KEY_REF, NodeSpec, PortValue, TreeDoc, TreeLoadError, TreeErrors,
                                  did_you_mean)
from navcore.safe_read import MAX_TREE_DEPTH, MAX_TREE_NODES
from navcore.types import Pose2D

SUBTREE = "SubTree"
# Keys the executive (not the tree) writes.
EXTERNAL_KEYS = frozenset({"goal", "goals", "goal_update"})


@dataclass(frozen=True)
class Literal:
    """A SubTree remapping to a constant: references to that key become this literal."""

    value: Any


@dataclass
class Scope:
    prefix: str
    root_ns: str
    mapping: dict[str, Any] = field(default_factory=dict)  # inner key -> absolute key | Literal
    autoremap: bool = False
    parent: "Scope | None" = None

    def resolve(self, key: str) -> Any:
        if key.startswith("@"):
            return namespaced(self.root_ns, key[1:])
        if key in self.mapping:
            return self.mapping[key]
        if self.autoremap and self.parent is not None:
            return self.parent.resolve(key)
        return namespaced(self.prefix, key)

    def resolve_default(self, key: str) -> Any:
        if key in self.mapping:
            return self.mapping[key]
        if self.parent is not None:
            return self.parent.resolve_default(key)
        return namespaced(self.root_ns, key)


def convert_literal(value: Any, data_type: Any, from_text: bool) -> Any:
    """Convert a literal to the port type, or raise ValueError with what was expected."""
    if data_type is object:  # any value (SetBlackboard's value, Switch cases): as written
        return value
    if data_type is float:
        if from_text and isinstance(value, str):
            return float(value)
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise ValueError("a number")
        return float(value)
    if data_type is int:
        if from_text and isinstance(value, str):
            return int(value)
        if isinstance(value, bool) or not isinstance(value, int):
            raise ValueError("an integer")
        return value
    if data_type is bool:
        if from_text and isinstance(value, str) and value.lower() in ("true", "false"):
            return value.lower() == "true"
        if not isinstance(value, bool):
            raise ValueError("true or false")
        return value
    if data_type is str:
        if isinstance(value, (dict, list)) or value is None:
            raise ValueError("a string")
        return str(value)
    if data_type is list:
        if from_text and isinstance(value, str):
            return [_scalar(v) for v in value.split(";") if v.strip()]
        if not isinstance(value, list):
            raise ValueError("a list")
        return value
    if data_type is dict:
        if from_text and isinstance(value, str):
            return parse_values(value)
        if not isinstance(value, dict):
            raise ValueError("a mapping")
        return value
    if data_type is Pose2D:
        if from_text and isinstance(value, str):
            value = [float(v) for v in value.split(";")]
        if isinstance(value, dict) and set(value) <= {"x", "y", "theta"}:
            return Pose2D(float(value.get("x", 0.0)), float(value.get("y", 0.0)),
                          float(value.get("theta", 0.0)))
        if isinstance(value, list) and len(value) in (2, 3):
            return Pose2D(*(float(v) for v in value))
        raise ValueError("a pose {x, y, theta} or [x, y, theta]")
    raise ValueError(f"a {getattr(data_type, '__name__', data_type)} (only a {{key}} reference "
                     f"can carry one)")


def _scalar(text: str) -> Any:
    text = text.strip()
    for conv in (int, float):
        try:
            return conv(text)
        except ValueError:
            pass
    return text


def unknown_type_message(node_type: str, known: Iterable[str]) -> str:
    """What to say about a node type navbt does not have: a Nav2 or BT.CPP node says so (a
    close navbt name would have other semantics); anything else gets a close match."""
    distros = nav2_model.distros_of(node_type)
    if distros:
        reason = nav2_model.NOT_PROVIDED.get(node_type)
        return (f"a Nav2 node ({', '.join(distros)}) that navbt does not provide"
                + (f": {reason}" if reason else ""))
    if node_type in nav2_model.BTCPP_BUILTINS:
        return "a BehaviorTree.CPP 4 built-in that navbt does not provide"
    if node_type in ("Action", "Condition", "Control", "Decorator"):
        return f"<{node_type}> needs an ID attribute naming the node type"
    return f"unknown node type{did_you_mean(node_type, known)}"


def costmap_of_service(service: str) -> str | None:
    """Which costmap a Nav2 clear-costmap ``service_name`` addresses: local, global or None."""
    local, glob = "local" in service, "global" in service
    return "local" if local and not glob else "global" if glob and not local else None


class _Invalid(py_trees.behaviours.Success):
    """Stands in for a node that failed validation so that the rest can still be checked."""


@dataclass
class Builder:
    """Validates and builds a ``TreeDoc``. Every problem is collected; ``build`` raises one
    ``TreeErrors`` listing them all. Ports Nav2 defines for a node type that have no meaning
    here (server plumbing) are accepted and listed in ``ignored``, never dropped silently."""

    doc: TreeDoc
    namespace: str
    from_text: bool = False  # XML: literals are strings to convert
    ignored_ports: frozenset[str] = frozenset()
    classes: dict[str, type[NavNode]] = field(default_factory=node_classes)
    distro: str | None = None  # the Nav2 distribution whose semantics apply; None: navbt's
    # node type -> {port: value} for ports a node leaves unset (the robot config's
    # behavior_server values), instead of the ports' declared defaults; "Type/name" -> {port:
    # value} for one named node, over its literals (the move_base namespace's values)
    port_defaults: dict[str, dict[str, Any]] = field(default_factory=dict)
    errors: list[TreeLoadError] = field(default_factory=list)
    ignored: list[str] = field(default_factory=list)

    def build(self, tree_id: str | None = None) -> py_trees.behaviour.Behaviour:
        tree_id = tree_id or self.main_tree()
        scope = Scope(prefix=self.namespace, root_ns=self.namespace)
        self._visited: set[str] = set()
        self._reads: list[tuple[NodeSpec, str, PortValue, str]] = []
        self._writes: set[str] = set()
        self._count, self._depth = 0, 0
        root = self._tree(tree_id, scope, (), None)
        self._check_reads()
        self._check_unused()
        if self.errors:
            raise TreeErrors(self.errors)
        return root

    def _check_reads(self) -> None:
        """A ``{key}`` read that nothing writes and that is one letter off a key the tree does
        write (or a well-known key) is a typo: say so before the robot moves."""
        known = {k.rsplit("/", 1)[-1] for k in self._writes} | EXTERNAL_KEYS
        for spec, port, pv, key in self._reads:
            name = key.rsplit("/", 1)[-1]
            if key in self._writes or name in known:
                continue
            hint = did_you_mean(name, known)
            if hint:
                self.errors.append(spec.error(f"port '{port}' reads {pv.raw!r}, which nothing in "
                                              f"the tree writes{hint}", pv.where))

    def _check_unused(self) -> None:
        """Trees that the main tree never reaches are still checked (validate reports them)."""
        for tid in list(self.doc.trees):
            if tid not in self._visited:
                scope = Scope(prefix=namespaced(self.namespace, tid), root_ns=self.namespace)
                self._tree(tid, scope, (), None)

    def main_tree(self) -> str:
        doc = self.doc
        key = doc.main_key
        if doc.main_tree is None:
            if len(doc.trees) == 1:
                return next(iter(doc.trees))
            raise TreeLoadError(f"{doc.source}:1: several trees ({', '.join(doc.trees)}) and no "
                            f"'{key}' saying which one runs")
        if doc.main_tree not in doc.trees:
            raise TreeLoadError(f"{doc.source}:1: {key} '{doc.main_tree}' is not defined"
                            f"{did_you_mean(doc.main_tree, doc.trees)}")
        return doc.main_tree

    def _tree(self, tree_id: str, scope: Scope, stack: tuple[str, ...],
              caller: NodeSpec | None) -> py_trees.behaviour.Behaviour:
        if tree_id in stack:
            chain = " -> ".join((*stack, tree_id))
            assert caller is not None
            self.errors.append(caller.error(f"recursive subtree: {chain}"))
            return _Invalid(name=caller.label)
        self._visited.add(tree_id)
        return self._node(self.doc.trees[tree_id], scope, (*stack, tree_id))

    def _node(self, spec: NodeSpec, scope: Scope,
              stack: tuple[str, ...]) -> py_trees.behaviour.Behaviour:
        if spec.type == SUBTREE:
            return self._subtree(spec, scope, stack)
        cls = self.classes.get(spec.type)
        if cls is None:
            self.errors.append(spec.error(unknown_type_message(spec.type,
                                                               [*self.classes, SUBTREE])))
            for c in spec.children:  # their problems are reported too
                self._node(c, scope, stack)
            return _Invalid(name=spec.label)
        self._count += 1
        index = self._count  # the node's place in the tree (pre-order): names its private keys
        if self._count > MAX_TREE_NODES or self._depth >= MAX_TREE_DEPTH:
            raise spec.error(f"the tree (subtrees expanded) is larger than the limits of "
                             f"{MAX_TREE_NODES} nodes and {MAX_TREE_DEPTH} levels")
        before = len(self.errors)
        self._depth += 1
        children = self._children(spec, cls, scope, stack)
        self._depth -= 1
        refs, literals = self._ports(spec, cls, scope)
        for port, value in self.port_defaults.get(spec.type, {}).items():
            if port not in refs and port not in literals:
                literals[port] = value
        # "Type/name": the robot config's value for that one node, over the tree's literal
        for port, value in self.port_defaults.get(f"{spec.type}/{spec.name}", {}).items():
            if port not in refs:
                literals[port] = value
        if len(self.errors) > before:
            return _Invalid(name=spec.label)
        kwargs: dict[str, Any] = {}
        if issubclass(cls, Control):
            kwargs["children"] = children
        elif issubclass(cls, DecoratorNode):
            kwargs["child"] = children[0]
        if cls.USES_NAV2_DISTRO:
            kwargs["nav2_distro"] = self.distro
        node = cls(name=spec.name or spec.type, **kwargs)
        try:
            node.wire(scope.prefix, refs, literals, private_tag=str(index))
        except (KeyError, ValueError, TypeError) as e:
            self.errors.append(spec.error(f"cannot wire ports: {e}"))
            return _Invalid(name=spec.label)
        if isinstance(node, Scripted):
            port = next((p for p in (*cls.SCRIPT_PORTS, *cls.KEY_PORTS) if p in spec.ports), None)
            try:
                node.bind(self._resolver(scope))
            except ScriptError as e:
                where = spec.ports[port].where if port else spec.where
                self.errors.append(spec.error(f"{port}: {e}", where))
                return _Invalid(name=spec.label)
            for program in getattr(node, "_programs", {}).values():
                self._writes.update(program.keys_written())
        scripts = self._prepost(spec, scope)
        if scripts:
            return PrePostConditions(node, scripts)
        return node

    def _children(self, spec: NodeSpec, cls: type[NavNode], scope: Scope,
                  stack: tuple[str, ...]) -> list[py_trees.behaviour.Behaviour]:
        n = len(spec.children)
        if issubclass(cls, Control):
            lo, hi = cls.MIN_CHILDREN, cls.MAX_CHILDREN
            if lo > 0 and not spec.has_children_key:
                self.errors.append(spec.error("needs 'children:' (a list of nodes)"))
            elif n < lo or (hi is not None and n > hi):
                want = f"exactly {lo}" if lo == hi else (f"at least {lo}" if hi is None
                                                         else f"{lo} to {hi}")
                self.errors.append(spec.error(f"needs {want} children, has {n}"))
        elif issubclass(cls, DecoratorNode):
            if n != 1:
                self.errors.append(spec.error(f"a decorator needs exactly one 'child:', has {n}"))
        elif spec.has_children_key:
            self.errors.append(spec.error("is a leaf and takes no children"))
        return [self._node(c, scope, stack) for c in spec.children]

    def _resolver(self, scope: Scope) -> Callable[[str], str]:
        """Script entry names as the tree's ``{key}`` references resolve them."""
        def resolve(name: str) -> str:
            target = scope.resolve(name)
            if isinstance(target, Literal):
                raise ScriptError(f"entry '{name}' is mapped to a constant by its SubTree")
            return target
        return resolve

    def _prepost(self, spec: NodeSpec, scope: Scope) -> dict[str, Program]:
        """The compiled ``_skipIf`` ... ``_onHalted`` scripts of a node (errors collected)."""
        out = {}
        for attr in PREPOST_ATTRIBUTES:
            pv = spec.ports.get(attr)
            if pv is None:
                continue
            try:
                out[attr] = compile_script(str(pv.raw), self._resolver(scope))
            except ScriptError as e:
                self.errors.append(spec.error(f"{attr}: {e}", pv.where))
                continue
            self._writes.update(out[attr].keys_written())
        return out

    def _nav2_port(self, spec: NodeSpec, port: str, pv: PortValue,
                   literals: dict[str, Any]) -> bool:
        """A port Nav2 defines for this node type but navbt's node lacks: understood (a
        translation such as ``service_name``) or accepted as ignored. False if Nav2 has no
        such port either."""
        if port not in nav2_model.any_ports(spec.type) and port not in self.ignored_ports:
            return False
        if port == "service_name" and spec.type.startswith("Clear"):
            which = costmap_of_service(str(pv.raw))
            if pv.ref is not None or which is None:
                self.errors.append(spec.error(
                    f"service_name {pv.raw!r} names neither the local nor the global costmap "
                    f"(Nav2's are local_costmap/clear_... and global_costmap/clear_...); "
                    f"write costmap: local, global or both", pv.where))
            elif "costmap" not in spec.ports:
                literals["costmap"] = which
            return True
        self.ignored.append(f"{pv.where}: {spec.label}: '{port}' is Nav2 plumbing with no "
                            f"meaning here; kept as written, ignored")
        return True

    def _ports(self, spec: NodeSpec, cls: type[NavNode], scope: Scope
               ) -> tuple[dict[str, str], dict[str, Any]]:
        inputs, outputs = cls.input_ports(), cls.output_ports()
        known = [*inputs, *outputs, "name"]
        refs: dict[str, str] = {}
        literals: dict[str, Any] = {}
        choices = getattr(cls, "CHOICES", {})
        for port, pv in spec.ports.items():
            if port in PREPOST_ATTRIBUTES:
                continue  # BT.CPP's pre/post conditions: compiled once the node is built
            if port not in inputs and port not in outputs:
                if self._nav2_port(spec, port, pv, literals):
                    continue
                extra = ("children" if issubclass(cls, Control) else
                         "child" if issubclass(cls, DecoratorNode) else None)
                self.errors.append(spec.error(
                    f"unknown port '{port}'"
                    f"{did_you_mean(port, known + ([extra] if extra else []))}", pv.where))
                continue
            key = pv.ref
            if key is None and pv.looks_like_ref():
                self.errors.append(spec.error(f"port '{port}': malformed blackboard reference "
                                              f"{pv.raw!r} (write \"{{key}}\" with a plain name)",
                                              pv.where))
                continue
            try:
                if key is not None:
                    target = scope.resolve(key)
                    if isinstance(target, Literal):
                        value = target.value
                        if port in outputs:
                            raise spec.error(f"output port '{port}' is mapped to a constant by "
                                             f"its SubTree; it needs a blackboard key", pv.where)
                        literals[port] = self._literal(spec, cls, port,
                                                       PortValue(value, pv.where), choices,
                                                       from_text=isinstance(value, str))
                    else:
                        refs[port] = target
                        if port in outputs:
                            self._writes.add(target)
                        else:
                            self._reads.append((spec, port, pv, target))
                    continue
                if port in outputs:
                    raise spec.error(f"output port '{port}' needs a blackboard reference such as "
                                     f"\"{{{port}}}\", got {pv.raw!r}", pv.where)
                literals[port] = self._literal(spec, cls, port, pv, choices, self.from_text)
            except TreeLoadError as e:
                self.errors.append(e)
        for port, by_distro in nav2_model.DISTRO_DEFAULTS.get(spec.type, {}).items():
            if port in inputs and port not in refs and port not in literals \
                    and self.distro in by_distro:
                literals[port] = by_distro[self.distro]
        for port, key in cls.DEFAULT_KEYS.items():
            if port not in refs and port not in literals:
                target = scope.resolve_default(key)
                if isinstance(target, Literal):
                    literals[port] = target.value
                else:
                    refs[port] = target
                    if port in outputs:
                        self._writes.add(target)
        for port, info in inputs.items():
            if info.required and not info.has_default and port not in refs and port not in literals:
                self.errors.append(spec.error(f"missing required port '{port}' "
                                              f"({info.description})"))
        return refs, literals

    def _literal(self, spec: NodeSpec, cls: type[NavNode], port: str, pv: PortValue,
                 choices: dict[str, tuple], from_text: bool) -> Any:
        info = cls.input_ports()[port]
        try:
            value = convert_literal(pv.raw, info.data_type, from_text)
        except (ValueError, TypeError, OverflowError) as e:
            want = str(e) if str(e) and not str(e).startswith(("could not", "invalid")) \
                else getattr(info.data_type, "__name__", "?")
            raise spec.error(f"port '{port}' expects {want}, got {pv.raw!r}", pv.where) from None
        problem = port_problem(info, value)
        if problem is not None:
            raise spec.error(f"port '{port}' {problem}", pv.where)
        if port in choices and value not in choices[port]:
            raise spec.error(f"port '{port}' must be one of {', '.join(choices[port])}, got "
                             f"{value!r}{did_you_mean(str(value), choices[port])}", pv.where)
        return value

    def _subtree(self, spec: NodeSpec, scope: Scope,
                 stack: tuple[str, ...]) -> py_trees.behaviour.Behaviour:
        tid = spec.subtree_id
        if tid is None:
            self.errors.append(spec.error("needs 'id:' naming the tree to insert"))
            return _Invalid(name=spec.label)
        if tid not in self.doc.trees:
            self.errors.append(spec.error(f"unknown subtree id '{tid}'"
                                          f"{did_you_mean(tid, self.doc.trees)}"))
            return _Invalid(name=spec.label)
        if spec.has_children_key:
            self.errors.append(spec.error("takes no children (its tree is given by 'id')"))
        mapping: dict[str, Any] = {}
        used = referenced_keys(self.doc, tid, self.classes, set())
        for inner, pv in spec.ports.items():
            if inner not in used:
                self.errors.append(spec.error(f"subtree '{tid}' does not use key '{inner}'"
                                              f"{did_you_mean(inner, used)}", pv.where))
                continue
            key = pv.ref
            if key is None and pv.looks_like_ref():
                self.errors.append(spec.error(f"'{inner}': malformed blackboard reference "
                                              f"{pv.raw!r}", pv.where))
                continue
            mapping[inner] = scope.resolve(key) if key is not None else Literal(pv.raw)
        name = spec.name or tid
        child_scope = Scope(prefix=namespaced(scope.prefix, name), root_ns=scope.root_ns,
                            mapping=mapping, autoremap=spec.autoremap, parent=scope)
        return self._tree(tid, child_scope, stack, spec)


def referenced_keys(doc: TreeDoc, tree_id: str, classes: dict[str, type[NavNode]],
                    seen: set[str]) -> set[str]:
    """Blackboard key names a tree refers to (explicit refs and unwired default keys)."""
    if tree_id in seen or tree_id not in doc.trees:
        return set()
    seen.add(tree_id)
    out: set[str] = set()

    def walk(spec: NodeSpec) -> None:
        if spec.type == SUBTREE:
            out.update(p for p in spec.ports)
            if spec.autoremap and spec.subtree_id:
                out.update(referenced_keys(doc, spec.subtree_id, classes, seen))
            return
        cls = classes.get(spec.type)
        for pv in spec.ports.values():
            if pv.ref:
                out.add(pv.ref.lstrip("@"))
        if cls is not None:
            out.update(k for p, k in cls.DEFAULT_KEYS.items() if p not in spec.ports)
        for c in spec.children:
            walk(c)

    walk(doc.trees[tree_id])
    return out


def check_key(text: str) -> bool:
    return bool(KEY_REF.match(text))
