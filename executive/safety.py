"""The safety gate between the tree's ``cmd_vel`` and the base.

Every command passes here: it is clipped to hard velocity limits, and it becomes zero for the
period when any of these holds (each returned as a short fault name the executive records):

- ``sense_error`` / ``estimate_error`` / ``perceive_error``: that phase raised in this cycle;
- ``stale_laser`` / ``stale_odometry``: no message, one older than ``sensor_timeout``, or a tick
  without a new message although the sensor's own rate promised one (learned from the spacing of
  arrivals while healthy);
- ``laser_stamp_invalid`` / ``odometry_stamp_invalid``: a stamp that is NaN/inf or lies more than
  ``stamp_tolerance`` in the future;
- ``laser_frozen``: ``frozen_scans`` consecutive scans with fresh stamps and bit-identical ranges
  while odometry reports motion (held until the ranges change);
- ``odometry_frozen``: a fresh odometry message whose pose did not change although its twist says
  the robot moves (held until the pose changes);
- ``loop_overrun``: the previous cycle took longer than ``watchdog_periods`` control periods of
  wall time (only when the executive runs on a wall clock; ``Watchdog`` stops the base during
  such a stall);
- ``stall``: motion commanded for ``stall_timeout`` while the base reports none;
- ``bumper`` (forward motion only) and ``non_finite_command``.

The gate's parameters may be changed from a tree (``SetParameters`` on ``safety``) only to be
tighter than the robot config made them: never loosened, never switched off. The gate never raises.
"""

from __future__ import annotations

import math
import threading
from collections import deque
from dataclasses import dataclass, field
from typing import Any, Callable

import numpy as np

from navcore.params import ParameterError, Parameters
from navcore.types import LaserScan, Odometry, Twist

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

# Which way each safety parameter may move from a tree: "down" = only smaller, "up" = only
# larger, "keep_true" = cannot be switched off. A parameter not listed cannot change at all.
TIGHTEN = {"max_vel_x": "down", "min_vel_x": "up", "max_vel_y": "down", "max_vel_theta": "down",
           "sensor_timeout": "down", "stall_timeout": "down", "stall_speed": "up",
           "stop_on_bumper": "keep_true", "stamp_tolerance": "down", "frozen_scans": "down",
           "watchdog_periods": "down"}


SPACINGS_KEPT = 200  # arrival spacings a sensor's rate is learnt from


class _Arrivals:
    """When one sensor's messages arrive: a tick without a new message, later after the last
    arrival than any spacing seen while healthy, is a missed message."""

    __slots__ = ("stamp", "arrived", "spacings", "missing", "_count", "_peaks")

    def __init__(self) -> None:
        self.stamp: float | None = None
        self.arrived: float | None = None
        self.spacings: deque[float] = deque(maxlen=SPACINGS_KEPT)
        self.missing = False
        self._count = 0  # spacings appended so far
        # (number, spacing) of the spacings kept that no later one equals or exceeds, oldest
        # first: the first is the longest kept (max() over 200 floats took ~4 us per tick)
        self._peaks: deque[tuple[int, float]] = deque()

    def _add_spacing(self, gap: float) -> None:
        self.spacings.append(gap)
        peaks = self._peaks
        while peaks and peaks[-1][1] <= gap:
            peaks.pop()
        peaks.append((self._count, gap))
        self._count += 1
        if peaks[0][0] < self._count - SPACINGS_KEPT:  # dropped from ``spacings``
            peaks.popleft()

    def longest(self) -> float:
        """max(spacings) (there is at least one)."""
        return self._peaks[0][1]

    def missed(self, stamp: float, now: float) -> bool:
        if stamp != self.stamp:  # a new message
            if self.arrived is not None:
                gap = now - self.arrived
                # a gap up to twice the usual one is the sensor's jitter (a 10 Hz laser read by
                # a 10 Hz loop sometimes skips a cycle): learnt, so that it stops the robot once
                # at most; a longer one was a drop-out and is not
                if not self.missing or (self.spacings and gap <= 2.0 * self.longest()):
                    self._add_spacing(gap)
            self.stamp, self.arrived, self.missing = stamp, now, False
            return False
        if len(self.spacings) >= 3 and self.arrived is not None:
            if now - self.arrived >= self.longest() - 1e-9:
                self.missing = True
        return self.missing


class SafetyGate:
    """Velocity limits, sensor watchdogs (stale, invalid stamps, frozen content), phase errors,
    overruns and stall. Any fault sends zero velocity."""

    def __init__(self, params: Parameters | None = None, require_laser: bool = True) -> None:
        self.params = params if params is not None else Parameters(SAFETY_PARAMS)
        self.require_laser = require_laser
        self._baseline = self.params.as_dict()
        self.params.before_change(self._refuse_loosening)
        self._stall_since: float | None = None
        self._laser = _Arrivals()
        self._odom = _Arrivals()
        self._ranges: np.ndarray | None = None
        self._repeats = 0
        self._laser_frozen = False
        self._odom_pose: Any = None
        self._odom_frozen = False

    def reset(self) -> None:
        self._stall_since = None

    def _refuse_loosening(self, new: dict[str, Any]) -> None:
        """A tree may tighten the gate, never loosen or disable it (``Parameters.before_change``
        runs after validation; raising here rejects the whole change)."""
        for name, value in new.items():
            base = self._baseline.get(name)
            rule = TIGHTEN.get(name)
            ok = (value == base or (rule == "down" and value <= base)
                  or (rule == "up" and value >= base) or (rule == "keep_true" and value))
            if name == "stall_timeout" and base > 0 and value <= 0:
                ok = False  # 0 switches the stall watchdog off
            if not ok:
                raise ParameterError(f"safety: parameter '{name}' = {value!r} would loosen the "
                                     f"safety gate (robot config: {base!r}); a tree may only "
                                     f"tighten it")

    # --- the checks ---------------------------------------------------------------------------
    def _stamp_faults(self, stamp: float | None, now: float, tol: float, timeout: float,
                      arrivals: _Arrivals, name: str, faults: list[str]) -> bool:
        """Append ``stale_<name>`` or ``<name>_stamp_invalid``; True when the message is usable."""
        if stamp is None:
            faults.append(f"stale_{name}")
            return False
        if not math.isfinite(stamp) or stamp > now + tol:
            faults.append(f"{name}_stamp_invalid")
            return False
        if arrivals.missed(stamp, now) or now - stamp > timeout:
            faults.append(f"stale_{name}")
            return False
        return True

    def _laser_faults(self, scan: LaserScan, fresh: bool, moving: bool, n_frozen: int,
                      faults: list[str]) -> None:
        if fresh:
            ranges = scan.ranges
            prev = self._ranges
            # np.array_equal's test without its Python wrapper (this runs every cycle)
            same = (prev is not None and prev.shape == ranges.shape
                    and (ranges.size == 0 or ranges[0] == prev[0])  # most scans differ at once
                    and bool((ranges == prev).all()))
            self._repeats = self._repeats + 1 if same else 0
            self._ranges = ranges
            if not same:
                self._laser_frozen = False
            elif moving and self._repeats >= n_frozen - 1:
                self._laser_frozen = True
        if self._laser_frozen:
            faults.append("laser_frozen")

    def _odom_faults(self, odom: Odometry, fresh: bool, still: float, faults: list[str]) -> None:
        if fresh:
            pose = odom.pose
            prev = self._odom_pose
            same = prev is not None and (pose.x, pose.y, pose.theta) == prev
            tw = odom.twist
            says_moving = abs(tw.vx) > still or abs(tw.vy) > still or abs(tw.wz) > still
            if not same:
                self._odom_frozen = False
            elif says_moving:
                self._odom_frozen = True
            self._odom_pose = (pose.x, pose.y, pose.theta)
        if self._odom_frozen:
            faults.append("odometry_frozen")

    def filter(self, cmd: Twist | None, now: float, *, scan_stamp: float | None,
               odom_stamp: float | None, measured: Twist | None, bumper: bool = False,
               scan: LaserScan | None = None, odom: Odometry | None = None,
               errors: tuple[str, ...] | list[str] = (), cycle_periods: float | None = None
               ) -> GateResult:
        """Return the command to send at ``now`` given the newest sensor stamps and velocity.

        ``scan``/``odom`` (the newest messages) enable the frozen-content checks; ``errors``
        names the phases that raised this cycle; ``cycle_periods`` is the wall time of the
        previous cycle in control periods (None when not on a wall clock).
        """
        p = _Snapshot(self.params.as_dict())  # one dict copy instead of a dozen lookups
        faults: list[str] = [f"{e}_error" for e in errors]
        still = p.stall_speed
        moving = measured is not None and (abs(measured.vx) > still or abs(measured.vy) > still
                                           or abs(measured.wz) > still)
        timeout, tol = p.sensor_timeout, p.stamp_tolerance
        laser_prev = self._laser.stamp
        if self.require_laser and self._stamp_faults(scan_stamp, now, tol, timeout, self._laser,
                                                     "laser", faults) and scan is not None:
            self._laser_faults(scan, scan_stamp != laser_prev, moving, p.frozen_scans, faults)
        odom_prev = self._odom.stamp
        if self._stamp_faults(odom_stamp, now, tol, timeout, self._odom, "odometry", faults) \
                and odom is not None:
            self._odom_faults(odom, odom_stamp != odom_prev, still, faults)
        if cycle_periods is not None and cycle_periods > p.watchdog_periods:
            faults.append("loop_overrun")
        if cmd is None:
            self._stall_since = None
            return GateResult(_STOP)
        values = (cmd.vx, cmd.vy, cmd.wz)
        isfinite = math.isfinite
        if not (isfinite(values[0]) and isfinite(values[1]) and isfinite(values[2])):
            faults.append("non_finite_command")
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

        moving_cmd = abs(vx) > still or abs(vy) > still or abs(wz) > still
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


class Watchdog:
    """Stops the base when a control cycle stalls on a wall clock: ``kick()`` at every command;
    if no kick follows within ``timeout`` seconds, ``stop()`` is called once from a daemon
    thread (a stalled loop cannot send the zero itself)."""

    def __init__(self, timeout: float, stop: Callable[[], None]) -> None:
        if not timeout > 0:
            raise ValueError(f"Watchdog: timeout must be > 0, got {timeout}")
        self.timeout = timeout
        self._stop = stop
        self._kicked = threading.Event()
        self._closed = False
        self.fired = 0
        self._thread: threading.Thread | None = None

    def kick(self) -> None:
        if self._thread is None:
            self._thread = threading.Thread(target=self._run, name="navbt-watchdog", daemon=True)
            self._thread.start()
        self._kicked.set()

    def _run(self) -> None:
        while not self._closed:
            if self._kicked.wait(self.timeout):
                self._kicked.clear()
                continue
            if self._closed:
                return
            self.fired += 1
            try:
                self._stop()
            except Exception:  # noqa: BLE001 - the loop records the base's errors itself
                pass
            self._kicked.wait()  # stopped once; wait for the loop to come back

    def close(self) -> None:
        self._closed = True
        self._kicked.set()
