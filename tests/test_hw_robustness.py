"""Drivers of weak protocols drop implausible frames (and count them in their diagnostics), and
every driver connects to a device that answers up to a second late (issue 18)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import hw.emulators as emu
from hw.drivers import kobuki_codec as kc
from hw.drivers import razor_codec as rc
from hw.drivers import vectornav_codec as vc
from hw.drivers.arduino import ArduinoBaseDriver
from hw.drivers.kobuki import KobukiDriver
from hw.drivers.razor import RazorDriver
from hw.drivers.serial_link import DEVICE_LATENCY
from hw.drivers.urg04lx import Urg04lxDriver
from hw.drivers.vectornav import VectorNavDriver
from hw.emulators.arduino import ArduinoBridgeEmulator
from hw.emulators.harness import wait_until
from hw.emulators.kobuki import KobukiEmulator
from hw.emulators.razor import RazorEmulator
from hw.emulators.urg04lx import Urg04lxEmulator
from hw.emulators.vectornav import VectorNavEmulator
from navcore.clock import SimClock, WallClock
from navcore.types import Twist, angle_diff
from tests.test_hw_support import clean_registry  # noqa: F401 (pytest fixture)

# ------------------------------------------------------------------ slow devices


def _ranges(t: float, angles: np.ndarray) -> np.ndarray:
    return 1.0 + 0.5 * np.cos(3 * angles)


@pytest.mark.parametrize("kind", ["urg04lx", "razor", "vectornav", "arduino", "kobuki"])
def test_device_answering_a_second_late_connects_and_delivers(clean_registry, kind: str
                                                              ) -> None:
    clock = WallClock()
    emulator, driver, read = {
        "urg04lx": (lambda: Urg04lxEmulator(clock, _ranges), Urg04lxDriver, "scan"),
        "razor": (lambda: RazorEmulator(clock), RazorDriver, "imu"),
        "vectornav": (lambda: VectorNavEmulator(clock), VectorNavDriver, "imu"),
        "arduino": (lambda: ArduinoBridgeEmulator(clock), ArduinoBaseDriver, "odometry"),
        "kobuki": (lambda: KobukiEmulator(clock), KobukiDriver, "odometry"),
    }[kind]
    emu.plug(f"{kind}-slow", emulator())
    with driver(f"sim://{kind}?id={kind}-slow&delay={DEVICE_LATENCY}", clock) as d:
        assert d.wait_connected(12.0), d.last_error
        if kind in ("arduino", "kobuki"):
            d.send(Twist(0.05, 0.0, 0.0))
        assert wait_until(lambda: getattr(d, read)() is not None and d.delivered >= 2, 8.0), \
            d.diagnostics()
        assert d.connects == 1  # no reconnect while waiting for the late replies


# ------------------------------------------------------------------ plausibility gates

def _turning(t: float) -> tuple[float, float]:
    """(yaw, yaw rate): a steady 0.5 rad/s turn."""
    return math.remainder(0.5 * t, 2 * math.pi), 0.5


def _feed_corrupted(d, clock: SimClock, lines: list[bytes], rng: np.random.Generator,
                    p_flip: float) -> list:
    """Feed the lines one per 20 ms with random bytes flipped; return the samples delivered."""
    got = []
    for line in lines:
        data = bytearray(line)
        for i in range(len(data) - 2):
            if rng.random() < p_flip:
                data[i] = int(rng.integers(0x20, 0x7f))
        before = d.delivered
        d._on_bytes(bytes(data))
        if d.delivered > before:
            got.append((clock.now(), d.imu()))
        clock.advance(0.02)
    return got


@pytest.mark.parametrize("kind", ["razor", "vectornav"])
def test_imu_delivers_no_wrong_value_from_corrupted_lines(kind: str) -> None:
    clock = SimClock(1.0)
    d = (RazorDriver if kind == "razor" else VectorNavDriver)("sim://x", clock)  # not started
    rng = np.random.default_rng(5)
    lines = []
    for k in range(1500):
        yaw, rate = _turning(1.0 + 0.02 * k)
        ypr = (-math.degrees(yaw), 0.0, 0.0)
        if kind == "razor":
            lines.append(rc.RazorSample(*ypr, (1.0, 2.0, -256.0),
                                        (0.0, 0.0, -rate)).line())
        else:
            lines.append(vc.Ymr(ypr, (0.0, 0.0, 0.0), (0.0, 0.0, -9.8),
                                (0.0, 0.0, -rate)).line())
    got = _feed_corrupted(d, clock, lines, rng, 0.004)
    wrong = [s for t, s in got if abs(angle_diff(s.yaw, _turning(t)[0])) > 0.02
             or abs(s.angular_velocity_z - 0.5) > 0.05]
    assert len(got) > 0.6 * len(lines)   # most lines still get through
    assert wrong == []
    diag = d.diagnostics()
    assert diag["rejected"] > 0 and diag["delivered"] == len(got)


def test_kobuki_drops_a_frame_whose_encoder_jumps() -> None:
    odo = kc.KobukiOdometry(use_imu_heading=False)
    base = kc.BasicSensors(timestamp_ms=1000, left_encoder=100, right_encoder=100)
    odo.update(kc.Feedback(base))
    ok = kc.Feedback(kc.BasicSensors(timestamp_ms=1020, left_encoder=110, right_encoder=110))
    assert odo.implausibility(ok, 2.0, 6.0) is None
    # two flipped bits in one column keep the XOR: the count jumps by 0x4000 ticks in 20 ms
    bad = kc.Feedback(kc.BasicSensors(timestamp_ms=1020, left_encoder=100 + 0x4000 + 10,
                                      right_encoder=110))
    assert "left wheel moved" in odo.implausibility(bad, 2.0, 6.0)


def test_kobuki_driver_counts_implausible_frames() -> None:
    clock = SimClock(1.0)
    d = KobukiDriver("sim://kobuki", clock)     # not started: frames are fed by hand

    def frame(ts: int, left: int, right: int) -> bytes:
        b = kc.BasicSensors(timestamp_ms=ts, left_encoder=left, right_encoder=right,
                            battery_dv=160)
        return kc.frame(kc.sub_payload(1, b.pack()))
    d._on_bytes(frame(1000, 100, 100))
    d._on_bytes(frame(1020, 110, 110))
    x = d.odometry().pose.x
    d._on_bytes(frame(1040, 110 + 0x4000, 120))
    assert d.implausible == 1 and d.diagnostics()["implausible"] == 1
    assert d.odometry().pose.x == x       # the jump never reached the odometry
    d._on_bytes(frame(1060, 130, 130))
    assert d.delivered == 3 and d.odometry().pose.x > x


def test_hardware_io_reports_each_drivers_diagnostics() -> None:
    from executive.robot_io import HardwareIO
    clock = SimClock(1.0)
    base, imu = KobukiDriver("sim://kobuki", clock), RazorDriver("sim://razor", clock)
    imu._on_bytes(b"#YPRAG=1.0\r\n")              # a garbled line: rejected
    diag = HardwareIO({"base": base, "imu": imu}).diagnostics()
    assert set(diag) == {"base", "imu"}
    assert diag["imu"]["rejected"] == 1 and diag["base"]["delivered"] == 0
