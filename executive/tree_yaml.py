"""Read a YAML tree file into a ``TreeDoc`` (safe: composed with SafeLoader, no object tags).

Format (docs/trees.md)::

    main_tree: Navigate            # optional when there is one tree
    include: [recoveries.yaml]     # optional: other files whose trees become available
    trees:
      Navigate:
        RecoveryNode:              # each node: a one-key mapping, type -> ports
          number_of_retries: 6
          children:                # controls: children; decorators: child
            - ComputePathToPose: {goal: "{goal}", path: "{path}"}
            - SubTree: {id: Recoveries, _autoremap: true}
"""

from __future__ import annotations

import os
from typing import Any

import yaml

from executive.tree_spec import NodeSpec, PortValue, TreeDoc, TreeLoadError, Where, did_you_mean
from navcore.safe_read import MAX_INCLUDE_DEPTH, compose_yaml, node_value, read_text

TOP_KEYS = ("main_tree", "nav2_distro", "trees", "include")
STRUCTURE_KEYS = ("name", "children", "child")


class _Reader:
    def __init__(self, file: str) -> None:
        self.file = file

    def where(self, node: yaml.Node) -> Where:
        return Where(self.file, node.start_mark.line + 1)

    def value(self, node: yaml.Node) -> Any:
        """Plain Python value of a YAML node (SafeLoader types only)."""
        return node_value(node, self.file, error=TreeLoadError)

    def pairs(self, node: yaml.MappingNode, what: str) -> list[tuple[str, yaml.Node, Where]]:
        if not isinstance(node, yaml.MappingNode):
            raise TreeLoadError(f"{self.where(node)}: {what} must be a mapping")
        if node.tag != "tag:yaml.org,2002:map":
            raise TreeLoadError(f"{self.where(node)}: {what}: YAML tag '{node.tag}' is not allowed "
                            f"(trees are plain data)")
        out = []
        for k, v in node.value:  # a key written twice was refused by compose_yaml
            key = self.value(k)
            if not isinstance(key, str):
                raise TreeLoadError(f"{self.where(k)}: {what}: keys must be names, got {key!r}")
            out.append((key, v, self.where(k)))
        return out

    def node(self, yn: yaml.Node) -> NodeSpec:
        """One tree node: ``Type: {ports...}``, ``Type: null`` or a bare ``Type`` string."""
        if isinstance(yn, yaml.ScalarNode):
            name = self.value(yn)
            if not isinstance(name, str) or not name:
                raise TreeLoadError(f"{self.where(yn)}: expected a node, got {name!r}")
            return NodeSpec(type=name, where=self.where(yn))
        if not isinstance(yn, yaml.MappingNode) or len(yn.value) != 1:
            n = len(yn.value) if isinstance(yn, yaml.MappingNode) else 0
            raise TreeLoadError(f"{self.where(yn)}: a node is a one-key mapping 'Type: {{ports}}'"
                            + (f", this one has {n} keys (a '-' or indentation missing?)"
                               if n > 1 else ""))
        (type_name, body, where), = self.pairs(yn, "node")
        spec = NodeSpec(type=type_name, where=where)
        if isinstance(body, yaml.ScalarNode) and self.value(body) is None:
            return spec
        for key, vn, kwhere in self.pairs(body, type_name):
            if key == "children":
                spec.has_children_key = True
                if not isinstance(vn, yaml.SequenceNode):
                    raise spec.error("'children' must be a list of nodes", kwhere)
                if vn.tag != "tag:yaml.org,2002:seq":
                    raise spec.error(f"YAML tag '{vn.tag}' is not allowed (trees are plain data)",
                                     kwhere)
                spec.children = [self.node(c) for c in vn.value]
            elif key == "child":
                spec.has_children_key = True
                spec.children = [self.node(vn)]
            elif key == "name":
                spec.name = str(self.value(vn))
            else:
                if isinstance(vn, (yaml.MappingNode, yaml.SequenceNode)) and _holds_nodes(vn):
                    raise spec.error(f"port '{key}' holds nodes; use 'children:' or 'child:'",
                                     kwhere)
                value = self.value(vn)
                text = vn.value if (isinstance(vn, yaml.ScalarNode) and not vn.style
                                    and isinstance(value, (int, float))
                                    and not isinstance(value, bool)) else None
                spec.ports[key] = PortValue(value, kwhere, text)
        if spec.type == "SubTree":
            spec.take_subtree_fields("id")
        return spec


def _holds_nodes(n: yaml.Node) -> bool:
    items = n.value if isinstance(n, yaml.SequenceNode) else []
    return any(isinstance(i, yaml.MappingNode) and len(i.value) == 1
               and isinstance(i.value[0][1], yaml.MappingNode)
               and any(isinstance(k, yaml.ScalarNode) and k.value in ("children", "child")
                       for k, _ in i.value[0][1].value)
               for i in items)


def read_yaml(path: str | os.PathLike, _stack: tuple[str, ...] = (),
              text: str | None = None) -> TreeDoc:
    """Parse ``path`` (or ``text``, named ``path`` in errors) and, recursively, its includes
    into one TreeDoc."""
    file = str(path)
    real = os.path.realpath(file)
    if real in _stack:
        chain = " -> ".join(os.path.basename(s) for s in (*_stack, real))
        raise TreeLoadError(f"{file}:1: include cycle: {chain}")
    if len(_stack) >= MAX_INCLUDE_DEPTH:
        raise TreeLoadError(f"{file}:1: includes nested more than {MAX_INCLUDE_DEPTH} files deep "
                        f"(limit)")
    if text is None:
        text = read_text(file, what="tree file", error=TreeLoadError)
    root = compose_yaml(text, file, error=TreeLoadError)
    if root is None:
        raise TreeLoadError(f"{file}:1: empty tree file")
    r = _Reader(file)
    doc = TreeDoc(main_tree=None, trees={}, tree_where={}, source=file)
    includes: list[tuple[str, Where]] = []
    for key, vn, where in r.pairs(root, "tree file"):
        if key == "main_tree":
            doc.main_tree = str(r.value(vn))
        elif key == "nav2_distro":
            from executive import nav2_model
            try:
                doc.nav2_distro = nav2_model.check_distro(str(r.value(vn)))
            except ValueError as e:
                raise TreeLoadError(f"{where}: nav2_distro: {e}") from None
        elif key == "include":
            items = vn.value if isinstance(vn, yaml.SequenceNode) else [vn]
            includes += [(str(r.value(i)), r.where(i)) for i in items]
        elif key == "trees":
            for tid, body, twhere in r.pairs(vn, "trees"):
                doc.trees[tid] = r.node(body)
                doc.tree_where[tid] = twhere
        else:
            raise TreeLoadError(f"{where}: unknown top-level key '{key}'{did_you_mean(key, TOP_KEYS)}"
                            f"; expected {', '.join(TOP_KEYS)}")
    for inc, where in includes:
        doc.include(inc, where, lambda target: read_yaml(target, (*_stack, real)))
    _attach_comments(doc, text, file)
    return doc


def _attach_comments(doc: TreeDoc, text: str, file: str) -> None:
    """Give each block of whole-line comments to a node: the one whose ``Type:`` line is just
    above the block (how ``write_yaml`` places them), else the one just below; comments above
    ``trees:`` belong to the file."""
    by_line: dict[int, NodeSpec] = {}

    def walk(spec: NodeSpec) -> None:
        if spec.where.file == file:
            by_line.setdefault(spec.where.line, spec)
        for c in spec.children:
            walk(c)

    for spec in doc.trees.values():
        walk(spec)
    first_node = min(by_line, default=0)
    lines = text.splitlines()
    i = 0
    while i < len(lines):
        if not lines[i].lstrip().startswith("#"):
            i += 1
            continue
        start = i
        while i < len(lines) and lines[i].lstrip().startswith("#"):
            i += 1
        block = [ln.lstrip()[1:].strip() for ln in lines[start:i]]
        above, below = by_line.get(start), by_line.get(i + 1)  # 1-based node lines
        if above is not None:
            above.comments.extend(block)
        elif below is not None:
            below.comments.extend(block)
        elif i + 1 <= first_node or not by_line:
            doc.comments.extend(block)


# ---------------------------------------------------------------------------- writing

def _plain(value: Any) -> Any:
    """A port value as plain YAML data (poses become {x, y, theta})."""
    from navcore.types import Pose2D
    if isinstance(value, _Lexical):
        return value
    if isinstance(value, Pose2D):
        return {"x": value.x, "y": value.y, "theta": value.theta}
    if isinstance(value, list):
        return [_plain(v) for v in value]
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    return value


class _Lexical(float):
    """A float written in YAML exactly as its XML text (``0.30`` stays ``0.30``)."""

    text: str


def _as_written(text: str, value: Any) -> Any:
    """The typed ``value`` of an XML attribute, written in YAML with the attribute's own text
    when it is a number, so that XML -> YAML -> XML keeps ``wait_duration="5"`` and
    ``backup_dist="0.30"`` as they were."""
    from executive.tree_xml import format_value
    if isinstance(value, bool) or not isinstance(value, (int, float)) \
            or format_value(value) == text:
        return value
    if isinstance(value, float):
        try:
            as_int = int(text)
            if str(as_int) == text.strip():
                return as_int
        except ValueError:
            pass
        try:
            if float(text) == value and yaml.safe_load(text) == value:
                lex = _Lexical(value)
                lex.text = text.strip()
                return lex
        except (ValueError, yaml.YAMLError):
            pass
    return value


class _Dumper(yaml.SafeDumper):
    pass


_Dumper.add_representer(
    _Lexical, lambda d, v: d.represent_scalar("tag:yaml.org,2002:float", v.text))


def _node_data(spec: NodeSpec, classes: dict[str, Any], from_text: bool,
               comments: list[list[str]]) -> dict[str, Any]:
    from executive.tree_build import convert_literal
    body: dict[str, Any] = {}
    if spec.comments:  # a marker key, replaced by comment lines once dumped
        body[f"{_MARK}{len(comments)}"] = None
        comments.append(spec.comments)
    if spec.type == "SubTree":
        body["id"] = spec.subtree_id
    if spec.name:
        body["name"] = spec.name
    if spec.type == "SubTree" and spec.autoremap:
        body["_autoremap"] = True
    cls = classes.get(spec.type)
    for port, pv in spec.ports.items():
        value = pv.raw
        if from_text and pv.ref is None and cls is not None and port in cls.input_ports():
            try:
                value = _as_written(value, convert_literal(
                    value, cls.input_ports()[port].data_type, True))
            except ValueError:
                pass  # left as text; loading it will report the problem
        elif pv.text is not None:
            value = _as_written(pv.text, value)
        body[port] = _plain(value)
    if spec.children:
        kids = [_node_data(c, classes, from_text, comments) for c in spec.children]
        cls_is_decorator = cls is not None and len(spec.children) == 1 and \
            getattr(cls, "CATEGORY", "") == "Decorator"
        if cls_is_decorator:
            body["child"] = kids[0]
        else:
            body["children"] = kids
    return {spec.type: body}


_MARK = "__navbt_comment_"


def write_yaml(doc: TreeDoc, main_tree: str, classes: dict[str, Any],
               distro: str | None = None) -> str:
    """The YAML text of every tree in ``doc``; a node's comments open its body."""
    comments: list[list[str]] = []
    data: dict[str, Any] = {"main_tree": main_tree}
    if distro:
        data["nav2_distro"] = distro
    data["trees"] = {tid: _node_data(spec, classes, doc.from_text, comments)
                     for tid, spec in doc.trees.items()}
    text = yaml.dump(data, Dumper=_Dumper, sort_keys=False, default_flow_style=False, width=100)
    out = [f"# {part}".rstrip() for c in doc.comments for part in (c.splitlines() or [""])]
    for line in text.splitlines():
        stripped = line.lstrip(" -")
        if stripped.startswith(_MARK):
            n = int(stripped[len(_MARK):].split(":")[0])
            pad = " " * (len(line) - len(stripped))
            out.extend(f"{pad}# {part}".rstrip() for c in comments[n]
                       for part in (c.splitlines() or [""]))
            continue
        out.append(line)
    return "\n".join(out) + "\n"
