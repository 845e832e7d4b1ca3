"""VectorNav driver: implements ``hw.interfaces.ImuSensor`` with ``$VNYMR`` async output.

Start-up: switch async output off (register 6 = 0), drain, set the rate (register 7) and then
the output type (register 6 = 14, YMR), each confirmed by the sensor's echo of the write.
Every sentence's XOR checksum is checked; error replies and other sentences are ignored.
"""

from __future__ import annotations

from typing import Any, Mapping

import serial

from hw.drivers import vectornav_codec as vc
from hw.drivers.imu_stream import LineImuDriver
from hw.drivers.lines import LineDecoder
from hw.drivers.serial_link import HandshakeError, REPLY_WAIT, wire_deadline
from navcore.clock import Clock
from navcore.params import Param, Parameters
from navcore.types import Imu, Pose2D

# The vectornav ROS driver's parameter names and defaults.
VN_PARAMS = (
    Param("serial_baud", 115200, int, "bit rate", 9600, 921600),
    Param("async_output_rate", 40, int, "samples per second (Hz)",
          choices=(1, 2, 4, 5, 10, 20, 25, 40, 50, 100, 200)),
    Param("frame_id", "imu", str, "frame of the published Imu"),
)


class VectorNavDriver(LineImuDriver):
    """A VectorNav IMU on ``url``. ``imu()`` never blocks."""

    def __init__(self, url: str, clock: Clock, params: Mapping[str, Any] | None = None,
                 mount: Pose2D = Pose2D()) -> None:
        self.params = Parameters(VN_PARAMS, params or {}, "vectornav")
        super().__init__(url, clock, self.params.serial_baud, "vectornav", mount)

    def _parse(self, line: str, stamp: float) -> Imu | None:
        if not line.startswith("$VNYMR"):
            vc.split_sentence(line)            # still checked: a garbled line is counted
            return None
        return vc.to_imu(vc.parse_ymr(line), stamp, self.params.frame_id)

    def _write_reg(self, port: serial.SerialBase, reg: int, value: int) -> None:
        want = f"VNWRG,{reg:02d},{value}"
        for _ in range(3):
            port.write(vc.write_register(reg, value))
            dec = LineDecoder(b"\n")
            deadline = wire_deadline(REPLY_WAIT)
            while self._waiting(deadline):
                for line in dec.feed(port.read(max(1, port.in_waiting))):
                    try:
                        if ",".join(vc.split_sentence(line)) == want:
                            return
                    except vc.VnError:
                        pass
        raise HandshakeError(f"register {reg} write not confirmed")

    def _handshake(self, port: serial.SerialBase) -> None:
        self._prev = None
        self._write_reg(port, 6, 0)
        self._write_reg(port, 7, self.params.async_output_rate)
        self._write_reg(port, 6, 14)
        self._lines.reset()

    def _on_close(self, port: serial.SerialBase) -> None:
        port.write(vc.write_register(6, 0))
