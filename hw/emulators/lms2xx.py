"""SICK LMS 200 / 291 emulator (reference hw_protocols.md section 2.7).

Powers up at 9600 baud in polling mode. Every telegram is answered with ACK (or NAK on a CRC
failure) and a reply; baud switches take effect after the reply; continuous mode streams 0xB0
telegrams as fast as the bit rate allows, at most 75 Hz. When the host's bit rate (reported by
the ``sim://`` transport) differs from the sensor's, both directions arrive as garbage, as on a
real wire. Ranges come from ``ranges_source(t, angles)`` in metres, angles counter-clockwise from
straight ahead.
"""

from __future__ import annotations

import struct
from typing import Callable

import numpy as np

from hw.drivers import lms2xx_codec as lc
from hw.emulators.link import Emulator
from navcore.clock import Clock

RangesSource = Callable[[float, np.ndarray], np.ndarray]
CODE_BAUD = {v: k for k, v in lc.BAUD_CODES.items()}


def default_ranges(t: float, angles: np.ndarray) -> np.ndarray:
    """A wall 4 m ahead, seen from its middle."""
    c = np.cos(angles)
    with np.errstate(divide="ignore"):
        return np.where(c > 0.05, 4.0 / np.maximum(c, 1e-9), 50.0)


class Lms2xxEmulator(Emulator):
    """The sensor's side of the LMS 2xx protocol. ``model`` is "lms200" or "lms291"."""

    device = "lms2xx"
    type_string = b"LMS200;30106        "

    def __init__(self, clock: Clock, ranges_source: RangesSource = default_ranges,
                 variant: lc.Variant = lc.Variant(180, 1.0), mm: bool = False) -> None:
        super().__init__(clock)
        self.ranges_source = ranges_source
        self.boot_variant = variant
        self.requests: list[int] = []       # command bytes of every accepted telegram
        self.naks = 0
        self.config = bytearray(32)           # kept in EEPROM: survives power cycles
        self.config[7] = 1 if mm else 0
        self.power_cycle()

    def power_cycle(self) -> None:
        super().power_cycle()
        self._dec = lc.TelegramDecoder(lc.TO_SENSOR)
        self.device_baud = 9600
        self.mode = 0x25
        self.install = False
        self.variant = self.boot_variant
        self.mm = bool(self.config[7])
        self._next = self.clock.now()
        self._rng = np.random.default_rng(0)

    def _garbled(self) -> bool:
        return self.baudrate is not None and self.baudrate != self.device_baud

    def receive(self, data: bytes) -> None:
        if self._garbled():   # wrong bit rate: the UART sees framing errors, not bytes
            data = self._rng.integers(0x80, 0x100, len(data), dtype=np.uint8).tobytes()
        before = self._dec.crc_failures
        items = self._dec.feed(data)
        for _ in range(self._dec.crc_failures - before):
            self.naks += 1
            self._send(bytes([lc.NAK]))
        for t in items:
            if isinstance(t, lc.Telegram):
                self.requests.append(t.cmd)
                self._send(bytes([lc.ACK]))
                self._handle(t)

    def _send(self, data: bytes) -> None:
        if self._garbled():
            data = self._rng.integers(0x80, 0x100, len(data), dtype=np.uint8).tobytes()
        self.emit(data)

    def _handle(self, t: lc.Telegram) -> None:
        cmd, d = t.cmd, t.data
        if cmd == 0x20 and d:
            m = d[0]
            if m == 0x00:
                ok = d[1:] == lc.PASSWORD
                self.install = self.install or ok
                return self._send(lc.reply(0x20, bytes([0x00 if ok else 0x01])))
            if m in CODE_BAUD:
                self._send(lc.reply(0x20, b"\x00"))
                self.device_baud = CODE_BAUD[m]          # after the reply, as the sensor does
                return
            if m in (0x24, 0x25):
                self.mode = m
                self._next = self.clock.now()
                return self._send(lc.reply(0x20, b"\x00"))
            return self._send(lc.reply(0x20, b"\x02"))
        if cmd == 0x30 and d == b"\x01":
            return self._send(self._scan(self.clock.now()))
        if cmd == 0x3A:
            return self._send(lc.reply(0x3A, self.type_string))
        if cmd == 0x31:
            blk = bytearray(152)
            blk[0:7] = b"V02.10 "
            return self._send(lc.reply(0x31, bytes(blk)))
        if cmd == 0x3B and len(d) == 4:
            angle, res = struct.unpack("<HH", d)
            v = lc.Variant(angle, res / 100.0)
            try:
                v.check()
                self.variant, ok = v, 1
            except lc.LmsError:
                ok = 0
            cur = self.variant
            return self._send(lc.reply(0x3B, bytes([ok]) + struct.pack(
                "<HH", cur.angle, int(round(cur.resolution * 100)))))
        if cmd == 0x74:
            return self._send(lc.reply(0x74, bytes(self.config)))
        if cmd == 0x77:
            if not self.install or len(d) != len(self.config):
                return self._send(lc.reply(0x77, b"\x00" + bytes(self.config)))
            self.config[:] = d
            self.mm = bool(d[7])
            return self._send(lc.reply(0x77, b"\x01" + bytes(self.config)))
        if cmd == 0x10:
            self._send(lc.reply(0x11))                 # 0x91: reset acknowledged
            self.power_cycle()
            return self._send(lc.reply(0x10, self.type_string))   # 0x90: power-on message
        self._send(lc.reply(0x12))            # 0x92: not acknowledged

    def _scan(self, t: float) -> bytes:
        v = self.variant
        angles = np.radians(-v.angle / 2.0 + v.resolution * np.arange(v.count))
        r = np.asarray(self.ranges_source(t, angles), dtype=np.float64)
        unit = 0.001 if self.mm else 0.01
        beyond = (1 << lc.range_bits(self.config[6])) - 9
        vals = np.where(np.isfinite(r), np.round(r / unit), np.inf)
        vals = np.where(vals >= beyond, beyond, vals).astype(np.int64)   # beyond maximum
        return lc.encode_scan(vals, self.mm)

    def advance(self, now: float) -> None:
        if self.mode != 0x24:
            return
        nbytes = 6 + 4 + 2 * self.variant.count
        period = max(1.0 / lc.MIRROR_HZ, nbytes * 10.0 / self.device_baud)
        if now - self._next > 1.0:
            self._next = now
        while now >= self._next:
            self._send(self._scan(self._next))
            self._next += period


class Lms200Emulator(Lms2xxEmulator):
    """LMS 200 defaults: 180 deg at 1 deg, cm units."""

    device = "lms200"


class Lms291Emulator(Lms2xxEmulator):
    """LMS 291 (long-range outdoor) defaults: 180 deg at 0.5 deg, cm units."""

    device = "lms291"
    type_string = b"LMS291;S05          "

    def __init__(self, clock: Clock, ranges_source: RangesSource = default_ranges,
                 variant: lc.Variant = lc.Variant(180, 0.5), mm: bool = False) -> None:
        super().__init__(clock, ranges_source, variant, mm)
