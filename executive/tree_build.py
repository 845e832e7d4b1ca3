"""Turn a ``TreeDoc`` into py_trees objects, validating everything first-hand.

Checks (each a ``TreeError`` naming file, line and node, with close-match suggestions): unknown
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
from typing import Any

import py_trees

from behaviors.base import Control, DecoratorNode, NavNode, namespaced, node_classes
from behaviors.reconfigure import parse_values
from executive.tree_spec import KEY_REF, NodeSpec, PortValue, TreeDoc, TreeError, did_you_mean
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


@dataclass
class Builder:
    doc: TreeDoc
    namespace: str
    from_text: bool = False  # XML: literals are strings to convert
    ignored_ports: frozenset[str] = frozenset()
    classes: dict[str, type[NavNode]] = field(default_factory=node_classes)

    def build(self, tree_id: str | None = None) -> py_trees.behaviour.Behaviour:
        tree_id = tree_id or self.main_tree()
        scope = Scope(prefix=self.namespace, root_ns=self.namespace)
        self._reads: list[tuple[NodeSpec, str, PortValue, str]] = []
        self._writes: set[str] = set()
        self._count, self._depth = 0, 0
        root = self._tree(tree_id, scope, (), None)
        self._check_reads()
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
                raise spec.error(f"port '{port}' reads {pv.raw!r}, which nothing in the tree "
                                 f"writes{hint}", pv.where)

    def main_tree(self) -> str:
        doc = self.doc
        if doc.main_tree is None:
            if len(doc.trees) == 1:
                return next(iter(doc.trees))
            raise TreeError(f"{doc.source}:1: several trees ({', '.join(doc.trees)}) and no "
                            f"'main_tree' saying which one runs")
        if doc.main_tree not in doc.trees:
            raise TreeError(f"{doc.source}:1: main_tree '{doc.main_tree}' is not defined"
                            f"{did_you_mean(doc.main_tree, doc.trees)}")
        return doc.main_tree

    def _tree(self, tree_id: str, scope: Scope, stack: tuple[str, ...],
              caller: NodeSpec | None) -> py_trees.behaviour.Behaviour:
        if tree_id in stack:
            chain = " -> ".join((*stack, tree_id))
            assert caller is not None
            raise caller.error(f"recursive subtree: {chain}")
        return self._node(self.doc.trees[tree_id], scope, (*stack, tree_id))

    def _node(self, spec: NodeSpec, scope: Scope, stack: tuple[str, ...]) -> py_trees.behaviour.Behaviour:
        if spec.type == SUBTREE:
            return self._subtree(spec, scope, stack)
        cls = self.classes.get(spec.type)
        if cls is None:
            raise spec.error(f"unknown node type{did_you_mean(spec.type, [*self.classes, SUBTREE])}")
        self._count += 1
        if self._count > MAX_TREE_NODES or self._depth >= MAX_TREE_DEPTH:
            raise spec.error(f"the tree (subtrees expanded) is larger than the limits of "
                             f"{MAX_TREE_NODES} nodes and {MAX_TREE_DEPTH} levels")
        self._depth += 1
        children = self._children(spec, cls, scope, stack)
        self._depth -= 1
        refs, literals = self._ports(spec, cls, scope)
        kwargs: dict[str, Any] = {}
        if issubclass(cls, Control):
            kwargs["children"] = children
        elif issubclass(cls, DecoratorNode):
            kwargs["child"] = children[0]
        node = cls(name=spec.name or spec.type, **kwargs)
        try:
            node.wire(scope.prefix, refs, literals)
        except (KeyError, ValueError, TypeError) as e:
            raise spec.error(f"cannot wire ports: {e}") from None
        node.source_location = str(spec.where)  # for error reports at run time
        return node

    def _children(self, spec: NodeSpec, cls: type[NavNode], scope: Scope,
                  stack: tuple[str, ...]) -> list[py_trees.behaviour.Behaviour]:
        n = len(spec.children)
        if issubclass(cls, Control):
            lo, hi = cls.MIN_CHILDREN, cls.MAX_CHILDREN
            if lo > 0 and not spec.has_children_key:
                raise spec.error("needs 'children:' (a list of nodes)")
            if n < lo or (hi is not None and n > hi):
                want = f"exactly {lo}" if lo == hi else (f"at least {lo}" if hi is None
                                                         else f"{lo} to {hi}")
                raise spec.error(f"needs {want} children, has {n}")
        elif issubclass(cls, DecoratorNode):
            if n != 1:
                raise spec.error(f"a decorator needs exactly one 'child:', has {n}")
        elif spec.has_children_key:
            raise spec.error("is a leaf and takes no children")
        return [self._node(c, scope, stack) for c in spec.children]

    def _ports(self, spec: NodeSpec, cls: type[NavNode], scope: Scope
               ) -> tuple[dict[str, str], dict[str, Any]]:
        inputs, outputs = cls.input_ports(), cls.output_ports()
        known = [*inputs, *outputs, "name"]
        refs: dict[str, str] = {}
        literals: dict[str, Any] = {}
        choices = getattr(cls, "CHOICES", {})
        for port, pv in spec.ports.items():
            if port not in inputs and port not in outputs:
                if port in self.ignored_ports:
                    continue
                extra = ("children" if issubclass(cls, Control) else
                         "child" if issubclass(cls, DecoratorNode) else None)
                raise spec.error(f"unknown port '{port}'{did_you_mean(port, known + ([extra] if extra else []))}",
                                 pv.where)
            key = pv.ref
            if key is None and pv.looks_like_ref():
                raise spec.error(f"port '{port}': malformed blackboard reference {pv.raw!r} "
                                 f"(write \"{{key}}\" with a plain name)", pv.where)
            if key is not None:
                target = scope.resolve(key)
                if isinstance(target, Literal):
                    value = target.value
                    if port in outputs:
                        raise spec.error(f"output port '{port}' is mapped to a constant by its "
                                         f"SubTree; it needs a blackboard key", pv.where)
                    literals[port] = self._literal(spec, cls, port, PortValue(value, pv.where),
                                                   choices, from_text=isinstance(value, str))
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
                raise spec.error(f"missing required port '{port}' ({info.description})")
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
        if port in choices and value not in choices[port]:
            raise spec.error(f"port '{port}' must be one of {', '.join(choices[port])}, got "
                             f"{value!r}{did_you_mean(str(value), choices[port])}", pv.where)
        return value

    def _subtree(self, spec: NodeSpec, scope: Scope, stack: tuple[str, ...]) -> py_trees.behaviour.Behaviour:
        tid = spec.subtree_id
        if tid is None:
            raise spec.error("needs 'id:' naming the tree to insert")
        if tid not in self.doc.trees:
            raise spec.error(f"unknown subtree id '{tid}'{did_you_mean(tid, self.doc.trees)}")
        if spec.has_children_key:
            raise spec.error("takes no children (its tree is given by 'id')")
        mapping: dict[str, Any] = {}
        used = referenced_keys(self.doc, tid, self.classes, set())
        for inner, pv in spec.ports.items():
            if inner not in used:
                raise spec.error(f"subtree '{tid}' does not use key '{inner}'"
                                 f"{did_you_mean(inner, used)}", pv.where)
            key = pv.ref
            if key is None and pv.looks_like_ref():
                raise spec.error(f"'{inner}': malformed blackboard reference {pv.raw!r}", pv.where)
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
