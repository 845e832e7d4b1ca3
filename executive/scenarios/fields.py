"""Checkers of scenario fields: each reports what is wrong at its path and raises ``_Bad``."""

from __future__ import annotations

import math
from typing import Any, Mapping

from navcore.params import suggest

from executive.errors import ExecutiveError
from executive.scenarios.model import Shape
from executive.scenarios.source import Path_, Problems


class _Bad(ExecutiveError):
    """A value already reported: stop building this field."""


def _num(pb: Problems, path: Path_, v: Any, lo: float | None = None, hi: float | None = None,
         strict_lo: bool = False) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(float(v)):
        pb.add(path, f"expected a number, got {v!r}")
        raise _Bad
    v = float(v)
    if lo is not None and (v < lo or (strict_lo and v == lo)):
        pb.add(path, f"must be {'>' if strict_lo else '>='} {lo:g}, got {v:g}")
        raise _Bad
    if hi is not None and v > hi:
        pb.add(path, f"must be <= {hi:g}, got {v:g}")
        raise _Bad
    return v


def _int(pb: Problems, path: Path_, v: Any, lo: int | None = None) -> int:
    if isinstance(v, bool) or not isinstance(v, int):
        pb.add(path, f"expected an integer, got {v!r}")
        raise _Bad
    if lo is not None and v < lo:
        pb.add(path, f"must be >= {lo}, got {v}")
        raise _Bad
    if abs(v) >= 2 ** 63:
        pb.add(path, f"integer too large: {v}")
        raise _Bad
    return v


def _mapping(pb: Problems, path: Path_, v: Any, keys: tuple[str, ...] | None = None) -> dict:
    if not isinstance(v, Mapping):
        pb.add(path, f"expected a mapping, got {v!r}")
        raise _Bad
    if keys is not None:
        bad = False
        for k in v:
            if k not in keys:
                pb.add(path + (k,), f"unknown key '{k}'{suggest(str(k), keys)}")
                bad = True
        if bad:
            raise _Bad
    return dict(v)


def _shape(pb: Problems, path: Path_, v: Any, extra: tuple[str, ...] = ()) -> Shape:
    if not isinstance(v, Mapping) or len([k for k in v if k in ("box", "circle")]) != 1:
        pb.add(path, f"expected {{box: [x0, y0, x1, y1]}} or {{circle: [x, y, r]}}, got {v!r}")
        raise _Bad
    for k in v:
        if k not in ("box", "circle", "name") + extra:
            pb.add(path + (k,), f"unknown key '{k}'{suggest(str(k), ('box', 'circle', 'name') + extra)}")
            raise _Bad
    kind = "box" if "box" in v else "circle"
    vals = v[kind]
    n = 4 if kind == "box" else 3
    if not isinstance(vals, (list, tuple)) or len(vals) != n:
        pb.add(path + (kind,), f"{kind} needs {n} numbers, got {vals!r}")
        raise _Bad
    nums = tuple(_num(pb, path + (kind, i), x) for i, x in enumerate(vals))
    if kind == "box":
        x0, y0, x1, y1 = nums
        nums = (min(x0, x1), min(y0, y1), max(x0, x1), max(y0, y1))
        if nums[0] == nums[2] or nums[1] == nums[3]:
            pb.add(path + (kind,), f"box has zero width or height: {list(vals)}")
            raise _Bad
    elif nums[2] <= 0:
        pb.add(path + (kind,), f"circle radius must be > 0, got {nums[2]:g}")
        raise _Bad
    name = v.get("name", "")
    if not isinstance(name, str):
        pb.add(path + ("name",), f"expected a name, got {name!r}")
        raise _Bad
    return Shape(kind, nums, name)
