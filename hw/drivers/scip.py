"""Hokuyo SCIP 2.0 codec (URG-04LX): request lines, reply framing, range data. No I/O.

A reply is a block of LF-terminated lines ended by an empty line: the echo of the request, a
status line ``<2 chars><sum>``, then data lines ``<payload><sum>``. The sum of a line is the low
6 bits of the byte sum of its payload plus 0x30. Every check the protocol allows is made here
(sums, charset, line lengths, value count, echo), so that a corrupted byte never yields a scan.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numba
import numpy as np

from navcore.types import LaserScan
from hw.errors import HwError

LF = 0x0A
MAX_LINE = 64          # data characters per line before its sum
TIME_WRAP = 1 << 24    # the sensor's millisecond timer is 24 bits wide


class ScipError(HwError, ValueError):
    """A SCIP byte sequence is malformed; the message says what and where."""


def scip_sum(payload: bytes) -> int:
    """The line checksum character (as an int) for ``payload``."""
    return (sum(payload) & 0x3F) + 0x30


def with_sum(payload: bytes) -> bytes:
    """``payload`` followed by its checksum character."""
    return payload + bytes([scip_sum(payload)])


def encode_value(v: int, width: int) -> bytes:
    """Encode a non-negative integer in ``width`` 6-bit characters (most significant first)."""
    if not 0 <= v < (1 << (6 * width)):
        raise ScipError(f"value {v} does not fit {width} SCIP characters")
    return bytes(((v >> (6 * (width - 1 - i))) & 0x3F) + 0x30 for i in range(width))


def decode_value(chars: bytes) -> int:
    """Decode a run of SCIP characters into an integer."""
    v = 0
    for c in chars:
        if not 0x30 <= c <= 0x6F:
            raise ScipError(f"character {c:#04x} is outside the SCIP range 0x30..0x6f")
        v = (v << 6) | (c - 0x30)
    return v


def request(command: str, params: str = "", tag: str = "") -> bytes:
    """A request line: ``<command><params>[;tag]`` + LF."""
    if len(command) != 2 and command != "SCIP2.0":
        raise ScipError(f"SCIP command must be two characters, got {command!r}")
    text = command + params + (";" + tag if tag else "")
    return text.encode("ascii") + b"\n"


def scan_request(command: str, start: int, end: int, cluster: int = 1, interval: int = 0,
                 count: int = 0) -> bytes:
    """``MD``/``MS`` (continuous, with interval and count) or ``GD``/``GS`` (one scan)."""
    p = f"{start:04d}{end:04d}{cluster:02d}"
    if command in ("MD", "MS"):
        p += f"{interval:01d}{count:02d}"
    elif command not in ("GD", "GS"):
        raise ScipError(f"not a scan command: {command!r}")
    return request(command, p)


@dataclass(frozen=True, slots=True)
class ScipReply:
    """One framed reply: echo text, 2-char status and the raw lines after the status line
    (each still carrying its sum; scan data is checked by ``parse_scan``)."""

    echo: str
    status: str
    lines: tuple[bytes, ...] = ()

    def text_lines(self) -> list[str]:
        """Payloads of key:value lines (VV/PP/II), with either semicolon sum rule accepted."""
        out = []
        for ln in self.lines:
            if len(ln) < 2:
                raise ScipError(f"{self.echo}: line {ln!r} too short")
            body, s = ln[:-1], ln[-1]
            if s != scip_sum(body) and not (body.endswith(b";") and s == scip_sum(body[:-1])):
                raise ScipError(f"{self.echo}: bad sum on line {ln!r}")
            out.append(body.rstrip(b";").decode("ascii", "replace"))
        return out

    def info(self) -> dict[str, str]:
        """A key:value reply (PP, VV, II) as a dict."""
        d = {}
        for t in self.text_lines():
            k, _, v = t.partition(":")
            d[k] = v
        return d


def frame_reply(echo: bytes, status: bytes, data_lines: list[bytes] = ()) -> bytes:
    """Build reply bytes (emulator side). ``data_lines`` already carry their sums."""
    return echo + b"\n" + with_sum(status) + b"\n" + b"".join(ln + b"\n" for ln in data_lines) \
        + b"\n"


def encode_scan_lines(timestamp_ms: int, values: np.ndarray, width: int) -> list[bytes]:
    """Time line and data lines (each with its sum) of a scan reply."""
    data = encode_values(values, width)
    lines = [with_sum(encode_value(timestamp_ms % TIME_WRAP, 4))]
    for i in range(0, len(data), MAX_LINE):
        lines.append(with_sum(data[i:i + MAX_LINE]))
    return lines


def encode_values(values: np.ndarray, width: int) -> bytes:
    """Concatenated fixed-width encoding of ``values`` (clipped to the width's range)."""
    v = np.clip(np.asarray(values, dtype=np.int64), 0, (1 << (6 * width)) - 1)
    out = np.empty((len(v), width), dtype=np.uint8)
    for i in range(width):
        out[:, i] = ((v >> (6 * (width - 1 - i))) & 0x3F) + 0x30
    return out.tobytes()


@numba.njit(cache=True)
def _decode_data_lines(buf: np.ndarray, width: int, n_values: int) -> tuple:
    """Walk LF-separated data lines (payload + sum) in ``buf``; check sums, charset and line
    lengths; decode ``n_values`` values of ``width`` chars that may straddle lines.
    Returns (values, error code, byte offset of the error). Error 0 = fine."""
    out = np.empty(n_values, dtype=np.int32)
    n = buf.shape[0]
    i = 0
    k = 0          # values done
    acc = 0        # partial value
    got = 0        # chars in acc
    while i < n:
        j = i
        while j < n and buf[j] != 10:
            j += 1
        if j == n:
            return out, 1, i            # line without LF
        ln = j - i
        if ln < 2 or ln > 65:
            return out, 2, i            # empty or overlong data line
        s = 0
        for p in range(i, j - 1):
            c = int(buf[p])  # plain ints: numpy's uint8 would wrap in plain Python
            if c < 0x30 or c > 0x6F:
                return out, 3, p        # not a SCIP data character
            s += c
        if (s & 0x3F) + 0x30 != buf[j - 1]:
            return out, 4, j - 1        # line sum mismatch
        if j + 1 < n and ln != 65:
            return out, 2, i            # only the last line may be short
        for p in range(i, j - 1):
            if k >= n_values:
                return out, 5, p        # more data than the request asked for
            acc = (acc << 6) | (int(buf[p]) - 0x30)
            got += 1
            if got == width:
                out[k] = acc
                k += 1
                acc = 0
                got = 0
        i = j + 1
    if k != n_values or got != 0:
        return out, 6, n                # less data than the request asked for
    return out, 0, 0


_DATA_ERRORS = {1: "line without LF", 2: "bad data line length", 3: "character outside 0x30..0x6f",
                4: "line sum mismatch", 5: "more values than requested",
                6: "fewer values than requested"}


@dataclass(frozen=True, slots=True)
class ScanRequest:
    """The fields of an MD/MS/GD/GS request, parsed from an echo."""

    command: str
    start: int
    end: int
    cluster: int
    interval: int = 0
    count: int = 0

    @property
    def width(self) -> int:
        return 3 if self.command in ("MD", "GD") else 2

    @property
    def n_values(self) -> int:
        c = max(self.cluster, 1)
        return (self.end - self.start) // c + 1

    @staticmethod
    def parse(echo: str) -> ScanRequest:
        cmd = echo[:2]
        body = echo[2:].split(";", 1)[0]
        cont = cmd in ("MD", "MS")
        if cmd not in ("MD", "MS", "GD", "GS") or len(body) != (13 if cont else 10) \
                or not body.isdigit():
            raise ScipError(f"not a scan request echo: {echo!r}")
        start, end, cl = int(body[0:4]), int(body[4:8]), int(body[8:10])
        if end < start:
            raise ScipError(f"{echo!r}: end step {end} before start step {start}")
        return ScanRequest(cmd, start, end, cl, int(body[10]) if cont else 0,
                           int(body[11:13]) if cont else 0)


@dataclass(frozen=True, slots=True)
class ScanData:
    """One decoded scan: sensor time stamp (ms, 24-bit) and raw values (mm or error codes)."""

    request: ScanRequest
    timestamp_ms: int
    values: np.ndarray = field(repr=False)


def parse_scan(reply: ScipReply, expected: ScanRequest | None = None) -> ScanData:
    """Check and decode a scan reply (status 99 for MD/MS, 00 for GD/GS).

    ``expected`` is the request this driver issued; the echo must match it in every field but the
    remaining-scan count (which must not exceed the requested count, or be 00 for unlimited)."""
    req = ScanRequest.parse(reply.echo)
    if expected is not None:
        same = (req.command, req.start, req.end, req.cluster, req.interval) == \
            (expected.command, expected.start, expected.end, expected.cluster, expected.interval)
        rr_ok = req.count == 0 if expected.count == 0 else req.count <= expected.count
        if not same or not rr_ok:
            raise ScipError(f"scan echo {reply.echo!r} does not match the request")
    want = "99" if req.command in ("MD", "MS") else "00"
    if reply.status != want:
        raise ScipError(f"{reply.echo}: scan status {reply.status!r}, expected {want!r}")
    if len(reply.lines) < 2:
        raise ScipError(f"{reply.echo}: scan reply without data lines")
    t = reply.lines[0]
    if len(t) != 5 or t[4] != scip_sum(t[:4]):
        raise ScipError(f"{reply.echo}: bad time stamp line {t!r}")
    ts = decode_value(t[:4])
    body = np.frombuffer(b"\n".join(reply.lines[1:]) + b"\n", dtype=np.uint8)
    values, err, where = _decode_data_lines(body, req.width, req.n_values)
    if err:
        raise ScipError(f"{reply.echo}: {_DATA_ERRORS[int(err)]} at data byte {int(where)}")
    return ScanData(req, ts, values)


class ScipDecoder:
    """Incremental reply framer: feed any chunks, get complete ``ScipReply`` objects.

    Replies end at an empty line. A block that is not a well-formed reply (garbage, a cut or a
    corrupted line) is dropped and counted in ``errors``, with the reason in ``last_error``."""

    def __init__(self, max_block: int = 8192) -> None:
        self._buf = bytearray()
        self._max = max_block
        self.errors = 0
        self.last_error = ""

    def reset(self) -> None:
        self._buf.clear()

    def feed(self, chunk: bytes) -> list[ScipReply]:
        self._buf += chunk
        out: list[ScipReply] = []
        while True:
            k = self._buf.find(b"\n\n")
            if k < 0:
                if len(self._buf) > self._max:   # no terminator in sight: garbage
                    self._reject(f"{len(self._buf)} bytes without a reply terminator")
                    del self._buf[:-1]
                break
            block = bytes(self._buf[:k + 1])
            del self._buf[:k + 2]
            if not block.strip(b"\n"):
                continue
            try:
                out.append(parse_reply_block(block))
            except ScipError as e:
                self._reject(str(e))
        return out

    def _reject(self, why: str) -> None:
        self.errors += 1
        self.last_error = why


def parse_reply_block(block: bytes) -> ScipReply:
    """Split one reply (without its terminating empty line) into echo, status and lines."""
    lines = block.split(b"\n")
    if lines and lines[-1] == b"":
        lines.pop()
    if len(lines) < 2:
        raise ScipError(f"reply {block[:20]!r}: fewer than two lines")
    echo_b, st = lines[0], lines[1]
    if any(c < 0x20 or c > 0x7E for c in echo_b) or len(echo_b) < 2:
        raise ScipError(f"reply echo {echo_b[:20]!r} is not a SCIP command line")
    echo = echo_b.decode("ascii")
    if echo == "SCIP2.0" and st == b"0":
        return ScipReply(echo, "00", tuple(lines[2:]))
    if len(st) != 3 or st[2] != scip_sum(st[:2]) or any(c < 0x30 or c > 0x5A for c in st[:2]):
        raise ScipError(f"{echo}: bad status line {st!r}")
    return ScipReply(echo, st[:2].decode("ascii"), tuple(lines[2:]))


@numba.njit(cache=True)
def _values_to_ranges(raw: np.ndarray, dmin: int) -> np.ndarray:
    """mm -> m; error codes (below dmin): 0 and 6 -> +inf, the rest NaN."""
    out = np.empty(raw.shape[0], dtype=np.float32)
    for i in range(raw.shape[0]):
        v = raw[i]
        if v >= dmin:
            out[i] = v / 1000.0
        elif v == 0 or v == 6:
            out[i] = np.inf
        else:
            out[i] = np.nan
    return out


@dataclass(frozen=True, slots=True)
class UrgGeometry:
    """Sensor parameters from ``PP`` (URG-04LX defaults): ranges in mm, steps, rpm."""

    dmin: int = 20
    dmax: int = 5600
    ares: int = 1024
    amin: int = 44
    amax: int = 725
    afrt: int = 384
    scan_rpm: int = 600

    @staticmethod
    def from_pp(info: dict[str, str]) -> UrgGeometry:
        try:
            return UrgGeometry(*(int(info[k]) for k in
                                 ("DMIN", "DMAX", "ARES", "AMIN", "AMAX", "AFRT", "SCAN")))
        except (KeyError, ValueError) as e:
            raise ScipError(f"PP reply lacks or garbles a field: {e}") from None

    def angle(self, step: float) -> float:
        """Beam angle (rad, counter-clockwise positive) of a step."""
        return (step - self.afrt) * 2.0 * math.pi / self.ares


def to_laser_scan(scan: ScanData, geom: UrgGeometry, stamp: float,
                  frame_id: str = "laser") -> LaserScan:
    """Raw values -> LaserScan with the header fields of this sensor (tuning guide 5.1).

    Values below DMIN are error codes. As REP 117 asks: 0 and 6 (no object within range) become
    +inf, the other codes (measurement errors) NaN."""
    req = scan.request
    c = max(req.cluster, 1)
    inc = 2.0 * math.pi / geom.ares
    r = _values_to_ranges(scan.values, geom.dmin)
    n = len(r)
    a0 = geom.angle(req.start)
    return LaserScan(stamp=stamp, angle_min=a0, angle_max=a0 + (n - 1) * c * inc,
                     angle_increment=c * inc, time_increment=60.0 / (geom.scan_rpm * geom.ares),
                     scan_time=60.0 / geom.scan_rpm * (req.interval + 1),
                     range_min=geom.dmin / 1000.0, range_max=geom.dmax / 1000.0, ranges=r,
                     frame_id=frame_id)
