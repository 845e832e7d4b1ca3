"""SCIP 2.0 codec: golden bytes from the reference (hw_protocols.md section 1) and properties."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from hw.drivers import scip
from hw.emulators.urg04lx import Urg04lxEmulator
from navcore.clock import SimClock
from tests.test_hw_support import decode_valid


@pytest.mark.parametrize("payload,char", [(b"00", "P"), (b"99", "b"), (b"02", "R"),
                                          (b"04", "T"), (b"0E", "e"), (b"10", "Q"),
                                          (b"DMIN:20", "4"), (b"DMAX:5600", "_"),
                                          (b"ARES:1024", "\\"), (b"AMIN:44", "7"),
                                          (b"AMAX:725", "o"), (b"AFRT:384", "6"),
                                          (b"SCAN:600", "e"), (b"PROT:SCIP 2.0", "N"),
                                          (b"SERI:H0614967", "V")])
def test_line_sums_match_reference(payload: bytes, char: str) -> None:
    assert chr(scip.scip_sum(payload)) == char


@pytest.mark.parametrize("value,width,chars", [(1234, 2, b"CB"), (5432, 3, b"1Dh"),
                                               (16_000_000, 4, b"m2@0"), (1000, 3, b"0?X"),
                                               (1000, 2, b"?X"), (4095, 2, b"oo"),
                                               (123456, 4, b"0N90"), (4660, 4, b"018d")])
def test_value_encoding_matches_reference(value: int, width: int, chars: bytes) -> None:
    assert scip.encode_value(value, width) == chars
    assert scip.decode_value(chars) == value


def test_value_errors_are_named() -> None:
    with pytest.raises(scip.ScipError, match="does not fit"):
        scip.encode_value(4096, 2)
    with pytest.raises(scip.ScipError, match="outside the SCIP range"):
        scip.decode_value(b"0p")


GD_REPLY = b"GD0384038601\n00P\n018dm\n0?X0CB1DhI\n\n"
GS_REPLY = b"GS0384038601\n00P\n018dm\n?XCBooj\n\n"
MD_ACK = b"MD0384038601000\n00P\n\n"
MD_SCAN = b"MD0384038601000\n99b\n018dm\n0?X0CB1DhI\n\n"


def test_reference_transcript_decodes() -> None:
    dec = scip.ScipDecoder()
    reps = dec.feed(GD_REPLY + GS_REPLY + MD_ACK + MD_SCAN + b"TM1\n00P\n018dm\n\n")
    assert [r.echo for r in reps] == ["GD0384038601", "GS0384038601", "MD0384038601000",
                                      "MD0384038601000", "TM1"]
    assert dec.errors == 0
    gd, gs, ack, md = (scip.parse_scan(reps[i]) if i != 2 else reps[i] for i in range(4))
    assert gd.timestamp_ms == 4660 and list(gd.values) == [1000, 1234, 5432]
    assert list(gs.values) == [1000, 1234, 4095]
    assert ack.status == "00" and ack.lines == ()
    assert md.timestamp_ms == 4660 and list(md.values) == [1000, 1234, 5432]
    assert scip.decode_value(reps[4].lines[0][:4]) == 4660


def test_request_bytes() -> None:
    assert scip.scan_request("GD", 384, 386, 1) == b"GD0384038601\n"
    assert scip.scan_request("MD", 44, 725, 1, 0, 0) == b"MD0044072501000\n"
    assert scip.request("BM") == b"BM\n"
    assert scip.request("VV", tag="a1") == b"VV;a1\n"


def test_full_range_first_line_matches_reference() -> None:
    lines = scip.encode_scan_lines(0, np.full(682, 1000), 3)
    assert lines[1] == b"0?X" * 21 + b"0" + b"3"
    assert len(lines) == 1 + 32 and len(lines[-1]) == 62 + 1     # 31 lines of 64 + one of 62


PP_REPLY = (b"PP\n00P\nMODL:URG-04LX(Hokuyo Automatic Co.,Ltd.);N\nDMIN:20;4\nDMAX:5600;_\n"
            b"ARES:1024;\\\nAMIN:44;7\nAMAX:725;o\nAFRT:384;6\nSCAN:600;e\n\n")


def test_pp_reply_gives_geometry_and_header_fields() -> None:
    (rep,) = scip.ScipDecoder().feed(PP_REPLY)
    g = scip.UrgGeometry.from_pp(rep.info())
    assert g == scip.UrgGeometry()
    assert math.degrees(g.angle(44)) == pytest.approx(-119.53, abs=0.01)
    assert math.degrees(g.angle(725)) == pytest.approx(119.88, abs=0.01)
    sd = scip.parse_scan(scip.ScipDecoder().feed(
        scip.frame_reply(b"MD0044072501000", b"99",
                         scip.encode_scan_lines(5, np.array([0, 6, 7, 19, 1000] * 136 + [20, 5600]),
                                                3)))[0])
    ls = scip.to_laser_scan(sd, g, 1.5)
    assert ls.stamp == 1.5 and len(ls.ranges) == 682
    assert ls.angle_increment == pytest.approx(2 * math.pi / 1024)
    assert ls.time_increment == pytest.approx(9.765625e-05)
    assert ls.scan_time == pytest.approx(0.1)
    assert (ls.range_min, ls.range_max) == (pytest.approx(0.02), pytest.approx(5.6))
    assert np.isinf(ls.ranges[0]) and np.isinf(ls.ranges[1])      # codes 0, 6: no return
    assert np.isnan(ls.ranges[2]) and np.isnan(ls.ranges[3])     # other codes: errors (REP 117)
    assert ls.ranges[4] == pytest.approx(1.0) and ls.ranges[-1] == pytest.approx(5.6)


def test_emulator_reproduces_reference_transcript() -> None:
    clock = SimClock(0.0)
    target = {384: 1.0, 385: 1.234, 386: 5.432}

    def source(t: float, angles: np.ndarray) -> np.ndarray:
        steps = np.round(angles * 1024 / (2 * np.pi)).astype(int) + 384
        return np.array([target.get(s, 2.0) for s in steps])

    emu = Urg04lxEmulator(clock, source, timer_offset_ms=4760)   # stamp of step 0 = 4660 ms
    emu.receive(b"GD0384038601\n")
    assert bytes(emu.outbox) == b"GD0384038601\n10Q\n\n"           # laser off: status 10
    emu.outbox.clear()
    emu.receive(b"BM\nGD0384038601\nGS0384038601\n")
    assert bytes(emu.outbox) == b"BM\n00P\n\n" + GD_REPLY + GS_REPLY   # 5432 mm clips to 4095
    reps = scip.ScipDecoder().feed(bytes(emu.outbox))
    assert [r.echo for r in reps] == ["BM", "GD0384038601", "GS0384038601"]
    emu.outbox.clear()
    emu.timer_offset_ms = 4660          # the MD scan below starts its sweep at t = 0
    emu.receive(b"QT\nMD0384038601000\n")
    clock.advance(0.1)
    emu.advance(clock.now())
    assert bytes(emu.outbox) == b"QT\n00P\n\n" + MD_ACK + MD_SCAN


def test_emulator_error_statuses() -> None:
    emu = Urg04lxEmulator(SimClock())
    for line in (b"XX", b"MD00440725", b"MD0725004401000", b"MD0044080001000", b"MDab44072501000",
                 b"TM1", b"VV;" + b"a" * 17):
        emu.receive(line + b"\n")
    reps = scip.ScipDecoder().feed(bytes(emu.outbox))
    assert [r.status for r in reps] == ["0E", "0C", "05", "04", "01", "04", "0G"]


# ---- properties -------------------------------------------------------------------------------

@given(st.integers(2, 4).flatmap(lambda w: st.tuples(st.just(w), st.integers(0, (1 << 6 * w) - 1))))
def test_value_round_trip(wv: tuple[int, int]) -> None:
    w, v = wv
    assert scip.decode_value(scip.encode_value(v, w)) == v


@st.composite
def scans(draw: st.DrawFn) -> tuple[scip.ScanRequest, bytes, np.ndarray, int]:
    cmd = draw(st.sampled_from(["MD", "MS"]))
    width = 3 if cmd == "MD" else 2
    start = draw(st.integers(0, 700))
    n = draw(st.integers(1, 68))
    values = np.array(draw(st.lists(st.integers(0, (1 << 6 * width) - 1), min_size=n,
                                    max_size=n)))
    ts = draw(st.integers(0, scip.TIME_WRAP - 1))
    line = scip.scan_request(cmd, start, start + n - 1, 1, 0, 0).strip()
    req = scip.ScanRequest.parse(line.decode())
    return req, scip.frame_reply(line, b"99", scip.encode_scan_lines(ts, values, width)), values, ts


def _valid_scans(stream: bytes, req: scip.ScanRequest, chunks: list[int] | None = None) -> list:
    return decode_valid(scip.ScipDecoder(), lambda rep: scip.parse_scan(rep, req), scip.ScipError,
                        stream, chunks or ())


@settings(max_examples=150, deadline=None)
@given(scans())
def test_scan_round_trip(s: tuple) -> None:
    req, data, values, ts = s
    (got,) = _valid_scans(data, req)
    assert got.timestamp_ms == ts and np.array_equal(got.values, values)


@settings(max_examples=300, deadline=None)
@given(scans(), st.data())
def test_every_single_byte_corruption_is_rejected(s: tuple, data: st.DataObject) -> None:
    req, raw, _, _ = s
    i = data.draw(st.integers(0, len(raw) - 1))
    b = data.draw(st.integers(0, 255).filter(lambda x: x != raw[i]))
    bad = raw[:i] + bytes([b]) + raw[i + 1:]
    assert _valid_scans(bad, req) == []


@settings(max_examples=150, deadline=None)
@given(st.lists(scans(), min_size=1, max_size=4), st.data())
def test_stream_cut_anywhere_decodes_the_same(ss: list, data: st.DataObject) -> None:
    req = ss[0][0]
    stream = b"".join(s[1] for s in ss if s[0] == req) + PP_REPLY + MD_ACK
    cuts = sorted(set(data.draw(st.lists(st.integers(1, len(stream) - 1), max_size=12))))
    whole = scip.ScipDecoder().feed(stream)
    dec = scip.ScipDecoder()
    parts = []
    for a, b in zip([0] + cuts, cuts + [len(stream)]):
        parts += dec.feed(stream[a:b])
    assert parts == whole and dec.errors == 0
