"""A safe subset of BehaviorTree.CPP 4's scripting language (Script, ScriptCondition,
Precondition and the ``_skipIf`` / ``_onSuccess`` ... attributes), with its own small parser:
nothing is ever handed to Python's ``eval``.

Statements are separated by ``;``. Expressions: numbers (``3``, ``0.5``, ``0x1F``), strings
(``'text'`` or ``"text"``), ``true``/``false``, blackboard entries by name (``goal_count``;
``@name`` is the mission-level entry), registered enum names, ``( )``; operators by
precedence, low to high: assignment ``:= = += -= *= /=`` (right to left; ``:=`` creates the
entry, ``=`` needs it to exist), ``? :``, ``||``, ``&&``, ``| ^ &`` (integers), comparisons
``== != < <= > >=``, ``+ - ..`` (``..`` joins strings), ``* /``, unary ``- ! ~``.

``compile_script(text, resolve)`` parses once (a ScriptError names the column) and turns
every entry name into a storage key with ``resolve``; ``Program.run(storage)`` evaluates.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Any, Callable, Mapping, MutableMapping

from navcore.error_codes import (BackUpError, ControllerError, DriveOnHeadingError, PlannerError,
                                 RecoveryError, SpinError, WaitError)
from behaviors.errors import BehaviorError


class ScriptError(BehaviorError, ValueError):
    """A script that does not parse, or fails when run; the message says where and what."""


def _unambiguous_enums() -> dict[str, int]:
    """Names of Nav2's error codes usable in scripts: those that mean one value only (UNKNOWN,
    TIMEOUT ... exist in several enums and are left out)."""
    seen: dict[str, set[int]] = {}
    for enum in (PlannerError, ControllerError, SpinError, BackUpError, DriveOnHeadingError,
                 WaitError, RecoveryError):
        for member in enum:
            seen.setdefault(member.name, set()).add(int(member))
    return {name: next(iter(v)) for name, v in seen.items() if len(v) == 1}


# Enum names a script may use, as BT.CPP's registerScriptingEnum; extend with register_enum.
ENUMS: dict[str, int] = {"SUCCESS": 1, "FAILURE": 2, "RUNNING": 3, "IDLE": 0, "SKIPPED": 4}
ENUMS.update(_unambiguous_enums())


def register_enum(name: str, value: int) -> None:
    """Make ``name`` mean ``value`` in every script compiled afterwards."""
    if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", name):
        raise ValueError(f"not an enum name: {name!r}")
    ENUMS[name] = int(value)


_TOKEN = re.compile(r"""
    (?P<ws>\s+)
  | (?P<num>0[xX][0-9a-fA-F]+|(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?)
  | (?P<str>'[^']*'|"[^"]*")
  | (?P<name>@?[A-Za-z_][A-Za-z0-9_]*)
  | (?P<op>:=|\+=|-=|\*=|/=|==|!=|<=|>=|&&|\|\||\.\.|[-+*/<>=!~&|^?:;()])
""", re.VERBOSE)


@dataclass(frozen=True)
class _Tok:
    kind: str
    text: str
    col: int  # 1-based


def _tokens(text: str) -> list[_Tok]:
    out, i = [], 0
    while i < len(text):
        m = _TOKEN.match(text, i)
        if m is None:
            raise ScriptError(f"column {i + 1}: unexpected {text[i]!r}")
        if m.lastgroup != "ws":
            out.append(_Tok(m.lastgroup or "", m.group(), i + 1))
        i = m.end()
    out.append(_Tok("end", "", len(text) + 1))
    return out


# AST nodes are tuples: ("num", v) ("str", s) ("bool", b) ("enum", name, v) ("key", name, key)
# ("un", op, e) ("bin", op, a, b) ("and"/"or", a, b) ("if", c, a, b) ("set", op, name, key, e)
_BINARY = [("|",), ("^",), ("&",), ("==", "!=", "<", "<=", ">", ">="), ("+", "-", ".."),
           ("*", "/")]
_ASSIGN = (":=", "=", "+=", "-=", "*=", "/=")


class _Parser:
    def __init__(self, text: str, resolve: Callable[[str], str]) -> None:
        self.toks, self.i, self.resolve = _tokens(text), 0, resolve

    @property
    def tok(self) -> _Tok:
        return self.toks[self.i]

    def take(self, text: str | None = None) -> _Tok:
        t = self.tok
        if text is not None and t.text != text:
            found = "the end" if t.kind == "end" else repr(t.text)
            raise ScriptError(f"column {t.col}: expected {text!r}, found {found}")
        self.i += 1
        return t

    def program(self) -> list[tuple]:
        stmts = []
        while self.tok.kind != "end":
            if self.tok.text == ";":
                self.take()
                continue
            stmts.append(self.expr())
            if self.tok.kind != "end":
                self.take(";")
        if not stmts:
            raise ScriptError("column 1: empty script")
        return stmts

    def expr(self) -> tuple:
        left = self.ternary()
        if self.tok.text in _ASSIGN:
            op = self.take()
            if left[0] != "key":
                raise ScriptError(f"column {op.col}: '{op.text}' needs a blackboard entry on "
                                  f"its left")
            return ("set", op.text, left[1], left[2], self.expr())
        return left

    def ternary(self) -> tuple:
        cond = self.logic_or()
        if self.tok.text == "?":
            self.take()
            a = self.expr()
            self.take(":")
            return ("if", cond, a, self.expr())
        return cond

    def logic_or(self) -> tuple:
        left = self.logic_and()
        while self.tok.text == "||":
            self.take()
            left = ("or", left, self.logic_and())
        return left

    def logic_and(self) -> tuple:
        left = self.binary(0)
        while self.tok.text == "&&":
            self.take()
            left = ("and", left, self.binary(0))
        return left

    def binary(self, level: int) -> tuple:
        if level == len(_BINARY):
            return self.unary()
        left = self.binary(level + 1)
        while self.tok.kind == "op" and self.tok.text in _BINARY[level]:
            op = self.take().text
            left = ("bin", op, left, self.binary(level + 1))
        return left

    def unary(self) -> tuple:
        if self.tok.text in ("-", "!", "~"):
            op = self.take().text
            return ("un", op, self.unary())
        if self.tok.text == "+":
            self.take()
            return self.unary()
        return self.primary()

    def primary(self) -> tuple:
        t = self.tok
        if t.kind == "num":
            self.take()
            text = t.text
            if text.lower().startswith("0x"):
                return ("num", int(text, 16))
            return ("num", float(text) if any(c in text for c in ".eE") else int(text))
        if t.kind == "str":
            self.take()
            return ("str", t.text[1:-1])
        if t.kind == "name":
            self.take()
            if t.text in ("true", "false"):
                return ("bool", t.text == "true")
            if t.text in ENUMS:
                return ("enum", t.text, ENUMS[t.text])
            return ("key", t.text, self.resolve(t.text))
        if t.text == "(":
            self.take()
            e = self.expr()
            self.take(")")
            return e
        found = "the end" if t.kind == "end" else repr(t.text)
        raise ScriptError(f"column {t.col}: expected a value, found {found}")


_MISSING = object()


def _number(v: Any, what: str) -> int | float:
    if isinstance(v, bool):
        return int(v)
    if isinstance(v, (int, float)):
        return v
    if isinstance(v, str):
        try:
            return int(v) if re.fullmatch(r"[-+]?\d+", v.strip()) else float(v)
        except ValueError:
            pass
    raise ScriptError(f"{what}: {v!r} is not a number")


def _truth(v: Any) -> bool:
    if isinstance(v, str):
        if v in ("true", "false"):
            return v == "true"
        raise ScriptError(f"{v!r} is not true or false")
    return bool(v)


def _arith(op: str, a: Any, b: Any) -> Any:
    if op == "..":
        return f"{a}{b}"
    if op == "+" and isinstance(a, str) and isinstance(b, str):
        return a + b
    x, y = _number(a, f"'{op}'"), _number(b, f"'{op}'")
    if op == "+":
        return x + y
    if op == "-":
        return x - y
    if op == "*":
        return x * y
    if op == "/":
        if y == 0:
            raise ScriptError("division by zero")
        return x / y if isinstance(x, float) or isinstance(y, float) or x % y else x // y
    if op in ("|", "^", "&"):
        if not isinstance(x, int) or not isinstance(y, int):
            raise ScriptError(f"'{op}' needs integers, got {a!r} and {b!r}")
        return x | y if op == "|" else x ^ y if op == "^" else x & y
    raise ScriptError(f"unknown operator {op!r}")


def _compare(op: str, a: Any, b: Any) -> bool:
    if isinstance(a, str) != isinstance(b, str):  # BT.CPP compares a string to a number
        a, b = _number(a, f"'{op}'"), _number(b, f"'{op}'")  # by converting the string
    if op == "==":
        return a == b
    if op == "!=":
        return a != b
    try:
        return {"<": a < b, "<=": a <= b, ">": a > b, ">=": a >= b}[op]
    except TypeError:
        raise ScriptError(f"cannot compare {a!r} {op} {b!r}") from None


@dataclass(frozen=True)
class Program:
    """A parsed script: ``run(storage)`` evaluates every statement against the blackboard
    storage (a mapping of absolute keys) and returns the last statement's value."""

    text: str
    statements: tuple[tuple, ...]

    def run(self, storage: MutableMapping[str, Any]) -> Any:
        value = None
        for stmt in self.statements:
            value = _eval(stmt, storage)
        return value

    def true(self, storage: MutableMapping[str, Any]) -> bool:
        return _truth(self.run(storage))

    def keys_written(self) -> set[str]:
        out: set[str] = set()

        def walk(e: tuple) -> None:
            if e[0] == "set":
                out.add(e[3])
            for part in e[1:]:
                if isinstance(part, tuple):
                    walk(part)

        for s in self.statements:
            walk(s)
        return out


def _eval(e: tuple, st: MutableMapping[str, Any]) -> Any:
    kind = e[0]
    if kind in ("num", "str", "bool"):
        return e[1]
    if kind == "enum":
        return e[2]
    if kind == "key":
        v = st.get(e[2], _MISSING)
        if v is _MISSING or v is None:
            raise ScriptError(f"blackboard entry '{e[1]}' ({e[2]}) does not exist")
        return v
    if kind == "un":
        v = _eval(e[2], st)
        if e[1] == "!":
            return not _truth(v)
        n = _number(v, f"'{e[1]}'")
        if e[1] == "-":
            return -n
        if not isinstance(n, int):
            raise ScriptError(f"'~' needs an integer, got {v!r}")
        return ~n
    if kind == "and":
        return _truth(_eval(e[1], st)) and _truth(_eval(e[2], st))
    if kind == "or":
        return _truth(_eval(e[1], st)) or _truth(_eval(e[2], st))
    if kind == "if":
        return _eval(e[2], st) if _truth(_eval(e[1], st)) else _eval(e[3], st)
    if kind == "bin":
        a, b = _eval(e[2], st), _eval(e[3], st)
        if e[1] in ("==", "!=", "<", "<=", ">", ">="):
            return _compare(e[1], a, b)
        return _arith(e[1], a, b)
    if kind == "set":
        op, name, key, rhs = e[1], e[2], e[3], e[4]
        value = _eval(rhs, st)
        exists = st.get(key) is not None
        if op != ":=" and not exists:
            raise ScriptError(f"'{op}' on blackboard entry '{name}' that does not exist "
                              f"(create it with ':=')")
        if op in ("+=", "-=", "*=", "/="):
            value = _arith(op[0], st[key], value)
        st[key] = value
        return value
    raise ScriptError(f"unknown expression {kind!r}")


def compile_script(text: str, resolve: Callable[[str], str]) -> Program:
    """Parse ``text``; ``resolve`` maps an entry name (``@`` for mission-level) to its key."""
    if not isinstance(text, str):
        raise ScriptError(f"a script must be text, got {text!r}")
    return Program(text, tuple(_Parser(text, resolve).program()))


def namespace_resolver(namespace: str, root: str | None = None) -> Callable[[str], str]:
    """Entry names inside ``namespace``; ``@name`` inside ``root`` (default: the same)."""
    def resolve(name: str) -> str:
        if name.startswith("@"):
            return f"{(root or namespace).rstrip('/')}/{name[1:]}"
        return f"{namespace.rstrip('/')}/{name}"
    return resolve


def literal_status(text: str, allowed: Mapping[str, Any]) -> Any:
    """A status name (``SUCCESS``...) from ``allowed``, or ScriptError naming the choices."""
    if text not in allowed:
        raise ScriptError(f"{text!r} is not one of {', '.join(allowed)}")
    return allowed[text]
