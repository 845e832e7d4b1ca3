"""Razor 9DOF AHRS driver: implements ``hw.interfaces.ImuSensor`` over the text protocol.

Start-up as the razor_imu_9dof node does it: stop streaming (``#o0``), drain, choose the
``#YPRAG=`` format (``#ox``), synchronise on a ``#SYNCH`` token so that everything after it is
known to follow our settings, and start streaming (``#o1``).
"""

from __future__ import annotations

from typing import Any, Mapping

import serial

from hw.drivers import razor_codec as rc
from hw.drivers.imu_stream import LineImuDriver
from hw.drivers.lines import LineDecoder
from hw.drivers.serial_link import HandshakeError, REPLY_WAIT, wire_deadline
from navcore.clock import Clock
from navcore.params import Param, Parameters
from navcore.types import Imu, Pose2D

# razor_imu_9dof's parameter names and defaults.
RAZOR_PARAMS = (
    Param("imu_yaw_calibration", 0.0, float, "degrees added to the reported yaw", -180.0, 180.0),
    Param("frame_id", "base_imu_link", str, "frame of the published Imu"),
    Param("baud", 57600, int, "bit rate of the Razor's serial port", 9600, 921600),
)


class RazorDriver(LineImuDriver):
    """A Razor AHRS on ``url``. ``imu()`` never blocks."""

    def __init__(self, url: str, clock: Clock, params: Mapping[str, Any] | None = None,
                 mount: Pose2D = Pose2D()) -> None:
        self.params = Parameters(RAZOR_PARAMS, params or {}, "razor")
        super().__init__(url, clock, self.params.baud, "razor", mount)
        self._token = 0

    def _parse(self, line: str, stamp: float) -> Imu | None:
        if line.startswith("#SYNCH"):
            return None
        s = rc.parse_line(line)
        if s.accel is None:
            raise rc.RazorError("YPR-only line while YPRAG was requested")
        return rc.to_imu(s, stamp, self.params.imu_yaw_calibration, self.params.frame_id)

    def _handshake(self, port: serial.SerialBase) -> None:
        port.reset_input_buffer()
        self._prev = None
        for _ in range(3):
            self._token = (self._token + 1) % 100
            tok = f"#SYNCH{self._token:02d}"
            # stop streaming, YPRAG format, then a sync token: lines after it follow our settings
            port.write(f"#o0#ox#s{self._token:02d}".encode())
            dec = LineDecoder(b"\n")
            deadline = wire_deadline(REPLY_WAIT)
            while self._waiting(deadline):
                if tok in dec.feed(port.read(max(1, port.in_waiting))):
                    port.write(b"#o1")
                    self._lines.reset()
                    return
        raise HandshakeError("no #SYNCH reply from the Razor")

    def _on_close(self, port: serial.SerialBase) -> None:
        port.write(b"#o0")
