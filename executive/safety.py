"""The safety gate between the tree's ``cmd_vel`` and the base.

Every command passes here: it is clipped to hard velocity limits, and it becomes zero when a
watchdog trips: laser or odometry older than ``sensor_timeout``, a stall (motion commanded for
``stall_timeout`` while the base reports none), or a pressed bumper for forward motion. Faults are
returned as short strings so the executive can record them; the gate never raises.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from navcore.params import Parameters
from navcore.types import Twist

from executive.config import SAFETY_PARAMS


@dataclass(slots=True)
class GateResult:
    """The command actually sent, and why it differs from the request (empty when it does not)."""

    cmd: Twist
    faults: list[str] = field(default_factory=list)
    clipped: bool = False


class _Snapshot:
    """Attribute access over a plain dict of parameter values."""

    __slots__ = ("__dict__",)

    def __init__(self, values: dict) -> None:
        self.__dict__ = values


_STOP = Twist.zero()  # immutable: one instance serves every stop


class SafetyGate:
    """Velocity limits, stale-sensor and stall watchdogs. Any fault sends zero velocity."""

    def __init__(self, params: Parameters | None = None, require_laser: bool = True) -> None:
        self.params = params if params is not None else Parameters(SAFETY_PARAMS)
        self.require_laser = require_laser
        self._stall_since: float | None = None

    def reset(self) -> None:
        self._stall_since = None

    def filter(self, cmd: Twist | None, now: float, *, scan_stamp: float | None,
               odom_stamp: float | None, measured: Twist | None, bumper: bool = False
               ) -> GateResult:
        """Return the command to send at ``now`` given the newest sensor stamps and velocity."""
        p = _Snapshot(self.params.as_dict())  # one dict copy instead of a dozen lookups
        if cmd is None:
            self._stall_since = None
            return GateResult(_STOP)
        faults: list[str] = []
        values = (cmd.vx, cmd.vy, cmd.wz)
        isfinite = math.isfinite
        if not (isfinite(values[0]) and isfinite(values[1]) and isfinite(values[2])):
            faults.append("non_finite_command")
        timeout = p.sensor_timeout
        if odom_stamp is None or now - odom_stamp > timeout:
            faults.append("stale_odometry")
        if self.require_laser and (scan_stamp is None or now - scan_stamp > timeout):
            faults.append("stale_laser")
        if faults:
            self._stall_since = None
            return GateResult(_STOP, faults)

        vx = min(max(cmd.vx, p.min_vel_x), p.max_vel_x)
        vy = min(max(cmd.vy, -p.max_vel_y), p.max_vel_y)
        wz = min(max(cmd.wz, -p.max_vel_theta), p.max_vel_theta)
        clipped = (vx, vy, wz) != values
        if bumper and p.stop_on_bumper and vx > 0.0:
            faults.append("bumper")
            vx = 0.0

        still = p.stall_speed
        moving_cmd = abs(vx) > still or abs(vy) > still or abs(wz) > still
        moving = measured is not None and (abs(measured.vx) > still or abs(measured.vy) > still
                                           or abs(measured.wz) > still)
        if moving_cmd and not moving and p.stall_timeout > 0.0:
            if self._stall_since is None:
                self._stall_since = now
            elif now - self._stall_since >= p.stall_timeout:
                # Stop for this period and re-arm, so a recovery gets its own chance to move.
                self._stall_since = None
                return GateResult(_STOP, faults + ["stall"], clipped)
        else:
            self._stall_since = None
        if faults:
            return GateResult(Twist(vx, vy, wz) if vx or vy or wz else _STOP, faults, clipped)
        if vx is cmd.vx and vy is cmd.vy and wz is cmd.wz:  # min/max kept every value: reuse
            return GateResult(cmd, faults, clipped)
        return GateResult(Twist(vx, vy, wz), faults, clipped)
