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
from dataclasses import dataclass
from typing import Any, Callable, Iterable, Mapping


class ParameterError(ValueError):
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


def suggest(name: str, known: Iterable[str]) -> str:
    """`` (did you mean 'x'?)`` for the closest known name, or an empty string."""
    close = difflib.get_close_matches(name, list(known), n=1, cutoff=0.6)
    return f" (did you mean '{close[0]}'?)" if close else ""


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
        for call in self._before_change:
            call(checked)
        self._values.update(checked)
        # Mirror the values into the instance dict so that ``p.name`` is a plain attribute read
        # (components read dozens per control cycle; the ``__getattr__`` fall-back is ~1 us
        # each). Names the class defines (methods) keep resolving to the class, as before.
        for name, value in checked.items():
            if not hasattr(Parameters, name):
                object.__setattr__(self, name, value)
        return previous

    def before_change(self, call: Callable[[dict[str, Any]], None]) -> None:
        """Call ``call(new_values)`` before every accepted change (after validation), e.g. to
        finish work that must still see the old values."""
        self._before_change.append(call)

    def as_dict(self) -> dict[str, Any]:
        return dict(self._values)

    def specs(self) -> tuple[Param, ...]:
        return tuple(self._specs.values())

    def __contains__(self, name: str) -> bool:
        return name in self._specs

    def __repr__(self) -> str:
        return f"Parameters({self._values!r})"
