"""The safety gate: every sensing fault stops the robot within one control period."""

from __future__ import annotations

import math
import threading
import time

import numpy as np
import pytest

from executive.config import SAFETY_PARAMS
from executive.safety import SPACINGS_KEPT, SafetyGate, Watchdog, _Arrivals
from navcore.params import ParameterError, Parameters
from navcore.types import LaserScan, Odometry, Pose2D, Twist

PERIOD = 0.1
GO = Twist(0.3, 0.0, 0.0)


class Feed:
    """A robot driving at 0.3 m/s along x with a laser and odometry at the control rate; each
    attribute can be overridden to script a fault."""

    def __init__(self) -> None:
        self.gate = SafetyGate()
        self.t = 0.0
        self.x = 0.0
        self.scan: LaserScan | None = None
        self.odom: Odometry | None = None

    def make_scan(self, t: float) -> LaserScan:
        d = 3.0 - self.x
        return LaserScan(t, -1.0, 1.0, 1.0, 0.0, PERIOD, 0.1, 5.0, np.array([d, d + 0.1, d]))

    def make_odom(self, t: float) -> Odometry:
        return Odometry(t, Pose2D(self.x, 0.0, 0.0), Twist(0.3, 0.0, 0.0))

    def tick(self, *, scan: bool = True, odom: bool = True, cmd: Twist | None = GO, **kw):
        self.x += 0.3 * PERIOD
        if scan:
            self.scan = self.make_scan(self.t)
        if odom:
            self.odom = self.make_odom(self.t)
        r = self.gate.filter(cmd, self.t, scan_stamp=self.scan.stamp if self.scan else None,
                             odom_stamp=self.odom.stamp if self.odom else None,
                             measured=self.odom.twist if self.odom else None,
                             scan=self.scan, odom=self.odom, **kw)
        self.t = round(self.t + PERIOD, 9)
        return r


def _healthy(f: Feed, n: int = 10) -> None:
    for _ in range(n):
        r = f.tick()
        assert r.faults == [] and r.cmd.vx == 0.3


def test_healthy_robot_drives() -> None:
    _healthy(Feed(), 50)


def test_laser_dropout_stops_at_the_first_missed_scan() -> None:
    f = Feed()
    _healthy(f)
    r = f.tick(scan=False)  # the scan this tick promised is missing
    assert r.cmd == Twist.zero() and "stale_laser" in r.faults
    r = f.tick(scan=False)
    assert r.cmd == Twist.zero() and "stale_laser" in r.faults
    _healthy(f, 3)  # scans back: drives again


def test_odometry_dropout_stops_at_the_first_missed_message() -> None:
    f = Feed()
    _healthy(f)
    r = f.tick(odom=False)
    assert r.cmd == Twist.zero() and r.faults == ["stale_odometry"]


def test_slower_laser_is_not_stale_between_its_scans() -> None:
    f = Feed()
    for i in range(30):  # a scan every second tick (10 Hz laser, 20 Hz loop)
        r = f.tick(scan=i % 2 == 0)
        assert r.faults == [], i
    f.tick(scan=False)
    r = f.tick(scan=False)  # the second-tick scan is missing now
    assert "stale_laser" in r.faults


@pytest.mark.parametrize("stamp,fault", [(math.nan, "laser_stamp_invalid"),
                                         (math.inf, "laser_stamp_invalid"),
                                         (+5.0, "laser_stamp_invalid")])
def test_bad_scan_stamp_stops_at_once(stamp: float, fault: str) -> None:
    f = Feed()
    _healthy(f)
    f.make_scan = lambda t, make=f.make_scan: make(t + stamp if math.isfinite(stamp) else stamp)
    r = f.tick()
    assert r.cmd == Twist.zero() and r.faults == [fault]


def test_bad_odometry_stamp_stops_at_once() -> None:
    f = Feed()
    _healthy(f)
    f.make_odom = lambda t, make=f.make_odom: make(math.nan)
    r = f.tick()
    assert r.cmd == Twist.zero() and r.faults == ["odometry_stamp_invalid"]


def test_frozen_laser_with_fresh_stamps_stops_at_the_first_repeat_while_moving() -> None:
    f = Feed()
    _healthy(f)
    frozen = f.scan.ranges  # the laser repeats its last scan with fresh stamps from now on
    f.make_scan = lambda t: LaserScan(t, -1.0, 1.0, 1.0, 0.0, PERIOD, 0.1, 5.0, frozen.copy())
    for _ in range(5):
        r = f.tick()
        assert r.cmd == Twist.zero() and r.faults == ["laser_frozen"]


def test_identical_scans_while_standing_are_fine() -> None:
    gate = SafetyGate()
    ranges = np.ones(5)
    for i in range(20):
        t = i * PERIOD
        scan = LaserScan(t, -1.0, 1.0, 0.5, 0.0, PERIOD, 0.1, 5.0, ranges)
        odom = Odometry(t, Pose2D(), Twist())
        r = gate.filter(Twist(0.0, 0.0, 0.0), t, scan_stamp=t, odom_stamp=t,
                        measured=odom.twist, scan=scan, odom=odom)
        assert r.faults == []


def test_frozen_odometry_restamped_stops_at_once() -> None:
    f = Feed()
    _healthy(f)
    f.make_odom = lambda t: Odometry(t, Pose2D(1.0, 0.0, 0.0), Twist(0.3, 0.0, 0.0))
    f.tick()  # the pose jumps to the frozen value: new pose, nothing to compare
    for _ in range(5):
        r = f.tick()
        assert r.cmd == Twist.zero() and "odometry_frozen" in r.faults


@pytest.mark.parametrize("phase", ["sense", "estimate", "perceive"])
def test_a_phase_that_raised_stops_the_robot_that_cycle(phase: str) -> None:
    f = Feed()
    _healthy(f)
    r = f.tick(errors=[phase])
    assert r.cmd == Twist.zero() and r.faults == [f"{phase}_error"]
    _healthy(f, 1)


def test_overrun_beyond_the_bound_stops() -> None:
    f = Feed()
    _healthy(f)
    assert f.tick(cycle_periods=1.2).faults == []
    r = f.tick(cycle_periods=15.0)
    assert r.cmd == Twist.zero() and r.faults == ["loop_overrun"]


@pytest.mark.parametrize("name,value", [
    ("sensor_timeout", 5.0), ("max_vel_x", 1.0), ("min_vel_x", -1.0), ("stall_timeout", 0.0),
    ("stall_timeout", 10.0), ("stop_on_bumper", False), ("stall_speed", 0.0),
    ("frozen_scans", 50), ("watchdog_periods", 5.0)])
def test_a_tree_cannot_loosen_the_gate(name: str, value) -> None:
    params = Parameters(SAFETY_PARAMS)
    SafetyGate(params)
    before = params.as_dict()
    with pytest.raises(ParameterError, match="would loosen"):
        params.set({name: value})
    assert params.as_dict() == before


def test_a_tree_cannot_disable_the_timeout_with_inf() -> None:
    params = Parameters(SAFETY_PARAMS)
    SafetyGate(params)
    with pytest.raises(ParameterError, match="finite"):
        params.set({"sensor_timeout": math.inf})
    assert params.sensor_timeout == 0.5


def test_a_tree_may_tighten_the_gate() -> None:
    params = Parameters(SAFETY_PARAMS)
    gate = SafetyGate(params)
    previous = params.set({"max_vel_x": 0.1, "sensor_timeout": 0.2, "stall_speed": 0.05})
    r = gate.filter(Twist(0.3, 0, 0), 0.0, scan_stamp=0.0, odom_stamp=0.0, measured=GO)
    assert r.cmd.vx == pytest.approx(0.1) and r.clipped
    params.set(previous)  # SetParameters restores: back to the config's values is allowed
    assert params.max_vel_x == 0.55


def test_watchdog_stops_a_stalled_loop_once() -> None:
    stops: list[float] = []
    done = threading.Event()

    def stop() -> None:
        stops.append(1.0)
        done.set()

    dog = Watchdog(0.3, stop)
    for _ in range(3):  # a loop that keeps kicking: no stop
        dog.kick()
    assert stops == []
    assert done.wait(5.0)  # the loop stalls: the watchdog stops the base, once
    time.sleep(0.15)
    assert stops == [1.0] and dog.fired == 1
    dog.close()


def test_a_sensor_that_sometimes_skips_a_cycle_stops_the_robot_once_only() -> None:
    f = Feed()
    _healthy(f, 20)
    assert "stale_laser" in f.tick(scan=False).faults  # the first skip: unknown jitter
    _healthy(f, 5)
    for _ in range(10):                                 # from now on a skip is jitter
        assert f.tick(scan=False).faults == []
        _healthy(f, 3)
    f.tick(scan=False)
    assert "stale_laser" in f.tick(scan=False).faults   # two in a row is more than jitter


def test_the_longest_arrival_spacing_kept_is_the_max_of_the_last_ones():
    rng = np.random.default_rng(2)
    arrivals = _Arrivals()
    # rising, falling, repeated and random spacings, past the number kept
    gaps = np.concatenate([np.linspace(0.05, 0.2, 150), np.linspace(0.3, 0.01, 150),
                           np.full(50, 0.1), rng.choice([0.05, 0.1, 0.2], 300),
                           rng.uniform(0.0, 1.0, 300)])
    for g in gaps:
        arrivals._add_spacing(float(g))
        assert len(arrivals.spacings) <= SPACINGS_KEPT
        assert arrivals.longest() == max(arrivals.spacings)
