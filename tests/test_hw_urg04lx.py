"""URG-04LX driver against its emulator: sim:// URL and pty pair, start-up and every fault."""

from __future__ import annotations

import math

import numpy as np
import pytest

import hw.emulators as emu
from hw.drivers.urg04lx import Urg04lxDriver
from hw.emulators.harness import wait_until
from hw.emulators.pty_port import PtyDevice
from hw.emulators.urg04lx import Urg04lxEmulator
from hw.interfaces import Laser
from navcore.clock import WallClock
from tests.test_hw_support import clean_registry  # noqa: F401 (pytest fixture)
from tests.test_hw_support import collect_fresh


def truth(angles: np.ndarray) -> np.ndarray:
    """A static scene whose every beam differs, so a garbled scan cannot pass as a right one."""
    return 1.0 + 0.5 * np.cos(3 * angles) + 0.1 * angles


def source(t: float, angles: np.ndarray) -> np.ndarray:
    return truth(angles)


def check(scan) -> None:
    """Every delivered scan must be the true one, to the millimetre."""
    want = np.round(truth(scan.angles()) * 1000) / 1000
    assert np.allclose(scan.ranges, want, atol=1.5e-3), "a wrong scan was delivered"


def collect(drv: Urg04lxDriver, n: int, timeout: float = 5.0, verify=check) -> list:
    return collect_fresh(drv.scan, n, timeout, verify)


def test_startup_and_streaming_over_sim_url(clean_registry) -> None:
    clock = WallClock()
    link = emu.plug("urg-a", Urg04lxEmulator(clock, source))
    with Urg04lxDriver("sim://urg04lx?id=urg-a", clock) as drv:
        assert isinstance(drv, Laser)
        assert drv.wait_connected(3.0), drv.last_error
        assert link.emulator.commands == ["QT", "SCIP2.0", "TM2", "RS", "SS115200", "PP",
                                          "MD0044072501000"]
        scans = collect(drv, 3)
        assert len(scans) == 3 and drv.rejected == 0
        s = scans[-1]
        assert len(s.ranges) == 682 and s.frame_id == "laser"
        assert s.angle_min == pytest.approx(math.radians(-119.53), abs=1e-4)
        assert s.angle_max == pytest.approx(math.radians(119.88), abs=1e-4)
        assert s.time_increment == pytest.approx(60 / 600 / 1024)
        assert s.scan_time == pytest.approx(0.1) and s.range_max == pytest.approx(5.6)
        assert scans[0].stamp < scans[1].stamp < scans[2].stamp
    assert link.emulator.commands[-1] == "QT"        # streaming stopped on close


def test_parameters_select_steps_and_cluster(clean_registry) -> None:
    clock = WallClock()
    link = emu.plug("urg-b", Urg04lxEmulator(clock, source))
    with Urg04lxDriver("sim://urg04lx?id=urg-b", clock,
                       {"angle_min": -1.0, "angle_max": 1.0, "cluster": 2}) as drv:
        assert drv.wait_connected(3.0), drv.last_error
        (s,) = collect(drv, 1, verify=lambda s: None)
        assert link.emulator.commands[-1] == "MD0222054602000"
        steps = np.arange(222, 547)
        pairs = np.round(truth((steps - 384) * 2 * np.pi / 1024) * 1000)
        want = np.minimum(pairs[0::2], np.append(pairs[1::2], np.inf)) / 1000
        assert np.allclose(s.ranges, want, atol=1e-6)
        assert s.angle_min >= -1.0 and s.angle_max <= 1.0 + 1e-9
        assert s.angle_increment == pytest.approx(2 * 2 * math.pi / 1024)


def test_streaming_on_a_pty(clean_registry) -> None:
    clock = WallClock()
    link = emu.Link(Urg04lxEmulator(clock, source))
    with PtyDevice(link) as dev, Urg04lxDriver(dev.port_name, clock) as drv:
        assert drv.wait_connected(3.0), drv.last_error
        assert len(collect(drv, 3)) == 3 and drv.rejected == 0


def test_scip11_unit_is_switched_to_scip2(clean_registry) -> None:
    clock = WallClock()
    emu.plug("urg-c", Urg04lxEmulator(clock, source, scip1_at_boot=True))
    with Urg04lxDriver("sim://urg04lx?id=urg-c", clock) as drv:
        assert drv.wait_connected(3.0), drv.last_error
        assert len(collect(drv, 2)) == 2


def test_unsolicited_stream_at_connect_is_stopped(clean_registry) -> None:
    clock = WallClock()
    e = Urg04lxEmulator(clock, source)
    e.receive(b"MD0044072501000\n")                   # left streaming by a previous program
    emu.plug("urg-d", e)
    wait_until(lambda: False, 0.25)                   # a few scans pile up on the wire
    with Urg04lxDriver("sim://urg04lx?id=urg-d", clock) as drv:
        assert drv.wait_connected(3.0), drv.last_error
        assert len(collect(drv, 2)) == 2


@pytest.mark.parametrize("faults", ["corrupt=0.0005", "drop=0.0005", "garbage=0.2",
                                    "corrupt=0.0003&drop=0.0003&garbage=0.1"])
def test_line_faults_never_deliver_a_wrong_scan(clean_registry, faults: str) -> None:
    clock = WallClock()
    emu.plug("urg-f", Urg04lxEmulator(clock, source), seed=7)
    with Urg04lxDriver(f"sim://urg04lx?id=urg-f&{faults}", clock) as drv:
        assert drv.wait_connected(5.0), drv.last_error
        assert len(collect(drv, 6, timeout=8.0)) == 6      # check() vets every one
        assert drv.rejected > 0                             # faults were seen and refused
        assert drv._thread is not None and drv._thread.is_alive()


def test_slow_replies_are_waited_for(clean_registry) -> None:
    clock = WallClock()
    emu.plug("urg-s", Urg04lxEmulator(clock, source))
    with Urg04lxDriver("sim://urg04lx?id=urg-s&delay=0.08", clock) as drv:
        assert drv.wait_connected(5.0), drv.last_error
        assert len(collect(drv, 2)) == 2


def test_stale_time_stamps_are_dropped_and_wrap_is_not_stale(clean_registry) -> None:
    clock = WallClock()
    e = Urg04lxEmulator(clock, source, stale_every=3)
    emu.plug("urg-t", e)
    with Urg04lxDriver("sim://urg04lx?id=urg-t", clock) as drv:
        assert drv.wait_connected(3.0), drv.last_error
        e.timer_offset_ms = (1 << 24) - 250 - e.timer_ms(clock.now()) + e.timer_offset_ms
        scans = collect(drv, 6)
        assert len(scans) == 6 and drv.stale >= 1
        assert drv._last_ts < 5000                          # the 24-bit timer did wrap


def test_unplug_and_replug_reconnects(clean_registry) -> None:
    clock = WallClock()
    link = emu.plug("urg-u", Urg04lxEmulator(clock, source))
    with Urg04lxDriver("sim://urg04lx?id=urg-u", clock) as drv:
        assert drv.wait_connected(3.0)
        collect(drv, 1)
        link.unplug()
        assert wait_until(lambda: not drv.connected, 2.0)
        wait_until(lambda: False, 0.3)                      # it keeps trying while unplugged
        assert "open failed" in drv.last_error or "disconnected" in drv.last_error
        link.replug()
        assert wait_until(lambda: drv.connects == 2, 3.0), drv.last_error
        before = drv.delivered
        assert wait_until(lambda: drv.delivered > before, 2.0)
        check(drv.scan())


def test_pty_device_that_falls_silent_is_reconnected(clean_registry) -> None:
    clock = WallClock()
    link = emu.Link(Urg04lxEmulator(clock, source))
    with PtyDevice(link) as dev, Urg04lxDriver(dev.port_name, clock) as drv:
        assert drv.wait_connected(3.0)
        collect(drv, 1)
        link.unplug()
        assert wait_until(lambda: not drv.connected, 3.0)   # silence_timeout noticed it
        link.replug()
        assert wait_until(lambda: drv.connects == 2, 4.0), drv.last_error
        before = drv.delivered
        assert wait_until(lambda: drv.delivered > before, 2.0)


def test_bad_url_is_reported_not_raised(clean_registry) -> None:
    clock = WallClock()
    with Urg04lxDriver("sim://nosuchdevice", clock) as drv:
        assert not drv.wait_connected(0.3)
        assert "unknown emulated device" in drv.last_error and drv.scan() is None


@pytest.mark.parametrize("left_at", [19200, 38400, 115200])
def test_rs232_unit_is_found_at_its_rate_and_switched(clean_registry, left_at: int) -> None:
    clock = WallClock()
    e = Urg04lxEmulator(clock, source, rs232=True)
    e.device_baud = left_at                           # where a previous session left it
    emu.plug("urg-r", e)
    with Urg04lxDriver("sim://urg04lx?id=urg-r", clock, {"serial_baud": 57600}) as drv:
        assert drv.wait_connected(5.0), drv.last_error
        assert e.device_baud == 57600 and e.baudrate == 57600
        assert len(collect(drv, 2)) == 2
