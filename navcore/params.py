"""Typed, ranged, reconfigurable parameters: the dynamic_reconfigure idea without ROS.

A component declares its parameters once as a tuple of ``Param`` (ROS name, default, type, range,
one-line meaning) and keeps a ``Parameters`` object. Values arrive from a user's ROS YAML namespace;
an unknown name, a wrong type or an out-of-range value is a ``ParameterError`` that names the
parameter (and suggests the closest known name). ``set`` returns the previous values so that a
caller (the tree's ``SetParameters``) can restore them.
"""

from __future__ import annotations

import math

import difflib
import weakref
from dataclasses import dataclass, field
from typing import Any, Callable, Iterable, Mapping

from navcore.errors import NavcoreError


class ParameterError(NavcoreError, ValueError):
    """A parameter name, type or value is not acceptable; the message says which and why."""


@dataclass(frozen=True, slots=True)
class Param:
    """Declaration of one parameter. ``choices`` restricts strings (and ints) to a set."""

    name: str
    default: Any
    type: type
    doc: str = ""
    min: float | None = None
    max: float | None = None
    choices: tuple | None = None
    finite: bool = True  # a float must be finite (inf passes every min or max on one side)

    def check(self, value: Any, where: str = "") -> Any:
        """Return ``value`` converted to this parameter's type, or raise ParameterError."""
        prefix = f"{where}: " if where else ""
        t = self.type
        if t is bool:
            if not isinstance(value, bool):
                raise ParameterError(f"{prefix}parameter '{self.name}' must be true or false, "
                                     f"got {value!r}")
        elif t is int:
            if isinstance(value, bool) or not (isinstance(value, int)
                                               or (isinstance(value, float) and value.is_integer())):
                raise ParameterError(f"{prefix}parameter '{self.name}' must be an integer, "
                                     f"got {value!r}")
            value = int(value)
        elif t is float:
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                raise ParameterError(f"{prefix}parameter '{self.name}' must be a number, "
                                     f"got {value!r}")
            try:
                value = float(value)
            except OverflowError:
                raise ParameterError(f"{prefix}parameter '{self.name}' = {value} is out of "
                                     f"range") from None
            if math.isnan(value):  # NaN passes every min/max comparison: refuse it by name
                raise ParameterError(f"{prefix}parameter '{self.name}' must be a number, "
                                     f"got NaN")
            if self.finite and math.isinf(value):
                raise ParameterError(f"{prefix}parameter '{self.name}' must be finite, "
                                     f"got {value}")
        elif t is str:
            if not isinstance(value, str):
                raise ParameterError(f"{prefix}parameter '{self.name}' must be a string, "
                                     f"got {value!r}")
        elif t is list:
            if not isinstance(value, (list, tuple)):
                raise ParameterError(f"{prefix}parameter '{self.name}' must be a list, "
                                     f"got {value!r}")
            value = list(value)
        if self.min is not None and value < self.min:
            raise ParameterError(f"{prefix}parameter '{self.name}' = {value!r} is below its "
                                 f"minimum {self.min}")
        if self.max is not None and value > self.max:
            raise ParameterError(f"{prefix}parameter '{self.name}' = {value!r} is above its "
                                 f"maximum {self.max}")
        if self.choices is not None and value not in self.choices:
            raise ParameterError(f"{prefix}parameter '{self.name}' = {value!r} is not one of "
                                 f"{', '.join(map(repr, self.choices))}")
        return value


# Words that mean the same in ROS parameter names (``max_rot_vel`` is ``max_vel_theta``): a
# suggestion compares names by these words as well as by spelling.
_SYNONYMS = {"rot": "theta", "rotational": "theta", "th": "theta", "yaw": "theta",
             "velocity": "vel", "speed": "vel", "limit": "lim", "accel": "acc",
             "trans": "trans", "translational": "trans", "dist": "distance", "pdist": "path",
             "gdist": "goal"}


def _words(name: str) -> set[str]:
    return {_SYNONYMS.get(w, w) for w in name.lower().split("_") if w}


def _similarity(a: str, b: str) -> float:
    """The better of spelling similarity and shared words (same words in any order: 1.0)."""
    spelled = difflib.SequenceMatcher(None, a, b).ratio()
    wa, wb = _words(a), _words(b)
    shared = len(wa & wb) / len(wa | wb) if wa | wb else 0.0
    return max(spelled, shared)


def suggest(name: str, known: Iterable[str]) -> str:
    """`` (did you mean 'x'?)`` for the closest known name, or an empty string."""
    name = str(name)  # a YAML key may be a number
    scored = [(_similarity(name, str(k)), str(k)) for k in known]
    scored = [sk for sk in scored if sk[0] >= 0.6]
    if not scored:
        return ""
    best = max(scored, key=lambda sk: sk[0])[1]
    return f" (did you mean '{best}'?)"


@dataclass(frozen=True)
class Leniency:
    """What a component's original (ROS) implementation tolerates in its parameter namespace.

    ``renamed``: old name -> current name, still accepted (with a warning naming the new one);
    ``clamps``: name -> (low, high) that out-of-range values are clamped to (with a warning), as
    dynamic_reconfigure does; ``ignored``: name -> why it has no effect here (accepted with a
    note); ``misspelled``: a misspelling the original silently does not read -> the name it
    reads (accepted with a warning; the value is not used, as in the original). Everything
    else stays strict: the ``Param`` table decides.
    """

    renamed: Mapping[str, str] = field(default_factory=dict)
    clamps: Mapping[str, tuple[float | None, float | None]] = field(default_factory=dict)
    ignored: Mapping[str, str] = field(default_factory=dict)
    misspelled: Mapping[str, str] = field(default_factory=dict)

    def apply(self, values: Mapping[str, Any]
              ) -> tuple[dict[str, Any], list[tuple[str, str, str, str]]]:
        """``values`` with old names renamed, ignored names dropped and values clamped; plus
        (kind, level, name, message) for each change: kind "renamed", "ignored", "misspelled"
        or "clamped", level "warning" or "ignored"."""
        out: dict[str, Any] = {}
        notes: list[tuple[str, str, str, str]] = []
        for name, value in values.items():
            if name in self.renamed:
                new = self.renamed[name]
                if new in values or new in out:
                    notes.append(("renamed", "warning", name, f"'{name}' is a deprecated name of "
                                  f"'{new}', which is also given: '{name}' is ignored"))
                    continue
                notes.append(("renamed", "warning", name, f"'{name}' is deprecated: use "
                              f"'{new}' (the value is used as '{new}')"))
                name = new
            elif name in self.ignored:
                notes.append(("ignored", "ignored", name, f"'{name}': {self.ignored[name]}"))
                continue
            elif name in self.misspelled:
                notes.append(("misspelled", "warning", name, f"'{name}' is not read (a "
                              f"misspelling of '{self.misspelled[name]}'?): its value is not "
                              "used, as in the original"))
                continue
            out[name] = value
        for name, (lo, hi) in self.clamps.items():
            v = out.get(name)
            if isinstance(v, bool) or not isinstance(v, (int, float)):
                continue
            c = v if lo is None or v >= lo else type(v)(lo)
            c = c if hi is None or c <= hi else type(v)(hi)
            if c != v:
                notes.append(("clamped", "warning", name, f"'{name}' = {v!r} is clamped to "
                              f"{c!r}, as ROS does (range {lo if lo is not None else '-inf'} .. "
                              f"{hi if hi is not None else 'inf'})"))
                out[name] = c
        return out, notes

    def known(self) -> tuple[str, ...]:
        """Names this leniency accepts besides the Param table's (for suggestions)."""
        return tuple(self.renamed) + tuple(self.ignored) + tuple(self.misspelled)


class Parameters:
    """The live values of a component's declared parameters, read as attributes.

    >>> p = Parameters((Param("hz", 1.0, float, min=0.0),), {"hz": 2})
    >>> p.hz
    2.0
    """

    def __init__(self, specs: Iterable[Param], values: Mapping[str, Any] | None = None,
                 where: str = "", ignore: Iterable[str] = ()) -> None:
        object.__setattr__(self, "_specs", {s.name: s for s in specs})
        object.__setattr__(self, "_values", {n: s.default for n, s in self._specs.items()})
        object.__setattr__(self, "_where", where)
        object.__setattr__(self, "_ignore", frozenset(ignore))
        object.__setattr__(self, "_before_change", [])
        for name, value in self._values.items():
            if not hasattr(Parameters, name):
                object.__setattr__(self, name, value)
        if values:
            self.set(values)

    def __getattr__(self, name: str) -> Any:
        try:
            return self._values[name]
        except KeyError:
            raise AttributeError(f"{self._where or 'Parameters'}: no parameter '{name}'"
                                 f"{suggest(name, self._specs)}") from None

    def __setattr__(self, name: str, value: Any) -> None:
        self.set({name: value})

    def set(self, values: Mapping[str, Any]) -> dict[str, Any]:
        """Validate and apply ``values`` all or nothing; return the previous values of those set.

        Names in ``ignore`` (keys a ROS file may carry that have no meaning here, such as
        ``plugins`` handled elsewhere) are skipped.
        """
        checked: dict[str, Any] = {}
        for name, value in values.items():
            if name in self._ignore:
                continue
            spec = self._specs.get(name)
            if spec is None:
                raise ParameterError(f"{self._where + ': ' if self._where else ''}unknown parameter "
                                     f"'{name}'{suggest(name, self._specs)}")
            checked[name] = spec.check(value, self._where)
        previous = {n: self._values[n] for n in checked}
        for hook in self._before_change:
            call = hook() if isinstance(hook, weakref.WeakMethod) else hook
            if call is not None:
                call(checked)
        self._values.update(checked)
        # Mirror the values into the instance dict so that ``p.name`` is a plain attribute read
        # (components read dozens per control cycle; the ``__getattr__`` fall-back is ~1 us
        # each). Names the class defines (methods) keep resolving to the class, as before.
        for name, value in checked.items():
            if not hasattr(Parameters, name):
                object.__setattr__(self, name, value)
        return previous

    def before_change(self, call: Callable[[dict[str, Any]], None], weak: bool = False) -> None:
        """Call ``call(new_values)`` before every accepted change (after validation), e.g. to
        finish work that must still see the old values.

        ``weak``: hold the bound method ``call`` weakly, for an object that owns these
        parameters: a strong reference back would make a cycle that only the garbage collector
        frees (a costmap's grids then outlive it until the next collection). The hook ends with
        its object."""
        self._before_change.append(weakref.WeakMethod(call) if weak else call)

    def as_dict(self) -> dict[str, Any]:
        return dict(self._values)

    def specs(self) -> tuple[Param, ...]:
        return tuple(self._specs.values())

    def __contains__(self, name: str) -> bool:
        return name in self._specs

    def __repr__(self) -> str:
        return f"Parameters({self._values!r})"
