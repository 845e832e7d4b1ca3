"""ros_arduino_bridge: codec, properties and the base driver against the firmware emulator."""

from __future__ import annotations


import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import hw.emulators as emu
from hw.drivers import arduino_codec as ac
from hw.drivers.arduino import ArduinoBaseDriver
from hw.emulators.arduino import ArduinoBridgeEmulator
from hw.emulators.harness import wait_until
from hw.emulators.pty_port import PtyDevice
from hw.interfaces import Base
from navcore.clock import SimClock, WallClock
from navcore.types import Twist
from tests.test_hw_support import clean_registry  # noqa: F401 (pytest fixture)
from tests.test_hw_support import drive, pieces


def test_command_bytes_and_replies() -> None:
    assert ac.motor_command(10, -20) == b"m 10 -20\r"
    assert ac.pid_command(20, 12, 0, 50) == b"u 20:12:0:50\r"
    assert ac.command("e") == b"e\r"
    e = ArduinoBridgeEmulator(SimClock())
    e.receive(b"b\re\rm 5 6\ru 1:2:3:4\rz\rm x y\r")
    assert bytes(e.outbox) == b"57600\r\n0 0\r\nOK\r\nOK\r\nInvalid Command\r\nInvalid Command\r\n"
    assert e.targets == (5, 6) and e.pid == (1, 2, 3, 4)


def test_geometry_matches_the_host_node() -> None:
    g = ac.Geometry()
    assert g.ticks_per_meter == pytest.approx(8384 / (0.146 * 3.141592653589793))
    left, right = g.wheel_targets(0.2, 0.0)
    assert left == right == int(0.2 * g.ticks_per_meter / 30)
    left, right = g.wheel_targets(0.0, 1.0)
    assert left == -right and right == int(0.2969 / 2 * g.ticks_per_meter / 30)


def test_firmware_auto_stop_after_two_seconds() -> None:
    clock = SimClock()
    e = ArduinoBridgeEmulator(clock)
    e.receive(b"m 10 10\r")
    clock.advance(1.9)
    e.advance(clock.now())
    assert e.targets == (10, 10)
    clock.advance(0.2)
    e.advance(clock.now())
    assert e.targets == (0, 0)
    assert e.encoders[0] == pytest.approx(10 * 30 * 2.0, abs=11)


@settings(max_examples=200, deadline=None)
@given(st.integers(-2**31, 2**31 - 1), st.integers(-2**31, 2**31 - 1), st.data())
def test_encoder_reply_round_trip_and_cuts(left: int, right: int, data: st.DataObject) -> None:
    stream = f"{left} {right}\r\nOK\r\n".encode()
    cuts = sorted(set(data.draw(st.lists(st.integers(1, len(stream) - 1), max_size=6))))
    dec, lines = ac.LineDecoder(b"\r"), []
    for piece in pieces(stream, cuts):
        lines += dec.feed(piece)
    assert lines == [f"{left} {right}", "OK"]
    assert ac.parse_encoders(lines[0]) == (left, right)


@settings(max_examples=300, deadline=None)
@given(st.integers(-10**6, 10**6), st.integers(-10**6, 10**6), st.data())
def test_corruption_outside_digits_is_rejected(left: int, right: int, data: st.DataObject) -> None:
    """No checksum in this protocol: a flipped digit cannot be seen in one reply (the driver's
    plausibility gate catches large jumps); every other single-byte corruption is refused."""
    raw = f"{left} {right}\r\n".encode()
    i = data.draw(st.integers(0, len(raw) - 1))
    b = data.draw(st.integers(0, 255).filter(lambda x: x != raw[i]))
    if chr(raw[i]).isdigit() and chr(b).isdigit():
        return
    if raw[i] == ord("-") and chr(b).isdigit() or chr(raw[i]).isdigit() and b == ord("-"):
        return                                  # sign flip: a digit-like change
    if b in (0x0A, 0x0D) or raw[i] == 0x0A:
        return      # a terminator cuts the line: the tail may be a well-formed shorter reply
    dec = ac.LineDecoder(b"\r")
    parsed = []
    for line in dec.feed(raw[:i] + bytes([b]) + raw[i + 1:]):
        try:
            parsed.append(ac.parse_encoders(line))
        except ac.ArduinoError:
            pass
    assert parsed == []


def test_driving_and_odometry_over_sim_url(clean_registry) -> None:
    clock = WallClock()
    e = ArduinoBridgeEmulator(clock)
    emu.plug("ard-a", e)
    with ArduinoBaseDriver("sim://arduino?id=ard-a", clock, {"base_controller_rate": 20.0}) as d:
        assert isinstance(d, Base)
        assert d.wait_connected(3.0), d.last_error
        assert e.pid == (20, 12, 0, 50)
        drive(d, Twist(0.2, 0.0, 0.0), 0.6)
        assert e.targets == d.geometry.wheel_targets(0.2, 0.0)
        wait_until(lambda: False, 0.1)
        x_true = e.encoders[0] / d.geometry.ticks_per_meter
        assert d.odometry().pose.x == pytest.approx(x_true, abs=0.04)
        assert d.odometry().pose.x > 0.05 and d.rejected == 0
        assert d.battery() is None and not d.events().bumper


def test_watchdog_stops_motors_within_one_period(clean_registry) -> None:
    clock = SimClock()
    e = ArduinoBridgeEmulator(clock)
    emu.plug("ard-w", e)
    with ArduinoBaseDriver("sim://arduino?id=ard-w", clock) as d:
        assert wait_until(lambda: d.connected, 3.0, clock=clock, step=0.002), d.last_error
        t_last = clock.now()
        d.send(Twist(0.3, 0.0, 0.0))
        timeout = d.params.base_controller_timeout

        def step_to(pred) -> bool:
            for _ in range(400):
                if pred():
                    return True
                clock.advance(0.01)
                n = d.ticks
                wait_until(lambda: d.ticks >= n + 2, 1.0)
            return pred()
        assert step_to(lambda: e.targets != (0, 0))
        assert step_to(lambda: clock.now() > t_last + timeout - 0.02) and e.targets != (0, 0)
        assert step_to(lambda: e.targets == (0, 0))
        t_stop = [t for t, l, r in e.motions if (l, r) == (0, 0) and t > t_last][0]
        assert t_stop <= t_last + timeout + 0.011     # the stop does not wait for a poll


@pytest.mark.parametrize("faults", [dict(garbage=0.3, corrupt=0.01), dict(drop=0.02),
                                    dict(host_corrupt=0.01, host_drop=0.01)])
def test_pty_and_line_faults(clean_registry, faults: dict) -> None:
    clock = WallClock()
    e = ArduinoBridgeEmulator(clock)
    link = emu.Link(e, emu.Faults(), seed=2)
    with PtyDevice(link) as dev, ArduinoBaseDriver(dev.port_name, clock,
                                                   {"base_controller_rate": 20.0}) as d:
        assert d.wait_connected(3.0), d.last_error
        for k, v in faults.items():
            setattr(link.faults, k, v)
        drive(d, Twist(0.1, 0.0, 0.3), 1.0)
        link.faults = emu.Faults()
        drive(d, Twist(), 0.3)
        wait_until(lambda: False, 0.2)
        assert d.rejected > 0 and d._thread.is_alive()
        assert e.targets == (0, 0)                     # the stop got through once clean
        # a corrupted count that slipped through as a small error would leave a small offset;
        # a large one is refused by the plausibility gate
        true_th = (e.encoders[1] - e.encoders[0]) / d.geometry.ticks_per_meter / 0.2969
        assert d.odometry().pose.theta == pytest.approx(true_th, abs=0.05)


def test_unplug_and_replug(clean_registry) -> None:
    clock = WallClock()
    e = ArduinoBridgeEmulator(clock)
    link = emu.plug("ard-u", e)
    with ArduinoBaseDriver("sim://arduino?id=ard-u", clock) as d:
        assert d.wait_connected(3.0)
        link.unplug()
        assert wait_until(lambda: not d.connected, 2.0)
        link.replug()
        assert wait_until(lambda: d.connects == 2, 3.0), d.last_error
        assert e.targets == (0, 0) and e.pid == (20, 12, 0, 50)


def test_slow_replies_and_plausibility_gate(clean_registry) -> None:
    clock = WallClock()
    e = ArduinoBridgeEmulator(clock)
    link = emu.plug("ard-s", e)
    with ArduinoBaseDriver("sim://arduino?id=ard-s&delay=0.06", clock,
                           {"base_controller_rate": 10.0}) as d:
        assert d.wait_connected(3.0), d.last_error
        drive(d, Twist(0.1, 0.0, 0.0), 0.5)
        assert e.targets == d.geometry.wheel_targets(0.1, 0.0) and d.delivered > 2
        x = d.odometry().pose.x
        link.faults.delay = 0.0
        e._enc[0] += 10**6                     # a count no wheel can make in one poll
        assert wait_until(lambda: "exceeds" in d.last_error, 2.0)
        n = d.delivered
        assert wait_until(lambda: d.delivered > n + 2, 2.0)    # re-referenced after 3 refusals
        assert d.odometry().pose.x < x + 0.2   # the jump never reached the odometry
