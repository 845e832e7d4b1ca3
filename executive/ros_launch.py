"""The roslaunch XML subset move_base users write, read into a parameter tree.

``read_launch("move_base.launch", {"model": "burger"})`` evaluates ``<arg>`` (``default`` /
``value``, overridden by ``args``), the substitutions ``$(arg)``, ``$(find pkg)``, ``$(env)``,
``$(optenv)``, ``$(dirname)``, ``$(anon)``, ``if`` / ``unless``, ``<group ns>``, ``<node>``
(its private namespace), ``<param name value type textfile>``, ``<rosparam>`` (``command="load"``
of a file or of inline YAML, ``delete``; ``ns``, ``param``, ``subst_value``) and ``<include>``
with its ``<arg>``s, as roslaunch does. It starts no process. What has no meaning here
(``<remap>``, ``<env>``, ``<machine>``, ``<test>``, other nodes and their parameters, ``command=``
parameters) is listed in one "ignored" note. Errors name ``file:line``.
"""

from __future__ import annotations

import os
import re
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, Mapping
from xml.parsers import expat

from executive.param_files import (Note, ParamsError, Path_, duplicate_notes, parse_yaml_lines,
                                   read_ros_yaml)
from executive.ros_params import ParamTree, split_name
from navcore.params import suggest
from navcore.safe_read import (MAX_INCLUDE_DEPTH, MAX_XML_DEPTH, Duplicate, parse_xml, parse_yaml,
                               read_bytes, read_text)
from executive.errors import ExecutiveError


@dataclass
class _Elem:
    tag: str
    attrs: dict[str, str]
    line: int
    children: list["_Elem"] = field(default_factory=list)
    text: str = ""
    text_line: int = 0


def _parse(file: str) -> _Elem:
    """The element tree of a launch file, each element with its line (navcore.safe_read's size
    limit; no entity declarations, nesting at most MAX_XML_DEPTH)."""
    data = read_bytes(file, what="launch file", error=ParamsError)
    parser = expat.ParserCreate()
    stack: list[_Elem] = []
    root: list[_Elem] = []

    def start(tag: str, attrs: dict[str, str]) -> None:
        if len(stack) >= MAX_XML_DEPTH:
            raise ParamsError(f"{file}:{parser.CurrentLineNumber}: elements nested more than "
                              f"{MAX_XML_DEPTH} deep (limit)")
        el = _Elem(tag, dict(attrs), parser.CurrentLineNumber)
        (stack[-1].children if stack else root).append(el)
        stack.append(el)

    def end(tag: str) -> None:
        stack.pop()

    def chars(text: str) -> None:
        if stack:
            el = stack[-1]
            if not el.text:
                el.text_line = parser.CurrentLineNumber
            el.text += text

    parser.StartElementHandler = start
    parser.EndElementHandler = end
    parser.CharacterDataHandler = chars
    parse_xml(parser, data, file, error=ParamsError)
    if not root:
        raise ParamsError(f"{file}:1: not valid XML: no element")
    if root[0].tag != "launch":
        raise ParamsError(f"{file}:{root[0].line}: the top element must be <launch>, "
                          f"not <{root[0].tag}>")
    return root[0]


@dataclass
class LaunchNode:
    """A ``<node>``: package, type, name and its private namespace."""

    pkg: str
    type: str
    name: str
    ns: Path_
    where: str
    args: str = ""


@dataclass
class Launched:
    """What a launch file sets: the parameter tree, its nodes and the findings."""

    tree: ParamTree
    nodes: list[LaunchNode]
    notes: list[Note]
    move_base_ns: Path_ | None = None
    amcl_ns: Path_ | None = None


class _Skip(ExecutiveError):
    """An element that cannot be evaluated (the error is already recorded)."""


@dataclass
class _Context:
    file: str
    ns: Path_
    args: dict[str, str]
    overrides: dict[str, str]
    used: set[str]
    node: LaunchNode | None = None
    failed: set[str] = field(default_factory=set)  # args whose value could not be evaluated
    declared: dict[str, str] = field(default_factory=dict)  # arg name -> where it is declared


class _Reader:
    def __init__(self, package_path: list[str]) -> None:
        self.package_path = [str(p) for p in package_path]
        self.tree = ParamTree()
        self.nodes: list[LaunchNode] = []
        self.notes: list[Note] = []
        self.ignored: dict[str, list[str]] = {}
        self.depth = 0
        self.anon = 0

    # ------------------------------------------------------------ findings
    def error(self, where: str, text: str) -> None:
        self.notes.append(Note("error", where, text))

    def ignore(self, what: str, where: str) -> None:
        self.ignored.setdefault(what, []).append(where)

    # ------------------------------------------------------------ substitution
    def find(self, pkg: str, ctx: _Context) -> str | None:
        """The folder of package ``pkg``: the search path, the launch file's folder and its
        parents (a folder named ``pkg``, or holding one), then ROS_PACKAGE_PATH."""
        here = Path(ctx.file).resolve().parent
        roots = [Path(p) for p in self.package_path] + [here, *here.parents]
        roots += [Path(p) for p in os.environ.get("ROS_PACKAGE_PATH", "").split(os.pathsep) if p]
        for root in roots:
            if root.name == pkg and root.is_dir():
                return str(root)
            if (root / pkg).is_dir():
                return str(root / pkg)
        return None

    _SUBST = re.compile(r"\$\(([^()]*)\)")

    def subst(self, text: str, ctx: _Context, where: str) -> str:
        """Evaluate every ``$(...)`` in ``text``; an unknown one is an error (raises _Skip)."""
        if "$(eval" in text:
            self.error(where, f"$(eval ...) is not supported (it runs Python): {text}")
            raise _Skip
        out, pos = [], 0
        for m in self._SUBST.finditer(text):
            out.append(text[pos:m.start()])
            out.append(self._one(m.group(1).split(), ctx, where, m.group(0)))
            pos = m.end()
        out.append(text[pos:])
        return "".join(out)

    def _one(self, parts: list[str], ctx: _Context, where: str, whole: str) -> str:
        kind = parts[0] if parts else ""
        if kind == "arg" and len(parts) == 2:
            name = parts[1]
            if name in ctx.failed:
                raise _Skip  # already reported where the arg was declared
            if name not in ctx.args:
                self.error(where, f"{whole}: arg '{name}' is not declared before this point"
                                  f"{suggest(name, ctx.args)}")
                raise _Skip
            return ctx.args[name]
        if kind == "env" and len(parts) == 2:
            if parts[1] not in os.environ:
                self.error(where, f"{whole}: environment variable '{parts[1]}' is not set")
                raise _Skip
            return os.environ[parts[1]]
        if kind == "optenv" and len(parts) >= 2:
            return os.environ.get(parts[1], " ".join(parts[2:]))
        if kind == "find" and len(parts) == 2:
            found = self.find(parts[1], ctx)
            if found is None:
                self.error(where, f"{whole}: package '{parts[1]}' not found beside the launch "
                                  "file, in its parents or in ROS_PACKAGE_PATH (give "
                                  "--package-path DIR)")
                raise _Skip
            return found
        if kind == "dirname" and len(parts) == 1:
            return str(Path(ctx.file).resolve().parent)
        if kind == "anon" and len(parts) == 2:
            self.anon += 1
            return f"{parts[1]}_anon{self.anon}"
        self.error(where, f"{whole}: unknown or unsupported substitution (supported: arg, find, "
                          "env, optenv, dirname, anon)")
        raise _Skip

    def attr(self, el: _Elem, name: str, ctx: _Context, default: str | None = None
             ) -> str | None:
        if name not in el.attrs:
            return default
        return self.subst(el.attrs[name], ctx, f"{ctx.file}:{el.line}")

    def enabled(self, el: _Elem, ctx: _Context) -> bool:
        """``if`` / ``unless`` as roslaunch reads them ("true"/"1", "false"/"0")."""
        where = f"{ctx.file}:{el.line}"
        if "if" in el.attrs and "unless" in el.attrs:
            self.error(where, f"<{el.tag}>: give 'if' or 'unless', not both (roslaunch refuses "
                              "that)")
            raise _Skip
        for key, want in (("if", True), ("unless", False)):
            if key in el.attrs:
                value = self.subst(el.attrs[key], ctx, where).strip().lower()
                if value not in ("true", "1", "false", "0"):
                    self.error(where, f"<{el.tag} {key}=...>: '{value}' is not a boolean "
                                      "(true, false, 1 or 0)")
                    raise _Skip
                if (value in ("true", "1")) != want:
                    return False
        return True

    # ------------------------------------------------------------ names
    def resolve(self, name: str, ctx: _Context, where: str) -> Path_:
        """A parameter name: global (``/x``), private (``~x``, in a node) or relative."""
        if name.startswith("/"):
            return split_name(name)
        if name.startswith("~"):
            if ctx.node is None:
                self.error(where, f"'{name}': a private name needs an enclosing <node>")
                raise _Skip
            return ctx.node.ns + split_name(name[1:])
        base = ctx.node.ns if ctx.node is not None else ctx.ns
        return base + split_name(name)

    # ------------------------------------------------------------ elements
    def read(self, file: str, ctx_args: Mapping[str, str], ns: Path_ = (),
             where: str = "") -> None:
        self.depth += 1
        if self.depth > MAX_INCLUDE_DEPTH:
            raise ParamsError(f"{where or file}: includes nest deeper than "
                              f"{MAX_INCLUDE_DEPTH} (a cycle?)")
        root = _parse(file)
        ctx = _Context(file, ns, {}, dict(ctx_args), set())
        self.children(root, ctx)
        unused = sorted(set(ctx.overrides) - ctx.used)
        for name in unused:
            self.error(where or file, f"arg '{name}' is given but {file} declares no such arg"
                                      f"{suggest(name, set(ctx.args) | ctx.failed)}")
        self.depth -= 1

    def children(self, el: _Elem, ctx: _Context) -> None:
        for child in el.children:
            try:
                self.element(child, ctx)
            except _Skip:
                continue

    def element(self, el: _Elem, ctx: _Context) -> None:
        where = f"{ctx.file}:{el.line}"
        tag = el.tag
        if tag == "arg":
            self.arg(el, ctx, where)
            return
        if not self.enabled(el, ctx):
            return
        if tag == "group":
            ns = self.attr(el, "ns", ctx)
            # as in roslaunch, an arg declared inside the group is not declared after it
            sub = replace(ctx, ns=self.resolve(ns, ctx, where) if ns else ctx.ns,
                          declared=dict(ctx.declared))
            if el.attrs.get("clear_params", "false").lower() in ("true", "1") and ns:
                self.tree.delete(sub.ns)
            self.children(el, sub)
        elif tag == "node":
            self.node(el, ctx, where)
        elif tag == "param":
            self.param(el, ctx, where)
        elif tag == "rosparam":
            self.rosparam(el, ctx, where)
        elif tag == "include":
            self.include(el, ctx, where)
        elif tag in ("remap", "env", "machine", "test", "master"):
            self.ignore(f"<{tag}>", where)
        else:
            self.ignore(f"<{tag}> (not a roslaunch tag navbt reads)", where)

    def arg(self, el: _Elem, ctx: _Context, where: str) -> None:
        name = el.attrs.get("name")
        if not name:
            self.error(where, "<arg> needs a name")
            raise _Skip
        if not self.enabled(el, ctx):
            return
        if name in ctx.declared:   # roslaunch: "arg '...' has already been declared"
            self.error(where, f"arg '{name}' is declared twice (first at "
                              f"{ctx.declared[name]}); roslaunch refuses that")
            raise _Skip
        ctx.declared[name] = where
        if "value" in el.attrs and "default" in el.attrs:
            self.error(where, f"<arg name=\"{name}\">: give value or default, not both")
            raise _Skip
        if "value" in el.attrs:
            if name in ctx.overrides:
                ctx.used.add(name)
                self.notes.append(Note("warning", where, f"arg '{name}' has a fixed value in "
                                                         "the launch file; the given value is "
                                                         "not used"))
            ctx.args[name] = self.subst(el.attrs["value"], ctx, where)
        elif name in ctx.overrides:
            ctx.used.add(name)
            ctx.args[name] = ctx.overrides[name]  # the default is not evaluated
        elif "default" in el.attrs:
            try:
                ctx.args[name] = self.subst(el.attrs["default"], ctx, where)
            except _Skip:
                ctx.failed.add(name)
                self.notes[-1] = Note("error", where, f"{self.notes[-1].text} (or give "
                                                      f"--arg {name}=VALUE)")
                raise
        else:
            ctx.failed.add(name)
            self.error(where, f"arg '{name}' has no value: give --arg {name}=VALUE")
            raise _Skip

    def node(self, el: _Elem, ctx: _Context, where: str) -> None:
        pkg = self.attr(el, "pkg", ctx, "") or ""
        kind = self.attr(el, "type", ctx, "") or ""
        name = self.attr(el, "name", ctx, "") or ""
        if not name:
            self.error(where, f"<node pkg=\"{pkg}\" type=\"{kind}\"> needs a name")
            raise _Skip
        ns = self.attr(el, "ns", ctx)
        base = (self.resolve(ns, ctx, where) if ns else ctx.ns)
        info = LaunchNode(pkg, kind, name, base + (name,), where,
                          self.attr(el, "args", ctx, "") or "")
        self.nodes.append(info)
        if el.attrs.get("clear_params", "false").lower() in ("true", "1"):
            self.tree.delete(info.ns)
        sub = replace(ctx, ns=base, node=info)
        self.children(el, sub)

    def param(self, el: _Elem, ctx: _Context, where: str) -> None:
        name = self.attr(el, "name", ctx)
        if not name:
            self.error(where, "<param> needs a name")
            raise _Skip
        path = self.resolve(name, ctx, where)
        if "command" in el.attrs:
            self.ignore(f"<param command=...> ({'/' + '/'.join(path)}: the command is not run)",
                        where)
            return
        if "binfile" in el.attrs:
            self.ignore(f"<param binfile=...> ({'/' + '/'.join(path)})", where)
            return
        if "textfile" in el.attrs:
            file = self.attr(el, "textfile", ctx) or ""
            try:
                value: Any = read_text(file, what="textfile", error=ParamsError)
            except ParamsError as e:
                self.error(where, f"<param textfile=...>: {e}")
                raise _Skip from None
        elif "value" in el.attrs:
            value = self.convert(self.attr(el, "value", ctx) or "",
                                 self.attr(el, "type", ctx, "auto") or "auto", where)
        else:
            self.error(where, f"<param name=\"{name}\"> needs value, textfile or command")
            raise _Skip
        self.tree.set(path, value, where)

    def convert(self, value: str, kind: str, where: str) -> Any:
        """roslaunch's convert_value: auto (int, float, bool, else str), str, int, double,
        bool, yaml."""
        kind = kind.lower()
        if kind in ("str", "string"):
            return value
        v = value.strip()
        try:
            if kind == "auto":
                try:
                    return float(v) if "." in v else int(v)
                except ValueError:
                    pass
                return {"true": True, "false": False}.get(v.lower(), value)
            if kind == "int":
                return int(v)
            if kind == "double":
                return float(v)
            if kind in ("bool", "boolean"):
                low = v.lower()
                if low in ("true", "1"):
                    return True
                if low in ("false", "0"):
                    return False
                raise ValueError(v)
            if kind == "yaml":
                return parse_yaml(v, "<param>", error=ValueError)
        except ValueError:
            self.error(where, f"<param value=\"{value}\" type=\"{kind}\">: not a valid {kind}")
            raise _Skip from None
        self.error(where, f"<param type=\"{kind}\">: unknown type (str, int, double, bool, "
                          "yaml or auto)")
        raise _Skip

    def rosparam(self, el: _Elem, ctx: _Context, where: str) -> None:
        command = self.attr(el, "command", ctx, "load") or "load"
        ns = self.attr(el, "ns", ctx)
        base = self.resolve(ns, ctx, where) if ns else (ctx.node.ns if ctx.node else ctx.ns)
        param = self.attr(el, "param", ctx)
        target = base + (split_name(param) if param else ())
        if command == "delete":
            self.tree.delete(target)
            return
        if command == "dump":
            self.ignore("<rosparam command=\"dump\">", where)
            return
        if command != "load":
            self.error(where, f"<rosparam command=\"{command}\">: load, dump or delete")
            raise _Skip
        subst = el.attrs.get("subst_value", "false").lower() in ("true", "1")
        if "file" in el.attrs:
            file = self.attr(el, "file", ctx) or ""
            try:
                text = read_text(file, what="rosparam file", error=ParamsError)
            except ParamsError as e:
                self.error(where, f"<rosparam file=...>: {e}")
                raise _Skip from None
            if subst:
                text = self.subst(text, ctx, file)
            try:
                doc, lines = read_ros_yaml(file, self.notes, text)
            except ParamsError as e:
                self.error(where, str(e))
                raise _Skip from None
            origin_file = file
        else:
            text = el.text
            if subst:
                text = self.subst(text, ctx, where)
            try:
                found: list[Duplicate] = []
                doc, rel = parse_yaml_lines(text, "<rosparam>", duplicates=found)
            except ParamsError as e:
                m = re.match(r"<rosparam>:(\d+): (.*)", str(e), re.S)
                # (the parser may place an end-of-text error one line past the text)
                rel_line = min(int(m.group(1)), text.count("\n") + 1) if m else 1
                line = el.text_line + rel_line - 1 if m else el.line
                self.error(f"{ctx.file}:{line}", f"<rosparam>: {m.group(2) if m else e}")
                raise _Skip from None
            lines = {k: el.text_line + n - 1 for k, n in rel.items()}
            self.notes += duplicate_notes(ctx.file, found, el.text_line - 1)
            origin_file = ctx.file
        if param:
            if isinstance(doc, Mapping):
                self.tree.load(doc, target, origin_file, lines)
            else:
                self.tree.set(target, doc, where)
            return
        if doc is None:
            return
        if not isinstance(doc, Mapping):
            self.error(where, "<rosparam> without param= must hold a mapping of parameters")
            raise _Skip
        self.tree.load(doc, target, origin_file, lines)

    def include(self, el: _Elem, ctx: _Context, where: str) -> None:
        file = self.attr(el, "file", ctx)
        if not file:
            self.error(where, "<include> needs a file")
            raise _Skip
        if not os.path.isabs(file):
            file = str(Path(ctx.file).resolve().parent / file)
        ns = self.attr(el, "ns", ctx)
        sub_ns = self.resolve(ns, ctx, where) if ns else ctx.ns
        passed: dict[str, str] = {}
        if el.attrs.get("pass_all_args", "false").lower() in ("true", "1"):
            passed.update(ctx.args)
        for child in el.children:
            if child.tag != "arg":
                self.ignore(f"<{child.tag}> inside <include>", f"{ctx.file}:{child.line}")
                continue
            try:
                if not self.enabled(child, ctx):
                    continue
                value = self.attr(child, "value", ctx)
                if value is None:
                    value = self.attr(child, "default", ctx)
            except _Skip:
                continue
            if value is not None:
                passed[child.attrs.get("name", "")] = value
        if el.attrs.get("clear_params", "false").lower() in ("true", "1") and ns:
            self.tree.delete(sub_ns)
        if not os.path.exists(file):
            self.error(where, f"<include file=\"{file}\">: no such file")
            raise _Skip
        self.read(file, passed, sub_ns, where)


def _places(wheres: list[str]) -> str:
    """``a.launch:3, a.launch:7, b.yaml:2`` -> ``a.launch:3, 7; b.yaml:2`` (file names only)."""
    by_file: dict[str, list[str]] = {}
    for w in wheres:
        file, _, line = w.rpartition(":")
        if not line.isdigit():
            file, line = w, ""
        by_file.setdefault(os.path.basename(file), []).append(line)
    return "; ".join(f"{f}:{', '.join(l for l in lines if l)}" if any(lines) else f
                     for f, lines in by_file.items())


def _is(node: LaunchNode, kind: str) -> bool:
    return node.type == kind or node.pkg == kind and node.type in ("", kind)


def read_launch(path: str | os.PathLike, args: Mapping[str, str] | None = None,
                package_path: list[str] | None = None) -> Launched:
    """Evaluate a launch file with ``args`` overriding its ``<arg>`` defaults."""
    reader = _Reader(list(package_path or []))
    path = str(path)
    reader.read(path, dict(args or {}))
    launched = Launched(reader.tree, reader.nodes, reader.notes)
    move_base = [n for n in reader.nodes if _is(n, "move_base")]
    amcl = [n for n in reader.nodes if _is(n, "amcl")]
    if move_base:
        launched.move_base_ns = move_base[0].ns
        for extra in move_base[1:]:
            reader.notes.append(Note("warning", extra.where, f"a second move_base node "
                                     f"'{extra.name}': only '{move_base[0].name}' is used"))
    if amcl:
        launched.amcl_ns = amcl[0].ns
    used = [n.ns for n in (move_base[:1] + amcl[:1])]
    for n in reader.nodes:
        if n.ns not in used:
            extra = f", args '{n.args}'" if n.args else ""
            reader.ignore(f"node '{n.name}' ({n.pkg}/{n.type}{extra}) and its parameters",
                          n.where)
    for p, value in reader.tree.leaves():
        if not any(p[:len(u)] == u for u in used) and not any(
                p[:len(n.ns)] == n.ns for n in reader.nodes):
            reader.ignore(f"parameter '/{'/'.join(p)}'", reader.tree.origin(p))
    if reader.ignored:
        parts = [f"{what} ({_places(where)})" for what, where in reader.ignored.items()]
        reader.notes.append(Note("ignored", path, "no counterpart in navbt: " + "; ".join(parts)))
    return launched
