"""SICK LMS 200/291: golden telegrams from the reference, properties, driver against the emulator."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import hw.emulators as emu
from hw.drivers import lms2xx_codec as lc
from hw.drivers.lms2xx import Lms2xxDriver
from hw.emulators.harness import wait_until
from hw.emulators.lms2xx import Lms200Emulator, Lms291Emulator
from hw.emulators.pty_port import PtyDevice
from navcore.clock import SimClock, WallClock
from tests.test_hw_support import clean_registry  # noqa: F401 (pytest fixture)
from tests.test_hw_support import collect_fresh, decode_valid


@pytest.mark.parametrize("tel,crc", [
    ("02 00 01 00 31", "15 12"), ("02 00 02 00 20 24", "34 08"), ("02 00 02 00 20 25", "35 08"),
    ("02 00 02 00 30 01", "31 18"), ("02 00 02 00 20 42", "52 08"), ("02 00 02 00 20 41", "51 08"),
    ("02 00 02 00 20 40", "50 08"), ("02 00 02 00 20 48", "58 08"),
    ("02 00 05 00 3B 64 00 64 00", "1D 0F"), ("02 00 05 00 3B B4 00 32 00", "3B 1F"),
    ("02 00 01 00 74", "50 12"), ("02 00 0A 00 20 00 53 49 43 4B 5F 4C 4D 53", "BE C5"),
    ("02 80 03 00 A0 00 10", "16 0A")])
def test_crc_matches_reference(tel: str, crc: str) -> None:
    raw = bytes.fromhex(tel)
    assert lc.telegram(raw[1], raw[4:]) == raw + bytes.fromhex(crc)


def test_requests_and_replies_build_the_reference_bytes() -> None:
    assert lc.request(0x20, b"\x24") == bytes.fromhex("02 00 02 00 20 24 34 08")
    assert lc.request(0x3B, lc.Variant(180, 0.5).data()) == \
        bytes.fromhex("02 00 05 00 3B B4 00 32 00 3B 1F")
    assert lc.reply(0x20, b"\x00") == bytes.fromhex("02 80 03 00 A0 00 10 16 0A")


def test_scan_telegram_header_matches_the_real_example() -> None:
    tel = lc.encode_scan(np.full(361, 123), mm=False)
    assert tel[:7] == bytes.fromhex("02 80 D6 02 B0 69 01")     # LEN 726, 361 values, cm
    (t,) = lc.TelegramDecoder().feed(bytes([lc.ACK]) + tel)[1:]
    sv = lc.parse_scan(t, 361)
    assert sv.unit_m == 0.01 and sv.status == 0x10 and np.all(sv.values == 123)


@pytest.mark.parametrize("variant,inc,tinc", [(lc.Variant(180, 1.0), 0.0174532923847,
                                               3.70370362361e-05),
                                              (lc.Variant(180, 0.5), 0.00872664619235,
                                               7.40740724722e-05)])
def test_header_fields_are_the_tuning_guide_values(variant, inc, tinc) -> None:
    sv = lc.ScanValues(np.array([100] * (variant.count - 3) + [0x1FF7, 0x1FFA, 0x1FFF]), 0.01, 0,
                       0x10)
    s = lc.to_laser_scan(sv, variant, 2.0)
    assert (s.range_min, s.range_max) == (0.0, 81.0)
    assert s.angle_min == pytest.approx(-1.57079637051) and s.angle_max == pytest.approx(
        1.57079637051)
    assert s.angle_increment == pytest.approx(inc) and s.time_increment == pytest.approx(tinc)
    assert s.scan_time == pytest.approx(0.0133333336562)
    assert s.ranges[0] == pytest.approx(1.0) and np.isinf(s.ranges[-3])
    assert np.isnan(s.ranges[-2]) and np.isnan(s.ranges[-1])


def test_ack_nak_and_unknown_command_from_emulator() -> None:
    e = Lms200Emulator(SimClock())
    good = lc.request(0x3A)
    e.receive(good)
    e.receive(good[:-1] + bytes([good[-1] ^ 1]))        # bad CRC
    e.receive(lc.request(0x55))
    items = lc.TelegramDecoder().feed(bytes(e.outbox))
    assert items[0] == lc.ACK and items[1].cmd == 0xBA and items[1].data.startswith(b"LMS200")
    assert items[2] == lc.NAK and items[3] == lc.ACK and items[4].cmd == 0x92


def test_configuration_needs_the_password() -> None:
    e = Lms200Emulator(SimClock())
    cfg = bytearray(32)
    cfg[7] = 1
    e.receive(lc.request(0x77, bytes(cfg)))
    e.receive(lc.request(0x20, b"\x00" + b"WRONG_PW"))
    e.receive(lc.request(0x20, b"\x00" + lc.PASSWORD))
    e.receive(lc.request(0x77, bytes(cfg)))
    tel = [t for t in lc.TelegramDecoder().feed(bytes(e.outbox)) if isinstance(t, lc.Telegram)]
    assert [(t.cmd, t.data[:1]) for t in tel] == [(0xF7, b"\x00"), (0xA0, b"\x01"),
                                                  (0xA0, b"\x00"), (0xF7, b"\x01")]
    assert e.mm


# ---- properties -------------------------------------------------------------------------------

def _values(n: int, seed: int) -> np.ndarray:
    """Range values from a seed (hypothesis draws the seed; long lists draw slowly)."""
    v = np.random.default_rng(seed).integers(0, 0x2000, n)
    v[:: max(1, seed % 7 + 1)] = seed % 0x2000         # runs of equal values, 0 included
    return v


def scans_of(counts: list[int]):
    return st.tuples(st.sampled_from(counts), st.booleans(), st.integers(0, 2**32 - 1)).map(
        lambda a: (a[0], a[1], _values(a[0], a[2])))


scans = scans_of([101, 181, 201, 361, 401])


def valid(stream: bytes, n: int, cuts: list[int] = ()) -> list[lc.ScanValues]:
    def parse(t) -> lc.ScanValues:
        if not isinstance(t, lc.Telegram):  # a lone ACK/NAK byte
            raise lc.LmsError("not a telegram")
        return lc.parse_scan(t, n)
    return decode_valid(lc.TelegramDecoder(), parse, lc.LmsError, stream, cuts)


@settings(max_examples=100, deadline=None)
@given(scans)
def test_scan_round_trip(s) -> None:
    n, mm, v = s
    (got,) = valid(lc.encode_scan(v, mm), n)
    assert np.array_equal(got.values, v) and got.unit_m == (0.001 if mm else 0.01)


@settings(max_examples=300, deadline=None)
@given(scans, st.data())
def test_every_single_byte_corruption_is_rejected(s, data: st.DataObject) -> None:
    n, mm, v = s
    raw = lc.encode_scan(v, mm)
    i = data.draw(st.integers(0, len(raw) - 1))
    b = data.draw(st.integers(0, 255).filter(lambda x: x != raw[i]))
    assert valid(raw[:i] + bytes([b]) + raw[i + 1:], n) == []


@settings(max_examples=100, deadline=None)
@given(st.lists(scans_of([181]), min_size=1, max_size=3), st.data())
def test_stream_cut_anywhere_decodes_the_same(ss, data: st.DataObject) -> None:
    stream = b"".join(bytes([lc.ACK]) + lc.encode_scan(v, mm) for _, mm, v in ss)
    cuts = sorted(set(data.draw(st.lists(st.integers(1, len(stream) - 1), max_size=12))))
    got = valid(stream, 181, cuts)
    assert len(got) == len(ss) and all(np.array_equal(g.values, s[2]) for g, s in zip(got, ss))


# ---- driver -------------------------------------------------------------------------------------


def truth(angles: np.ndarray) -> np.ndarray:
    return 2.0 + np.sin(2 * angles) + 0.3 * angles


def source(t: float, angles: np.ndarray) -> np.ndarray:
    return truth(angles)


def collect(drv: Lms2xxDriver, n: int, unit: float = 0.01, timeout: float = 5.0) -> list:
    def check(s) -> None:
        want = np.round(truth(s.angles()) / unit) * unit
        assert np.allclose(s.ranges, want, atol=unit * 0.6), "a wrong scan was delivered"
    return collect_fresh(drv.scan, n, timeout, check)


@pytest.mark.parametrize("model,cls,inc", [("lms200", Lms200Emulator, 1.0),
                                           ("lms291", Lms291Emulator, 0.5)])
def test_startup_switches_baud_and_streams(clean_registry, model, cls, inc) -> None:
    clock = WallClock()
    e = cls(clock, source)
    emu.plug("lms-a", e)
    with Lms2xxDriver(f"sim://{model}?id=lms-a", clock, model=model) as drv:
        assert drv.wait_connected(5.0), drv.last_error
        assert e.device_baud == 38400 and e.mode == 0x24
        scans = collect(drv, 3)
        assert len(scans) == 3 and drv.rejected == 0
        s = scans[-1]
        assert s.angle_increment == pytest.approx(math.radians(inc))
        assert len(s.ranges) == int(180 / inc) + 1 and s.range_max == 81.0
    assert e.device_baud == 9600 and e.mode == 0x25        # left as found at power-on


def test_sensor_left_at_another_baud_is_found(clean_registry) -> None:
    clock = WallClock()
    e = Lms200Emulator(clock, source)
    e.device_baud = 38400
    emu.plug("lms-b", e)
    with Lms2xxDriver("sim://lms200?id=lms-b", clock, {"baud": 500000}) as drv:
        assert drv.wait_connected(5.0), drv.last_error
        assert e.device_baud == 500000
        assert len(collect(drv, 2)) == 2


def test_mm_units_and_variant_100_deg(clean_registry) -> None:
    clock = WallClock()
    e = Lms200Emulator(clock, lambda t, a: np.full(len(a), 1.2345), mm=True)
    emu.plug("lms-c", e)
    with Lms2xxDriver("sim://lms200?id=lms-c", clock, {"angle": 100, "resolution": 0.25}) as drv:
        assert drv.wait_connected(5.0), drv.last_error
        assert wait_until(lambda: drv.scan() is not None, 3.0)
        s = drv.scan()
        assert len(s.ranges) == 401 and s.range_max == 8.1
        assert s.angle_min == pytest.approx(math.radians(-50))
        assert np.allclose(s.ranges, 1.234, atol=1e-3) or np.allclose(s.ranges, 1.235, atol=1e-3)


def test_streaming_on_a_pty(clean_registry) -> None:
    clock = WallClock()
    with PtyDevice(emu.Link(Lms291Emulator(clock, source))) as dev, \
            Lms2xxDriver(dev.port_name, clock, model="lms291") as drv:
        assert drv.wait_connected(5.0), drv.last_error
        assert len(collect(drv, 3)) == 3


@pytest.mark.parametrize("faults", ["corrupt=0.0005", "drop=0.0005", "garbage=0.2", "delay=0.05",
                                    "host_corrupt=0.02"])
def test_faults_never_deliver_a_wrong_scan(clean_registry, faults: str) -> None:
    clock = WallClock()
    e = Lms200Emulator(clock, source)
    emu.plug("lms-f", e, seed=11)
    with Lms2xxDriver(f"sim://lms200?id=lms-f&{faults}", clock) as drv:
        assert drv.wait_connected(8.0), drv.last_error
        assert len(collect(drv, 8, timeout=8.0)) == 8
        if faults.startswith(("corrupt", "drop", "garbage")):
            assert drv.rejected > 0


def test_unplug_and_replug_reconnects_at_power_on_baud(clean_registry) -> None:
    clock = WallClock()
    e = Lms200Emulator(clock, source)
    link = emu.plug("lms-u", e)
    with Lms2xxDriver("sim://lms200?id=lms-u", clock) as drv:
        assert drv.wait_connected(5.0)
        collect(drv, 1)
        link.unplug()
        assert wait_until(lambda: not drv.connected, 2.0)
        link.replug()
        assert wait_until(lambda: drv.connects == 2, 5.0), drv.last_error
        assert e.device_baud == 38400
        before = drv.delivered
        assert wait_until(lambda: drv.delivered > before, 2.0)


def test_inverted_mount_reverses_beams(clean_registry) -> None:
    clock = WallClock()
    emu.plug("lms-i", Lms200Emulator(clock, source))
    with Lms2xxDriver("sim://lms200?id=lms-i", clock, {"inverted": True}) as drv:
        assert drv.wait_connected(5.0)
        assert wait_until(lambda: drv.scan() is not None, 3.0)
        s = drv.scan()
        assert np.allclose(s.ranges[::-1], np.round(truth(s.angles()) * 100) / 100, atol=0.006)


def test_32m_mode_uses_15_range_bits(clean_registry) -> None:
    clock = WallClock()
    e = Lms200Emulator(clock, lambda t, a: np.where(np.abs(a) < 0.5, 20.0, 40.0), mm=True)
    e.config[6] = 0x05                     # 32 m measuring mode (mm units: 15-bit ranges)
    emu.plug("lms-32", e)
    with Lms2xxDriver("sim://lms200?id=lms-32", clock) as drv:
        assert drv.wait_connected(5.0), drv.last_error
        assert drv.bits == 15
        assert wait_until(lambda: drv.scan() is not None, 3.0)
        s = drv.scan()
        assert s.range_max == pytest.approx(32.76)
        ahead = np.abs(s.angles()) < 0.45
        assert np.allclose(s.ranges[ahead], 20.0) and np.all(np.isinf(s.ranges[np.abs(s.angles())
                                                                               > 0.55]))


def test_range_bits_by_mode() -> None:
    assert [lc.range_bits(m) for m in (0x00, 0x03, 0x06, 0x0F, 0x3F)] == [13, 14, 15, 15, 16]
    with pytest.raises(lc.LmsError, match="measuring mode 0x07"):
        lc.range_bits(0x07)
