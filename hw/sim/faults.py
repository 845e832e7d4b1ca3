"""Faults a scenario can script into the simulator, each active on [start, start + duration).

- ``laser_dropout``: no scans arrive; ``scan()`` keeps returning the last one, growing stale.
- ``laser_frozen``: scans keep arriving on time with fresh stamps but the same ranges.
- ``odom_slip``: the wheels turn but the robot moves only ``1 - slip`` of it (``slip`` 1.0 =
  stands still); odometry reports the wheel motion.
- ``blocked_rotation``: the body cannot yaw (wedged); it can still translate, and the wheels and
  odometry report the commanded turn while the IMU shows none.
- ``stuck_wheel``: the ``left`` or ``right`` drive wheel stops; the robot pivots about it and
  the odometry (encoders) agrees.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Mapping

from navcore.params import suggest
from hw.errors import HwError

FAULT_KINDS = ("laser_dropout", "laser_frozen", "odom_slip", "blocked_rotation", "stuck_wheel")
_KEYS = ("kind", "start", "duration", "wheel", "slip")


class FaultError(HwError, ValueError):
    """A fault description is malformed; the message names the field."""


@dataclass(frozen=True)
class Fault:
    """One scripted fault (see the module docstring for the kinds)."""

    kind: str
    start: float
    duration: float = math.inf
    wheel: str = "left"
    slip: float = 1.0

    def __post_init__(self) -> None:
        if self.kind not in FAULT_KINDS:
            hint = suggest(str(self.kind), FAULT_KINDS)
            raise FaultError(f"fault: unknown kind {self.kind!r}{hint}; one of "
                             f"{', '.join(FAULT_KINDS)}")
        for k in ("start", "duration", "slip"):
            v = getattr(self, k)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or math.isnan(v):
                raise FaultError(f"fault {self.kind}: {k} must be a number, got {v!r}")
        if not math.isfinite(self.start):
            raise FaultError(f"fault {self.kind}: start must be finite, got {self.start}")
        if self.duration <= 0:
            raise FaultError(f"fault {self.kind}: duration must be > 0, got {self.duration}")
        if self.wheel not in ("left", "right"):
            raise FaultError(f"fault {self.kind}: wheel must be 'left' or 'right', "
                             f"got {self.wheel!r}")
        if not 0.0 <= self.slip <= 1.0:
            raise FaultError(f"fault {self.kind}: slip must be in [0, 1], got {self.slip}")

    @property
    def end(self) -> float:
        return self.start + self.duration

    def active(self, t: float) -> bool:
        return self.start <= t < self.end


def fault_from_mapping(d: Mapping[str, Any], where: str = "fault") -> Fault:
    """A Fault from a scenario mapping such as ``{kind: stuck_wheel, start: 4, duration: 2,
    wheel: left}`` (``type`` is accepted for ``kind``)."""
    if not isinstance(d, Mapping):
        raise FaultError(f"{where}: expected a mapping, got {d!r}")
    d = dict(d)
    if "type" in d and "kind" not in d:
        d["kind"] = d.pop("type")
    for k in d:
        if k not in _KEYS:
            raise FaultError(f"{where}: unknown key '{k}'{suggest(str(k), _KEYS)}")
    if "kind" not in d or "start" not in d:
        raise FaultError(f"{where}: needs 'kind' and 'start'")
    try:
        return Fault(**d)
    except FaultError as e:
        raise FaultError(f"{where}: {e}") from None
    except TypeError as e:
        raise FaultError(f"{where}: {e}") from None
