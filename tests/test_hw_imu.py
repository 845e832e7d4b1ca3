"""Razor AHRS and VectorNav: codecs (golden lines, properties) and drivers against emulators."""

from __future__ import annotations

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import hw.emulators as emu
from hw.drivers import razor_codec as rc
from hw.drivers import vectornav_codec as vc
from hw.drivers.lines import LineDecoder
from hw.drivers.razor import RazorDriver
from hw.drivers.vectornav import VectorNavDriver
from hw.emulators.harness import wait_until
from hw.emulators.pty_port import PtyDevice
from hw.emulators.razor import RazorEmulator
from hw.emulators.vectornav import VectorNavEmulator
from hw.interfaces import ImuSensor
from navcore.clock import SimClock, WallClock
from navcore.types import angle_diff
from tests.test_hw_support import clean_registry  # noqa: F401 (pytest fixture)
from tests.test_hw_support import collect_fresh, decode_valid, pieces

VN_REF = ("$VNYMR,+100.949,-007.330,+000.715,-00.0049,-00.2449,+00.5397,-01.258,-00.100,"
          "-09.701,-00.000018,+00.001122,-00.000551*69")


def test_vectornav_reference_sentence() -> None:
    y = vc.parse_ymr(VN_REF)
    assert y.ypr == (100.949, -7.33, 0.715) and y.gyro[2] == -0.000551
    assert y.line() == VN_REF.encode() + b"\r\n"
    assert vc.read_register(1) == b"$VNRRG,01*72\r\n"
    imu = vc.to_imu(y, 1.0)
    assert imu.yaw == pytest.approx(-math.radians(100.949))
    assert imu.angular_velocity_z == pytest.approx(0.000551)
    assert imu.linear_acceleration_y == pytest.approx(0.100)


def test_vectornav_errors_are_named() -> None:
    with pytest.raises(vc.VnError, match="checksum mismatch"):
        vc.parse_ymr(VN_REF[:-2] + "68")
    with pytest.raises(vc.VnError, match="upper-case"):
        vc.parse_ymr(VN_REF[:-2] + "6a")
    with pytest.raises(vc.VnError, match="not a VNYMR"):
        vc.parse_ymr(vc.sentence("VNRRG,06,14").decode().strip())


def test_razor_lines_and_axes() -> None:
    s = rc.parse_line("#YPR=-142.28,-5.38,33.52")
    assert (s.yaw, s.pitch, s.roll, s.accel) == (-142.28, -5.38, 33.52, None)
    s = rc.parse_line("#YPRAG=10.00,0.00,0.00,25.60,-51.20,-256.00,0.00,0.00,-0.50")
    imu = rc.to_imu(s, 2.0)
    assert imu.yaw == pytest.approx(math.radians(-10.0))              # yaw negated (REP 103)
    assert imu.angular_velocity_z == pytest.approx(0.5)
    assert imu.linear_acceleration_x == pytest.approx(0.9806)
    assert imu.linear_acceleration_y == pytest.approx(1.9612)
    for bad in ("#YPR=1.0,2.0", "#YPR=200.00,0.00,0.00", "YPR=1.00,2.00,3.00", "#YPR=1.0,2.0,x"):
        with pytest.raises(rc.RazorError):
            rc.parse_line(bad)


def test_razor_emulator_controls() -> None:
    clock = SimClock()
    e = RazorEmulator(clock)
    clock.advance(0.1)
    e.advance(clock.now())
    lines = LineDecoder().feed(bytes(e.outbox))
    assert len(lines) == 5 and all(ln.startswith("#YPR=") for ln in lines)
    e.outbox.clear()
    e.receive(b"#o0#ox#s42")
    clock.advance(0.1)
    e.advance(clock.now())
    assert bytes(e.outbox) == b"#SYNCH42\r\n"
    e.receive(b"#f")
    assert LineDecoder().feed(bytes(e.outbox))[-1].startswith("#YPRAG=")


# ---- properties -------------------------------------------------------------------------------

angles = st.floats(-179.999, 179.999)
small = st.floats(-9.9, 9.9)
ymrs = st.builds(lambda a, m, c, g: vc.parse_ymr(vc.Ymr(a, m, c, g).line().decode().strip()),
                 st.tuples(angles, angles, angles), st.tuples(small, small, small),
                 st.tuples(small, small, small), st.tuples(small, small, small))


def vn_decode(stream: bytes, cuts: list[int] = ()) -> list[vc.Ymr]:
    return decode_valid(LineDecoder(), vc.parse_ymr, vc.VnError, stream, cuts)


@settings(max_examples=150, deadline=None)
@given(ymrs)
def test_vectornav_round_trip(y: vc.Ymr) -> None:
    assert vn_decode(y.line()) == [y]


@settings(max_examples=300, deadline=None)
@given(ymrs, st.data())
def test_vectornav_every_single_byte_corruption_is_rejected(y: vc.Ymr, data) -> None:
    raw = y.line()
    i = data.draw(st.integers(0, len(raw) - 1))
    b = data.draw(st.integers(0, 255).filter(lambda x: x != raw[i]))
    if raw[i] == 0x0D and b == 0x0A:
        return        # CR -> LF ends the line one byte early with the same content
    assert vn_decode(raw[:i] + bytes([b]) + raw[i + 1:]) == []


@settings(max_examples=100, deadline=None)
@given(st.lists(ymrs, min_size=1, max_size=5), st.data())
def test_vectornav_stream_cut_anywhere(ys: list, data) -> None:
    stream = b"".join(y.line() for y in ys)
    cuts = sorted(set(data.draw(st.lists(st.integers(1, len(stream) - 1), max_size=10))))
    assert vn_decode(stream, cuts) == ys


@settings(max_examples=150, deadline=None)
@given(st.tuples(angles, angles, angles), st.tuples(small, small, small), st.data())
def test_razor_round_trip_and_cuts(ypr, gyro, data) -> None:
    s = rc.RazorSample(*(round(v, 2) for v in ypr), (1.0, 2.0, -256.0),
                       tuple(round(v, 2) for v in gyro))
    stream = s.line() * 3
    cuts = sorted(set(data.draw(st.lists(st.integers(1, len(stream) - 1), max_size=8))))
    dec, got = LineDecoder(), []
    for piece in pieces(stream, cuts):
        got += [rc.parse_line(ln) for ln in dec.feed(piece)]
    assert got == [s, s, s]


# ---- drivers ----------------------------------------------------------------------------------


def turning(t: float) -> tuple[float, float, float, float]:
    return math.remainder(0.5 * t, 2 * math.pi), 0.5, 0.3, -0.2


def check(imu, clock, tol: float) -> None:
    """The yaw must be the true one at about the time of delivery."""
    truth = turning(imu.stamp)[0]
    assert abs(angle_diff(imu.yaw, truth)) < tol, "a wrong IMU sample was delivered"
    assert imu.angular_velocity_z == pytest.approx(0.5, abs=1e-3)


@pytest.mark.parametrize("kind", ["razor", "vectornav"])
@pytest.mark.parametrize("faults", ["", "corrupt=0.002", "drop=0.002", "garbage=0.3",
                                    "delay=0.05"])
def test_driver_streams_true_samples_through_faults(clean_registry, kind, faults) -> None:
    clock = WallClock()
    emu_cls, drv_cls = {"razor": (RazorEmulator, RazorDriver),
                        "vectornav": (VectorNavEmulator, VectorNavDriver)}[kind]
    e = emu_cls(clock, turning)
    emu.plug("imu", e, seed=4)
    with drv_cls(f"sim://{kind}?id=imu&{faults}".rstrip("&"), clock) as d:
        assert isinstance(d, ImuSensor)
        assert d.wait_connected(5.0), d.last_error
        # stamped on arrival: late by at most the injected delay plus one read
        tol = 0.05 + (0.03 if "delay" in faults else 0.0)
        assert len(collect_fresh(d.imu, 20, 5.0, lambda m: check(m, clock, tol))) >= 20
        if kind == "vectornav" and faults and not faults.startswith(("drop", "delay")):
            assert d.rejected > 0


@pytest.mark.parametrize("kind", ["razor", "vectornav"])
def test_driver_on_a_pty_and_replug(clean_registry, kind) -> None:
    clock = WallClock()
    emu_cls, drv_cls = {"razor": (RazorEmulator, RazorDriver),
                        "vectornav": (VectorNavEmulator, VectorNavDriver)}[kind]
    e = emu_cls(clock, turning)
    link = emu.Link(e)
    with PtyDevice(link) as dev, drv_cls(dev.port_name, clock) as d:
        assert d.wait_connected(3.0), d.last_error
        assert wait_until(lambda: d.delivered > 5, 2.0)
        link.unplug()
        assert wait_until(lambda: not d.connected, 2.0)
        link.replug()
        assert wait_until(lambda: d.connects == 2, 3.0), d.last_error
        n = d.delivered
        assert wait_until(lambda: d.delivered > n + 5, 2.0)
        check(d.imu(), clock, 0.05)


@settings(max_examples=300, deadline=None)
@given(st.tuples(angles, angles, angles), st.tuples(small, small, small), st.data())
def test_razor_corruption_outside_digits_is_rejected(ypr, gyro, data) -> None:
    """No checksum on a Razor line: a flipped digit is left to the driver's gyro gate; every
    corruption of the line's structure (prefix, separators, decimal points) is refused."""
    raw = rc.RazorSample(*ypr, (1.0, 2.0, -256.0), gyro).line()
    i = data.draw(st.integers(0, len(raw) - 1))
    b = data.draw(st.integers(0, 255).filter(lambda x: x != raw[i]))
    digit_like = b"0123456789-"
    if (raw[i] in digit_like and b in digit_like) or b in b"\r\n" or raw[i] in b"\r\n":
        return
    lines = LineDecoder().feed(raw[:i] + bytes([b]) + raw[i + 1:])
    for line in lines:
        with pytest.raises(rc.RazorError):
            rc.parse_line(line)


def test_razor_driver_gate_refuses_a_yaw_jump() -> None:
    from navcore.clock import SimClock
    clock = SimClock(1.0)
    d = RazorDriver("sim://razor", clock)       # not started: bytes are fed by hand
    ok = "#YPRAG=10.00,0.00,0.00,0.00,0.00,-256.00,0.00,0.00,-0.50\r\n"
    d._on_bytes(ok.encode())
    assert d.delivered == 1 and d.imu().yaw == pytest.approx(math.radians(-10.0))
    clock.advance(0.02)
    d._on_bytes(ok.replace("10.00", "40.00", 1).encode())   # 30 deg in 20 ms at 0.5 rad/s
    assert d.delivered == 1 and d.implausible == 1 and "yaw jumped" in d.last_error
    clock.advance(0.02)
    d._on_bytes(ok.replace("10.00", "10.50", 1).encode())
    assert d.delivered == 2 and d.diagnostics()["implausible"] == 1
