"""Kobuki codec (golden bytes, properties) and driver against the emulator (faults, watchdog)."""

from __future__ import annotations

import math
import struct

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import hw.emulators as emu
from hw.drivers import kobuki_codec as kc
from hw.drivers.kobuki import KobukiDriver
from hw.emulators.harness import wait_until
from hw.emulators.kobuki import KobukiEmulator
from hw.emulators.pty_port import PtyDevice
from hw.interfaces import Base
from navcore.clock import SimClock, WallClock
from navcore.types import Twist
from tests.test_hw_support import clean_registry  # noqa: F401 (pytest fixture)
from tests.test_hw_support import decode_valid, drive

# ---- codec: golden bytes from hw_protocols.md 3.2 ---------------------------------------------


@pytest.mark.parametrize("v,w,speed,radius,hexbytes", [
    (0.1, 0.0, 100, 0, "AA 55 06 01 04 64 00 00 00 67"),
    (0.2, 0.0, 200, 0, "AA 55 06 01 04 C8 00 00 00 CB"),
    (0.0, 0.0, 0, 0, "AA 55 06 01 04 00 00 00 00 03"),
    (0.0, 0.5, 57, 1, "AA 55 06 01 04 39 00 01 00 3B"),
    (0.2, 0.5, 257, 400, "AA 55 06 01 04 01 01 90 01 92"),
])
def test_command_frames_match_reference(v, w, speed, radius, hexbytes) -> None:
    assert kc.twist_to_speed_radius(v, w) == (speed, radius)
    assert kc.base_control_frame(speed, radius) == bytes.fromhex(hexbytes)


def test_request_extra_frame_matches_reference() -> None:
    assert kc.request_extra_frame(0x01 | 0x02 | 0x08) == bytes.fromhex("AA 55 04 09 02 0B 00 04")


FEEDBACK = bytes.fromhex("AA 55 1A 01 0F D2 04 00 00 00 E8 03 F2 03 00 00 00 00 A0 00 "
                         "04 07 28 23 00 00 00 00 00 70")


def test_reference_feedback_frame_decodes() -> None:
    (payload,) = kc.FrameDecoder().feed(FEEDBACK)
    fb = kc.parse_feedback(payload)
    b = fb.basic
    assert (b.timestamp_ms, b.left_encoder, b.right_encoder, b.battery_dv) == (1234, 1000, 1010, 160)
    assert fb.heading_cdeg == 9000 and fb.heading_rate == 0
    assert fb.pack() == FEEDBACK


def test_emulator_stream_has_the_real_frame_length() -> None:
    clock = SimClock()
    e = KobukiEmulator(clock)
    clock.advance(0.02)
    e.advance(clock.now())
    assert bytes(e.outbox[:5]) == bytes.fromhex("AA 55 4D 01 0F")   # as real units start


def test_wheel_speeds_invert_the_command() -> None:
    for v, w in [(0.3, 0.0), (0.0, 1.0), (0.2, 0.5), (0.2, -0.5), (-0.2, 0.4), (0.0, -0.7)]:
        vl, vr = kc.speed_radius_to_wheels(*kc.twist_to_speed_radius(v, w))
        assert (vl + vr) / 2 == pytest.approx(v, abs=2e-3)
        assert (vr - vl) / kc.WHEEL_BASE == pytest.approx(w, abs=1e-2)


def test_odometry_handles_encoder_wrap_and_constants() -> None:
    odo = kc.KobukiOdometry(use_imu_heading=False)
    start = kc.BasicSensors(timestamp_ms=65500, left_encoder=65000, right_encoder=65000)
    odo.update(kc.Feedback(start))
    ticks = round(kc.TICKS_PER_M)                 # one metre: 11724 ticks, wrapping past 65535
    pose, twist = odo.update(kc.Feedback(kc.BasicSensors(
        timestamp_ms=(65500 + 1000) & 0xFFFF, left_encoder=(65000 + ticks) & 0xFFFF,
        right_encoder=(65000 + ticks) & 0xFFFF)))
    assert pose.x == pytest.approx(1.0, abs=1e-4) and pose.theta == 0.0
    assert twist.vx == pytest.approx(1.0, abs=1e-4)
    assert kc.TICK_TO_RAD * kc.WHEEL_RADIUS == pytest.approx(0.0000852921, rel=1e-6)


def test_malformed_sub_payloads_are_named() -> None:
    with pytest.raises(kc.KobukiError, match="length 3, expected 15"):
        kc.parse_feedback(bytes([1, 3, 0, 0, 0]))
    with pytest.raises(kc.KobukiError, match="overruns"):
        kc.parse_feedback(kc.sub_payload(1, bytes(15)) + bytes([4, 7, 0]))
    with pytest.raises(kc.KobukiError, match="does not start with basic"):
        kc.parse_feedback(kc.sub_payload(4, bytes(7)))


# ---- properties -------------------------------------------------------------------------------

basics = st.builds(kc.BasicSensors, st.integers(0, 0xFFFF), st.integers(0, 7), st.integers(0, 3),
                   st.integers(0, 7), st.integers(0, 0xFFFF), st.integers(0, 0xFFFF),
                   st.integers(-128, 127), st.integers(-128, 127), st.integers(0, 7),
                   st.sampled_from([0, 2, 6, 18, 22]), st.integers(0, 255), st.integers(0, 3))
feedbacks = st.builds(
    kc.Feedback, basics, st.integers(-18000, 18000), st.integers(-32768, 32767),
    st.dictionaries(st.sampled_from([kc.DOCK_IR, kc.CLIFF, kc.CURRENT, kc.GPIO]),
                    st.just(b""), max_size=3).map(
        lambda d: {k: bytes(kc.FEEDBACK_LENGTHS[k]) for k in d}))


def decode_all(stream: bytes, cuts: list[int] = ()) -> list[kc.Feedback]:
    return decode_valid(kc.FrameDecoder(), kc.parse_feedback, kc.KobukiError, stream, cuts)


@settings(max_examples=150, deadline=None)
@given(feedbacks)
def test_feedback_round_trip(fb: kc.Feedback) -> None:
    assert decode_all(fb.pack()) == [fb]


@settings(max_examples=150, deadline=None)
@given(st.integers(-32768, 32767), st.integers(-32768, 32767))
def test_command_round_trip(speed: int, radius: int) -> None:
    (p,) = kc.FrameDecoder().feed(kc.base_control_frame(speed, radius))
    assert kc.parse_commands(p) == [(kc.BASE_CONTROL, struct.pack("<hh", speed, radius))]


@settings(max_examples=300, deadline=None)
@given(feedbacks, st.data())
def test_every_single_byte_corruption_is_rejected(fb: kc.Feedback, data: st.DataObject) -> None:
    raw = fb.pack()
    i = data.draw(st.integers(0, len(raw) - 1))
    b = data.draw(st.integers(0, 255).filter(lambda x: x != raw[i]))
    assert decode_all(raw[:i] + bytes([b]) + raw[i + 1:]) == []


@settings(max_examples=150, deadline=None)
@given(st.lists(feedbacks, min_size=1, max_size=5), st.binary(max_size=20), st.data())
def test_stream_cut_anywhere_decodes_the_same(fbs: list, junk: bytes, data: st.DataObject) -> None:
    stream = junk.replace(b"\xaa", b"") + b"".join(f.pack() for f in fbs)
    cuts = sorted(set(data.draw(st.lists(st.integers(1, len(stream) - 1), max_size=15))))
    assert decode_all(stream, cuts) == decode_all(stream) == fbs


# ---- driver against the emulator --------------------------------------------------------------


def test_streaming_odometry_battery_events_over_sim_url(clean_registry) -> None:
    clock = WallClock()
    e = KobukiEmulator(clock, battery_v=15.0)
    emu.plug("kob-a", e)
    with KobukiDriver("sim://kobuki?id=kob-a", clock) as drv:
        assert isinstance(drv, Base)
        assert drv.wait_connected(3.0), drv.last_error
        assert drv.versions["firmware"] == (12, 1, 1, 0)
        drive(drv, Twist(0.2, 0.0, 0.5), 0.6)
        x, y, th = e.pose
        odo = drv.odometry()
        assert th > 0.15 and x > 0.05
        assert odo.pose.x == pytest.approx(x, abs=0.01) and odo.pose.y == pytest.approx(y, abs=0.01)
        assert odo.pose.theta == pytest.approx(th, abs=0.01)
        assert odo.twist.vx == pytest.approx(0.2, abs=0.02)
        assert odo.pose_covariance[0, 0] == 0.1 and odo.pose_covariance[2, 2] == 0.05
        bat = drv.battery()
        assert bat.voltage == pytest.approx(15.0) and bat.percentage == pytest.approx(1.8 / 3.3)
        assert drv.events() == drv.events().__class__()
        e.bumper, e.charger = 0x02, 22
        assert wait_until(lambda: drv.events().bumper and drv.battery().charging, 1.0)
        assert drv.rejected == 0


def test_streaming_on_a_pty(clean_registry) -> None:
    clock = WallClock()
    e = KobukiEmulator(clock)
    with PtyDevice(emu.Link(e)) as dev:
        with KobukiDriver(dev.port_name, clock) as drv:
            assert drv.wait_connected(3.0), drv.last_error
            drive(drv, Twist(0.1, 0.0, 0.0), 0.3)
            assert e.speed == 100 and drv.odometry().pose.x > 0.0
        # closing stops the base; the pty hands the last bytes over asynchronously, so wait for
        # the emulator to have read them before the device goes away (a loaded machine is slow)
        assert wait_until(lambda: e.commands[-1][1:] == (0, 0), 3.0), e.commands[-3:]


def step_until(drv: KobukiDriver, clock: SimClock, pred, dt: float = 0.01,
               limit: float = 3.0) -> bool:
    """Advance simulated time in dt steps, each seen by the driver's loop, until pred()."""
    t_end = clock.now() + limit
    while clock.now() < t_end:
        if pred():
            return True
        clock.advance(dt)
        n = drv.ticks
        wait_until(lambda: drv.ticks >= n + 2, 1.0)
    return pred()


@pytest.mark.parametrize("faults", ["", "host_corrupt=0.01&host_drop=0.005"])
def test_watchdog_stops_the_base_within_one_period(clean_registry, faults: str) -> None:
    clock = SimClock()
    e = KobukiEmulator(clock)
    emu.plug("kob-w", e, seed=3)
    drv = KobukiDriver(f"sim://kobuki?id=kob-w&{faults}".rstrip("&"), clock)
    with drv:
        assert wait_until(lambda: drv.connected, 3.0, clock=clock, step=0.005), drv.last_error
        drv.send(Twist(0.3, 0.0, 0.0))
        assert step_until(drv, clock, lambda: e.speed == 300)
        t_last = clock.now()
        drv.send(Twist(0.3, 0.0, 0.0))                     # the last command
        timeout = drv.params.cmd_vel_timeout
        assert step_until(drv, clock, lambda: clock.now() >= t_last + timeout - 0.02)
        assert e.speed == 300                               # not stopped early
        assert step_until(drv, clock, lambda: e.speed == 0)
        t_stop = next(t for t, s, _ in e.commands if t > t_last and s == 0)
        bound = timeout + (0.011 if not faults else drv.params.cmd_resend_period * 3)
        assert t_last + timeout - 0.011 <= t_stop <= t_last + bound
        if faults:
            assert e.bad_frames > 0                         # commands really were mangled


@pytest.mark.parametrize("faults", ["corrupt=0.002", "drop=0.002", "garbage=0.2",
                                    "delay=0.05"])
def test_feedback_faults_never_give_wrong_odometry(clean_registry, faults: str) -> None:
    clock = WallClock()
    e = KobukiEmulator(clock)
    emu.plug("kob-f", e, seed=5)
    with KobukiDriver(f"sim://kobuki?id=kob-f&{faults}", clock) as drv:
        assert drv.wait_connected(5.0), drv.last_error
        drive(drv, Twist(0.0, 0.0, 0.8), 0.6)
        drv.send(Twist())
        wait_until(lambda: e.speed == 0, 1.0)
        wait_until(lambda: False, 0.2)
        # yaw comes from the gyro heading, so it must equal the truth despite lost frames;
        # a corrupted frame let through would show up as a jump
        assert drv.odometry().pose.theta == pytest.approx(e.pose[2], abs=0.01)
        if not faults.startswith("delay"):
            assert drv.rejected > 0


def test_unplug_replug_reconnects_and_keeps_the_base_stopped(clean_registry) -> None:
    clock = WallClock()
    e = KobukiEmulator(clock)
    link = emu.plug("kob-u", e)
    with KobukiDriver("sim://kobuki?id=kob-u", clock) as drv:
        assert drv.wait_connected(3.0)
        drive(drv, Twist(0.2, 0.0, 0.0), 0.2)
        link.unplug()
        assert wait_until(lambda: not drv.connected, 2.0)
        drv.send(Twist(0.2, 0.0, 0.0))                   # sending while unplugged is harmless
        wait_until(lambda: False, 0.7)                   # ...and the command goes stale
        n = len(e.commands)
        link.replug()
        assert wait_until(lambda: drv.connects == 2, 3.0), drv.last_error
        wait_until(lambda: False, 0.2)
        assert e.commands[n:] and all(s == 0 for _, s, _ in e.commands[n:])
        drive(drv, Twist(0.1, 0.0, 0.0), 0.2)
        assert e.speed == 100


def test_silent_base_is_reconnected(clean_registry) -> None:
    clock = WallClock()
    e = KobukiEmulator(clock)
    link = emu.Link(e)
    with PtyDevice(link) as dev, KobukiDriver(dev.port_name, clock) as drv:
        assert drv.wait_connected(3.0)
        link.unplug()
        assert wait_until(lambda: not drv.connected, 2.0)
        link.replug()
        assert wait_until(lambda: drv.connects == 2, 3.0), drv.last_error


def test_spin_integrates_heading() -> None:
    clock = SimClock()
    e = KobukiEmulator(clock)
    e.receive(kc.base_control_frame(*kc.twist_to_speed_radius(0.0, 1.0)))
    clock.advance(1.0)
    e.advance(clock.now())
    frames = [kc.parse_feedback(p) for p in kc.FrameDecoder().feed(bytes(e.outbox))]
    assert len(frames) == 50
    # speed 115 mm/s on each wheel in opposite senses: 2 * 0.115 / 0.230 = 1 rad/s
    assert math.radians(frames[-1].heading_cdeg / 100) == pytest.approx(1.0, abs=2e-4)


def test_acceleration_limit_ramps_the_wheels() -> None:
    clock = SimClock()
    e = KobukiEmulator(clock, accel_limit=1.0)
    e.receive(kc.base_control_frame(300, 0))
    clock.advance(0.1)
    e.advance(clock.now())
    assert e._wheels == (pytest.approx(0.1), pytest.approx(0.1))     # 5 ticks of 0.02 m/s
    clock.advance(0.5)
    e.advance(clock.now())
    assert e._wheels == (pytest.approx(0.3), pytest.approx(0.3))
