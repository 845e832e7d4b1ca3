"""SICK LMS 200 / 291 driver: implements ``hw.interfaces.Laser`` over LMS 2xx telegrams.

Start-up as sicktoolbox does it: find the sensor's bit rate (it powers up at 9600 but may have
been left at another), put it in polling mode, switch to the wanted rate (the host follows after
the reply), select the variant, read the units from the configuration, then request continuous
output. Closing stops the stream and returns the sensor to 9600 so the next start finds it.
"""

from __future__ import annotations

from typing import Any, Mapping

import serial

from hw.drivers import lms2xx_codec as lc
from hw.drivers.serial_link import HandshakeError, REPLY_WAIT, SerialDriver, wire_deadline
from navcore.clock import Clock
from navcore.params import Param, Parameters
from navcore.types import LaserScan, Pose2D

# sicktoolbox_wrapper (sicklms node) parameter names and defaults.
LMS_PARAMS = (
    Param("baud", 38400, int, "bit rate to switch to after power-up (9600 at power-on)",
          choices=(9600, 19200, 38400, 500000)),
    Param("angle", 0, int, "scanning angle in degrees (0: the model's default, 180)",
          choices=(0, 100, 180)),
    Param("resolution", 0.0, float, "angular resolution in degrees (0: the model's default: "
          "1.0 for lms200, 0.5 for lms291)", choices=(0.0, 0.25, 0.5, 1.0)),
    Param("inverted", False, bool, "sensor mounted upside down: reverse the beam order"),
    Param("frame_id", "laser", str, "frame of the published scans"),
)

REPLY_TIMEOUT = REPLY_WAIT


class Lms2xxDriver(SerialDriver):
    """An LMS 200 or 291 (``model``) on ``url``. ``scan()`` never blocks."""

    def __init__(self, url: str, clock: Clock, params: Mapping[str, Any] | None = None,
                 model: str = "lms200", mount: Pose2D = Pose2D()) -> None:
        if model not in ("lms200", "lms291"):
            raise ValueError(f"Lms2xxDriver: model must be lms200 or lms291, got {model!r}")
        self.params = Parameters(LMS_PARAMS, params or {}, model)
        super().__init__(url, clock, 9600, silence_timeout=1.0, name=model)
        self.model = model
        self.mount = mount
        p = self.params
        self.variant = lc.Variant(p.angle or 180,
                                  p.resolution or (1.0 if model == "lms200" else 0.5))
        self.variant.check()
        self.mm = False
        self.bits = 13               # range bits of a value, from the measuring mode
        self._dec = lc.TelegramDecoder()
        self._scan: LaserScan | None = None

    def scan(self) -> LaserScan | None:
        with self._lock:
            return self._scan

    # -- start-up ------------------------------------------------------------------------------
    def _transact(self, port: serial.SerialBase, cmd: int, data: bytes = b"",
                  tries: int = 3, timeout: float = REPLY_TIMEOUT) -> lc.Telegram:
        """Send a request until it is ACKed and its reply (cmd + 0x80) arrives."""
        for _ in range(tries):
            port.write(lc.request(cmd, data))
            dec = lc.TelegramDecoder()
            deadline = wire_deadline(timeout)
            while self._waiting(deadline):
                for item in dec.feed(port.read(max(1, port.in_waiting))):
                    if item == lc.NAK:
                        deadline = wire_deadline(0.0)     # resend at once
                    elif isinstance(item, lc.Telegram) and item.cmd == (cmd | 0x80):
                        return item
                    elif isinstance(item, lc.Telegram) and item.cmd == 0x92:
                        raise HandshakeError(f"sensor refused command {cmd:#04x}")
        raise HandshakeError(f"no reply to command {cmd:#04x} at {port.baudrate} baud")

    def _handshake(self, port: serial.SerialBase) -> None:
        want = self.params.baud
        found = None
        for baud in dict.fromkeys((9600, want, 38400, 19200, 500000)):
            port.baudrate = baud
            port.reset_input_buffer()
            try:
                self._transact(port, 0x20, b"\x25", tries=2, timeout=0.3)   # polling mode
            except HandshakeError:
                continue
            found = baud
            break
        if found is None:
            raise HandshakeError("sensor silent at every bit rate")
        if found != want:
            r = self._transact(port, 0x20, bytes([lc.BAUD_CODES[want]]))
            if r.data[:1] != b"\x00":
                raise HandshakeError(f"sensor refused {want} baud")
            port.baudrate = want
            self._transact(port, 0x20, b"\x25")                     # proves the new rate
        r = self._transact(port, 0x3B, self.variant.data())
        if r.data[:1] != b"\x01":
            raise HandshakeError(f"sensor refused variant {self.variant}")
        cfg = self._transact(port, 0x74).data
        if len(cfg) < 8:
            raise HandshakeError(f"configuration of {len(cfg)} bytes is too short")
        self.mm = cfg[7] == 1
        try:
            self.bits = lc.range_bits(cfg[6])
        except lc.LmsError as e:
            raise HandshakeError(str(e)) from None
        self._transact(port, 0x20, b"\x24")                         # continuous output
        self._dec.reset()

    def _on_close(self, port: serial.SerialBase) -> None:
        port.write(lc.request(0x20, b"\x25"))
        port.write(lc.request(0x20, bytes([lc.BAUD_CODES[9600]])))

    # -- streaming -----------------------------------------------------------------------------
    def _on_bytes(self, data: bytes) -> None:
        before = self._dec.errors
        for t in self._dec.feed(data):
            if not isinstance(t, lc.Telegram) or t.cmd != 0xB0:
                continue
            try:
                sv = lc.parse_scan(t, self.variant.count, self.bits)
            except lc.LmsError as e:
                self._reject(str(e))
                continue
            if (sv.unit_m == 0.001) != self.mm:
                self._reject("scan units differ from the configuration")
                continue
            msg = lc.to_laser_scan(sv, self.variant, self.clock.now(), self.params.frame_id)
            if self.params.inverted:
                msg.ranges = msg.ranges[::-1].copy()
            with self._lock:
                self._scan = msg
            self.delivered += 1
            self.mark_valid()
        self._reject_decoder_errors(before, self._dec.errors, self._dec.last_error)

