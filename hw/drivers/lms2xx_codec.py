"""SICK LMS 200 / 291 telegram codec: framing, CRC16, ACK/NAK, scan (0xB0) decoding. No I/O.

Telegram: ``02 <adr> <len lo> <len hi> <cmd> <data...> [status] <crc lo> <crc hi>``; ``adr`` is
0x00 towards the sensor and 0x80 from it; ``len`` counts cmd..status; a reply's cmd is the
request's + 0x80 and ends with a status byte (reference hw_protocols.md section 2).
"""

from __future__ import annotations

import math
import struct
from dataclasses import dataclass

import numba
import numpy as np

from navcore.types import LaserScan
from hw.errors import HwError

STX, ACK, NAK = 0x02, 0x06, 0x15
TO_SENSOR, FROM_SENSOR = 0x00, 0x80
MAX_PAYLOAD = 812
BAUD_CODES = {38400: 0x40, 19200: 0x41, 9600: 0x42, 500000: 0x48}
PASSWORD = b"SICK_LMS"
MIRROR_HZ = 75.0


class LmsError(HwError, ValueError):
    """A telegram or scan is malformed; the message says what."""


@numba.njit(cache=True)
def _crc16(buf: np.ndarray) -> int:
    crc = 0
    prev = 0
    for i in range(buf.shape[0]):
        b = int(buf[i])  # a plain int: numpy's uint8 would overflow in plain Python
        if crc & 0x8000:
            crc = ((crc & 0x7FFF) << 1) ^ 0x8005
        else:
            crc = (crc << 1) & 0xFFFF
        crc ^= b | (prev << 8)
        prev = b
    return crc


def crc16(data: bytes) -> int:
    """SICK's CRC16 variant over STX..last payload byte."""
    return int(_crc16(np.frombuffer(data, dtype=np.uint8)))


def telegram(address: int, payload: bytes) -> bytes:
    """Frame ``payload`` (cmd + data [+ status]) with STX, address, length and CRC."""
    if not 1 <= len(payload) <= MAX_PAYLOAD:
        raise LmsError(f"payload of {len(payload)} bytes outside 1..{MAX_PAYLOAD}")
    head = bytes([STX, address]) + struct.pack("<H", len(payload)) + payload
    return head + struct.pack("<H", crc16(head))


def request(cmd: int, data: bytes = b"") -> bytes:
    """A host-to-sensor telegram."""
    return telegram(TO_SENSOR, bytes([cmd]) + data)


def reply(cmd: int, data: bytes = b"", status: int = 0x10) -> bytes:
    """A sensor-to-host reply to request ``cmd`` (emulator side)."""
    return telegram(FROM_SENSOR, bytes([cmd | 0x80]) + data + bytes([status]))


@dataclass(frozen=True, slots=True)
class Telegram:
    """A checked telegram: ``cmd`` byte, ``data`` (without the status byte for replies)."""

    address: int
    cmd: int
    data: bytes
    status: int | None = None


class TelegramDecoder:
    """Incremental decoder for one direction (``address`` 0x80: replies, 0x00: requests).

    Yields ``Telegram`` objects and, for bytes seen between telegrams, the ints ACK / NAK.
    A bad CRC costs only the STX byte, so a false STX in garbage cannot hide a real telegram.
    ``crc_failures`` counts telegrams whose framing was plausible but whose CRC was wrong (the
    sensor answers those with NAK)."""

    def __init__(self, address: int = FROM_SENSOR) -> None:
        self.address = address
        self._buf = bytearray()
        self.errors = 0
        self.crc_failures = 0
        self.last_error = ""

    def reset(self) -> None:
        self._buf.clear()

    def feed(self, chunk: bytes) -> list[Telegram | int]:
        buf = self._buf
        buf += chunk
        out: list[Telegram | int] = []
        while buf:
            if buf[0] != STX:
                if buf[0] in (ACK, NAK):
                    out.append(buf[0])
                del buf[:1]
                continue
            if len(buf) < 4:
                break
            if buf[1] != self.address:
                self._reject(f"STX followed by address {buf[1]:#04x}")
                del buf[:1]
                continue
            n = buf[2] | (buf[3] << 8)
            if not 1 <= n <= MAX_PAYLOAD or (self.address == FROM_SENSOR and n < 2):
                self._reject(f"telegram length {n} out of range")
                del buf[:1]
                continue
            if len(buf) < n + 6:
                break
            body = bytes(buf[:n + 4])
            if crc16(body) != buf[n + 4] | (buf[n + 5] << 8):
                self.crc_failures += 1
                self._reject("CRC mismatch")
                del buf[:1]
                continue
            del buf[:n + 6]
            if self.address == FROM_SENSOR:
                out.append(Telegram(body[1], body[4], body[5:-1], body[-1]))
            else:
                out.append(Telegram(body[1], body[4], body[5:]))
        return out

    def _reject(self, why: str) -> None:
        self.errors += 1
        self.last_error = why


@dataclass(frozen=True, slots=True)
class Variant:
    """Scanning angle (100 or 180 degrees) and resolution (0.25, 0.5 or 1 degree)."""

    angle: int = 180
    resolution: float = 1.0

    @property
    def count(self) -> int:
        return int(round(self.angle / self.resolution)) + 1

    def check(self) -> None:
        ok = (self.angle == 180 and self.resolution in (0.5, 1.0)) or \
            (self.angle == 100 and self.resolution in (0.25, 0.5, 1.0))
        if not ok:
            raise LmsError(f"LMS variant {self.angle} deg / {self.resolution} deg does not exist")

    def data(self) -> bytes:
        """The data of the 0x3B telegram selecting this variant."""
        return struct.pack("<HH", self.angle, int(round(self.resolution * 100)))


@dataclass(frozen=True, slots=True)
class ScanValues:
    """A decoded 0xB0 scan: raw range values with flag bits removed, and the units (m per unit)."""

    values: np.ndarray
    unit_m: float
    partial: int
    status: int
    bits: int = 13


def encode_scan(values: np.ndarray, mm: bool, status: int = 0x10) -> bytes:
    """A 0xB0 reply telegram with ``values`` (the mode's range bits) in mm or cm (emulator side)."""
    v = np.asarray(values, dtype="<u2")
    count = len(v) | ((1 << 14) if mm else 0)
    return reply(0x30, struct.pack("<H", count) + v.tobytes(), status)


def range_bits(measuring_mode: int) -> int:
    """Bits of a value that carry the range, by measuring mode (configuration byte 6):
    8/80 m modes 13 (3 field bits above), 16 m modes 14, 32 m modes 15, reflectivity 16."""
    if measuring_mode in (0x00, 0x01, 0x02):
        return 13
    if measuring_mode in (0x03, 0x04):
        return 14
    if measuring_mode in (0x05, 0x06, 0x0F):
        return 15
    if measuring_mode == 0x3F:
        return 16
    raise LmsError(f"measuring mode {measuring_mode:#04x} unknown")


def parse_scan(t: Telegram, expected_count: int | None = None, bits: int = 13) -> ScanValues:
    """Check and decode a 0xB0 telegram; ``bits`` of each value are range (``range_bits``)."""
    if t.cmd != 0xB0:
        raise LmsError(f"not a scan telegram: cmd {t.cmd:#04x}")
    if len(t.data) < 2:
        raise LmsError("scan telegram without count word")
    word = t.data[0] | (t.data[1] << 8)
    n, units = word & 0x3FF, word >> 14
    if units > 1:
        raise LmsError(f"scan units code {units} unknown")
    if len(t.data) != 2 + 2 * n:
        raise LmsError(f"scan says {n} values but carries {(len(t.data) - 2) / 2:g}")
    if expected_count is not None and n != expected_count:
        raise LmsError(f"scan has {n} values, the variant gives {expected_count}")
    raw = np.frombuffer(t.data, dtype="<u2", offset=2)
    return ScanValues(raw & ((1 << bits) - 1), 0.001 if units == 1 else 0.01, (word >> 11) & 0x7,
                      t.status, bits)


def header(variant: Variant, mm: bool, bits: int = 13) -> dict[str, float]:
    """LaserScan header fields as sicktoolbox_wrapper publishes them (tuning guide 5.1):
    75 Hz, time_increment = scan_time / (360 * res), 0.0 to 81 m in the default 8/80 m mode
    with cm units (8.1 m with mm); the 16 m and 32 m modes reach 16.38 / 32.76 m (x10 in cm)."""
    scan_time = 1.0 / MIRROR_HZ
    top = {13: 8.1, 14: 16.38, 15: 32.76, 16: 65.53}[bits] * (1.0 if mm else 10.0)
    half = math.radians(variant.angle / 2.0)
    return dict(angle_min=-half, angle_max=half, angle_increment=math.radians(variant.resolution),
                time_increment=scan_time / (360.0 * variant.resolution), scan_time=scan_time,
                range_min=0.0, range_max=top)


def to_laser_scan(scan: ScanValues, variant: Variant, stamp: float,
                  frame_id: str = "laser") -> LaserScan:
    """Values -> LaserScan. The top eight codes of the range field (0x1FF7 and up with 13 bits):
    the first (beyond maximum) is +inf, the others (dazzle, overflow, low SNR, channel errors)
    NaN, as REP 117 asks. Reflectivity mode (16 bits) has no codes."""
    v = scan.values
    r = v.astype(np.float32) * np.float32(scan.unit_m)
    if scan.bits < 16:
        beyond = (1 << scan.bits) - 9
        r[v >= beyond] = np.nan
        r[v == beyond] = np.inf
    return LaserScan(stamp=stamp, ranges=r, frame_id=frame_id,
                     **header(variant, scan.unit_m == 0.001, scan.bits))
