"""The simulator's world and physics behind a Kobuki and a URG-04LX emulator.

``SimDevices(sim, rng)`` builds the two emulators and plugs them into the ``sim://`` registry, so
the real drivers (``hw.drivers.kobuki``, ``hw.drivers.urg04lx``) run a mission through real byte
streams while the simulator stays the ground truth:

- Kobuki: every 50 Hz emulator tick turns the commanded wheel speeds into a body twist for the
  simulator's base, steps the physics to that tick, and hands the wheel travel the simulator's
  odometry saw back as encoder motion (so slip, faults and contacts reach the encoders); the
  bumper and battery voltage follow the simulator too.
- URG-04LX: each scan is ray cast in the simulator's world (map + objects at the scan's time)
  from the laser's true pose at mid-sweep, with the simulated laser's range noise. The
  simulator's laser faults reach the wire: ``laser_dropout`` unplugs the emulated laser (the
  driver sees its port die and reconnects when the fault ends), ``laser_frozen`` repeats the
  last ranges under fresh time stamps.

Everything runs on the simulator's clock: drivers polled in lock-step on a SimClock give one trace
per seed.
"""

from __future__ import annotations

import bisect
import math
from typing import Any

import numpy as np

import hw.emulators as emu
from hw.devices import poll_devices
from hw.drivers import kobuki_codec as kc
from hw.emulators.kobuki import KobukiEmulator
from hw.emulators.link import Faults, Link
from hw.emulators.urg04lx import GEOM, Urg04lxEmulator
from hw.sim.sensors import scan_ranges
from hw.sim.simulator import Simulator
from navcore.types import Pose2D, Twist

_HISTORY_S = 2.0         # true poses kept for scans measured in the past (a sweep is 0.1 s)


class SimDevices:
    """A Kobuki and a URG-04LX emulator driven by ``sim`` (which must have a laser).

    ``urls`` names the ``sim://`` ports to hand the drivers once ``plug`` has registered the
    emulators; ``unplug`` removes them from the registry again."""

    def __init__(self, sim: Simulator, rng: np.random.Generator, ident: str = "sim") -> None:
        if sim.config.laser is None:
            raise ValueError("SimDevices: the simulator has no laser to feed the URG-04LX "
                             "emulator (sim.laser.enabled is false)")
        self.sim = sim
        self.clock = sim.clock
        self.ident = ident
        self.mount: Pose2D = sim.config.laser.mount
        self._noise = float(sim.config.laser.range_noise_stddev)
        self._rng = rng
        self._t = sim.time
        p = sim.true_pose()
        self._times = [self._t]
        self._poses = [(p.x, p.y, p.theta)]
        self.base = KobukiEmulator(self.clock, motion_source=self._wheels)
        self.laser = Urg04lxEmulator(self.clock, ranges_source=self._ranges)
        odo = sim.base.odometry()
        self._odom = odo.pose if odo is not None else Pose2D()
        self.links: dict[str, Link] = {}
        self._dropped = False          # the laser link is unplugged by a laser_dropout fault
        self._last_ranges: np.ndarray | None = None

    @property
    def urls(self) -> dict[str, str]:
        """Role -> ``hw.devices`` URL of the plugged emulators."""
        return {"base": f"kobuki://sim?id={self.ident}-base",
                "laser": f"urg04lx://sim?id={self.ident}-laser"}

    def plug(self, faults: dict[str, Faults] | None = None, seed: int = 0) -> dict[str, str]:
        """Register both emulators, with fault injection per role (``{"laser": Faults(...)}``)
        on their wires; returns ``urls``."""
        faults = faults or {}
        unknown = set(faults) - {"base", "laser"}
        if unknown:
            raise ValueError(f"SimDevices.plug: faults for unknown role(s) {sorted(unknown)}")
        self.links = {"base": emu.plug(f"{self.ident}-base", self.base, faults.get("base"),
                                       seed),
                      "laser": emu.plug(f"{self.ident}-laser", self.laser, faults.get("laser"),
                                        seed + 1)}
        return self.urls

    def unplug(self) -> None:
        for role in self.links:
            emu.unplug(f"{self.ident}-{role}")
        self.links = {}

    # -- the base ------------------------------------------------------------------------------
    def _wheels(self, dt: float, v_left: float, v_right: float) -> tuple[float, float]:
        """One emulator tick: command the simulator, step it, return (left, right) travel."""
        sim = self.sim
        sim.base.send(Twist(0.5 * (v_left + v_right), 0.0, (v_right - v_left) / kc.WHEEL_BASE))
        self._t += dt
        sim.step_to(self._t)
        odo = sim.base.odometry()
        # the odometry increment since the last tick, in the old odometry frame: forward travel
        # and turn, split over the Kobuki's wheels
        d = odo.pose.relative_to(self._odom)
        self._odom = odo.pose
        dth = d.theta
        ds = math.copysign(math.hypot(d.x, d.y), d.x)
        half = 0.5 * kc.WHEEL_BASE
        self.base.bumper = 0x02 if sim.bumper_pressed() else 0      # centre bumper
        battery = sim.base.battery()
        if battery is not None:
            self.base.battery_v = battery.voltage
        p = sim.true_pose()
        self._times.append(sim.time)
        self._poses.append((p.x, p.y, p.theta))
        if self._times[0] < sim.time - 2 * _HISTORY_S:
            k = bisect.bisect_left(self._times, sim.time - _HISTORY_S)
            del self._times[:k], self._poses[:k]
        self._laser_dropout(sim.time)
        return ds - dth * half, ds + dth * half

    def _laser_dropout(self, t: float) -> None:
        """Unplug the laser while the simulator has a laser_dropout fault, replug after."""
        link = self.links.get("laser")
        if link is None:
            return
        down = self.sim.fault_active("laser_dropout", t) is not None
        if down and not self._dropped:
            link.unplug()
            self._dropped = True
        elif not down and self._dropped:
            link.replug()
            self._dropped = False

    # -- the laser -----------------------------------------------------------------------------
    def pose_at(self, t: float) -> Pose2D:
        """True base pose at time ``t``, interpolated between physics ticks (clamped to the
        poses known: the newest when ``t`` is ahead of the simulator)."""
        k = bisect.bisect_right(self._times, t)
        if k == 0:
            return Pose2D(*self._poses[0])
        if k == len(self._times):
            return Pose2D(*self._poses[-1])
        t0, t1 = self._times[k - 1], self._times[k]
        a = (t - t0) / (t1 - t0) if t1 > t0 else 0.0
        (x0, y0, th0), (x1, y1, th1) = self._poses[k - 1], self._poses[k]
        dth = math.remainder(th1 - th0, 2 * math.pi)
        return Pose2D(x0 + a * (x1 - x0), y0 + a * (y1 - y0), th0 + a * dth)

    def _ranges(self, t: float, angles: np.ndarray) -> np.ndarray:
        """Ranges (m) of the beams at ``angles`` (laser frame, evenly spaced) for the sweep whose
        step 0 was at ``t``: cast from the laser's true pose at mid-sweep (a sweep is 0.1 s)."""
        n = len(angles)
        inc = float(angles[1] - angles[0]) if n > 1 else 0.0
        mid = t + 0.5 * 60.0 / GEOM.scan_rpm
        if (self._last_ranges is not None and len(self._last_ranges) == n
                and self.sim.fault_active("laser_frozen", mid) is not None):
            return self._last_ranges.copy()
        lp = self.pose_at(mid).compose(self.mount)
        w = self.sim.world
        circles, segments = w.shapes_at(mid)
        out = np.empty(n, np.float32)
        seed = int(self._rng.integers(0, 2 ** 32)) if self._noise > 0 else 0
        scan_ranges(w.clearance, w.origin_x, w.origin_y, w.resolution, lp.x, lp.y,
                    lp.theta + float(angles[0]), inc, GEOM.dmax / 1000.0, circles, segments,
                    self._noise, seed, math.inf, out)
        self._last_ranges = out.astype(np.float64)
        return self._last_ranges.copy()


def lockstep_start(drivers: dict[str, Any], clock: Any, step: float = 0.02,
                   limit: float = 5.0) -> None:
    """Start thread-free ``drivers`` in lock-step: move ``clock`` on by ``step`` and poll them,
    until every one is connected and has delivered a message (so the first control cycle has
    odometry and a scan). Raises TimeoutError naming the laggards after ``limit`` clock seconds."""
    t_end = clock.now() + limit
    while True:
        clock.sleep_until(clock.now() + step)   # the base emulator sends at 50 Hz: one period
        poll_devices(drivers)
        if all(d.connected and d.delivered > 0 for d in drivers.values()):
            return
        if clock.now() >= t_end:
            missing = {r: d.last_error or "connected, no message yet"
                       for r, d in drivers.items() if not (d.connected and d.delivered > 0)}
            raise TimeoutError(f"devices not ready after {limit:g} s: {missing}")
