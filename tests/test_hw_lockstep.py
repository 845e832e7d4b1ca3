"""Lock-step (thread-free) drivers on a SimClock: a small closed loop through real byte streams.

The base emulator's wheels move the robot; the laser emulator measures a wall from the robot's
true pose; the loop reads the laser through the URG driver, commands the Kobuki driver, and
stops in front of the wall. Run twice, the byte streams and therefore the runs are identical.
"""

from __future__ import annotations

import numpy as np
import pytest

import hw.emulators as emu
from hw.drivers.kobuki import KobukiDriver
from hw.drivers.urg04lx import Urg04lxDriver
from hw.emulators.kobuki import KobukiEmulator
from hw.emulators.urg04lx import Urg04lxEmulator
from navcore.clock import SimClock
from navcore.types import Twist

WALL_X = 3.0


def run(tag: str, faults: str = "") -> tuple[list, KobukiEmulator]:
    clock = SimClock()
    base = KobukiEmulator(clock)

    def ranges(t: float, angles: np.ndarray) -> np.ndarray:
        x, _, th = base.pose
        c = np.cos(angles + th)
        with np.errstate(divide="ignore"):
            return np.where(c > 1e-3, (WALL_X - x) / np.maximum(c, 1e-3), np.inf)

    emu.plug(f"{tag}-base", base, seed=1)
    emu.plug(f"{tag}-laser", Urg04lxEmulator(clock, ranges), seed=2)
    kob = KobukiDriver(f"sim://kobuki?id={tag}-base", clock)
    urg = Urg04lxDriver(f"sim://urg04lx?id={tag}-laser{faults}", clock)
    trace = []
    try:
        for _ in range(300):
            clock.advance(0.05)
            kob.poll()
            urg.poll()
            scan = urg.scan()
            odo = kob.odometry()
            if scan is None or odo is None:
                continue
            ahead = float(np.min(scan.ranges[np.abs(scan.angles()) < 0.1]))
            kob.send(Twist(0.3, 0.0, 0.0) if ahead > 1.0 else Twist())
            trace.append((round(clock.now(), 3), odo.pose.x, ahead, kob.commanded(), scan.stamp))
    finally:
        kob.close()
        urg.close()
        emu.unplug_all()
    return trace, base


def test_closed_loop_stops_before_the_wall_and_is_deterministic() -> None:
    a, base = run("ls1")
    b, _ = run("ls2")
    assert a == b                                           # same clock, same bytes, same run
    x_true = base.pose[0]
    assert base.speed == 0 and 1.9 <= x_true <= 2.05        # stopped about 1 m from the wall
    assert a[-1][1] == pytest.approx(x_true, abs=1e-3)      # odometry agrees with the wheels
    assert a[-1][2] == pytest.approx(WALL_X - x_true, abs=0.01)
    moving = [t for t in a if t[3] == (300, 0)]
    assert moving and moving[0][0] < 1.0                    # it did drive first
    # scan stamps: the sensor's timer mapped onto the clock, one rotation (0.1 s) apart, and
    # each at least a sweep (steps 0..725, 70.9 ms) before the scan was read
    stamps = sorted({t[4] for t in a})
    assert np.allclose(np.diff(stamps), 0.1, atol=1.5e-3)
    assert all(t[4] <= t[0] - 726 * 60 / 600 / 1024 + 1e-9 for t in a)


def test_closed_loop_survives_a_noisy_laser_line() -> None:
    trace, base = run("ls3", "&corrupt=0.0005&garbage=0.05")
    assert base.speed == 0 and 1.85 <= base.pose[0] <= 2.1
