"""Hokuyo URG-04LX driver over SCIP 2.0: implements ``hw.interfaces.Laser``.

Start-up follows urg_c / hokuyo_node: find the bit rate with ``QT`` (which also stops any
stream) and drain, ``SCIP2.0`` (in case the unit booted in SCIP 1.1), ``TM2`` and ``RS`` (leave
time-adjust mode, reset), ``SS`` to ``serial_baud`` (RS-232 units; USB ones ignore it), ``PP``
(read the geometry), then one ``MD`` request for continuous 3-character scans. Each scan is fully checked by
the codec; a scan whose sensor time stamp does not advance is dropped as stale.
"""

from __future__ import annotations

import math
from typing import Any, Mapping

import serial

from hw.drivers import scip
from hw.drivers.serial_link import HandshakeError, REPLY_WAIT, SerialDriver, wire_deadline
from navcore.clock import Clock
from navcore.params import Param, Parameters
from navcore.types import LaserScan, Pose2D

# urg_node's parameter names and defaults (the maintained ROS driver for this sensor).
URG_PARAMS = (
    Param("angle_min", -math.pi, float, "first beam angle wanted (rad); clipped to the sensor",
          -math.pi, math.pi),
    Param("angle_max", math.pi, float, "last beam angle wanted (rad); clipped to the sensor",
          -math.pi, math.pi),
    Param("cluster", 1, int, "merge this many adjacent steps (minimum valid range)", 1, 99),
    Param("skip", 0, int, "skip this many scans between transmitted scans", 0, 9),
    Param("frame_id", "laser", str, "frame of the published scans"),
    Param("time_offset", 0.0, float, "seconds added to every scan stamp", -1.0, 1.0),
    Param("serial_baud", 115200, int, "bit rate of RS-232 units (USB units ignore it)",
          choices=(19200, 38400, 57600, 115200, 250000, 500000, 750000)),
)

REPLY_TIMEOUT = REPLY_WAIT  # urg_c waits about 140 ms; a slow or loaded device needs more


class Urg04lxDriver(SerialDriver):
    """A URG-04LX on ``url`` (``/dev/ttyACM0``, ``sim://urg04lx``, ...). ``scan()`` never blocks."""

    def __init__(self, url: str, clock: Clock, params: Mapping[str, Any] | None = None,
                 mount: Pose2D = Pose2D()) -> None:
        self.params = Parameters(URG_PARAMS, params or {}, "urg04lx")
        super().__init__(url, clock, self.params.serial_baud, silence_timeout=1.0,
                         name="urg04lx")
        self.mount = mount
        self.geometry = scip.UrgGeometry()
        self._decoder = scip.ScipDecoder()
        self._request: scip.ScanRequest | None = None
        self._scan: LaserScan | None = None
        self._last_ts = -1
        self._sensor_ms = 0          # the sensor's 24-bit timer, unwrapped
        self._offset: float | None = None
        self.stale = 0

    def scan(self) -> LaserScan | None:
        with self._lock:
            return self._scan

    # -- start-up ----------------------------------------------------------------------------
    def _transact(self, port: serial.SerialBase, line: bytes, ok: tuple[str, ...] = ("00",),
                  tries: int = 3) -> scip.ScipReply:
        """Send ``line`` and wait for the reply whose echo matches; retry on silence/garble."""
        echo = line.rstrip(b"\r\n").decode("ascii")
        for _ in range(tries):
            port.write(line)
            dec = scip.ScipDecoder()
            deadline = wire_deadline(REPLY_TIMEOUT)
            while self._waiting(deadline):
                for rep in dec.feed(port.read(max(1, port.in_waiting))):
                    if rep.echo == echo:
                        if rep.status in ok:
                            return rep
                        raise HandshakeError(f"{echo}: status {rep.status}")
        raise HandshakeError(f"{echo}: no valid reply in {tries} tries")

    def _drain(self, port: serial.SerialBase, quiet: float = 0.05) -> None:
        """Read until the line stays quiet for ``quiet`` seconds (or 1 s at most)."""
        total = wire_deadline(1.0)
        q = wire_deadline(quiet)
        while self._waiting(total) and not q.expired():
            if port.read(max(1, port.in_waiting)):
                q = wire_deadline(quiet)

    def _find_rate(self, port: serial.SerialBase) -> None:
        """Find the bit rate the sensor listens at (as urg_c does): send QT at each rate and
        look for its echo; a USB unit answers at any rate."""
        for baud in dict.fromkeys((self.params.serial_baud, 19200, 38400, 115200)):
            port.baudrate = baud
            port.write(b"QT\n")          # also stops a stream left running
            seen = b""
            deadline = wire_deadline(REPLY_TIMEOUT)
            while self._waiting(deadline):
                seen = (seen + port.read(max(1, port.in_waiting)))[-4096:]
                if b"QT\n" in seen:
                    return
        raise HandshakeError("no QT echo at 19200, 38400 or 115200 bit/s")

    def _handshake(self, port: serial.SerialBase) -> None:
        self._find_rate(port)
        self._drain(port)
        port.reset_input_buffer()
        port.write(b"SCIP2.0\n")       # harmless in SCIP 2.0, switches a SCIP 1.1 unit
        self._drain(port)
        self._transact(port, b"TM2\n", ok=("00", "03"))
        self._transact(port, b"RS\n")
        port.baudrate = 19200           # RS restored the default rate (RS-232 units)
        if self.params.serial_baud != 19200:
            self._transact(port, f"SS{self.params.serial_baud:06d}\n".encode(),
                           ok=("00", "03", "04"))
            port.baudrate = self.params.serial_baud
        info = self._transact(port, b"PP\n").info()
        try:
            self.geometry = scip.UrgGeometry.from_pp(info)
        except scip.ScipError as e:
            raise HandshakeError(str(e)) from None
        g, p = self.geometry, self.params
        start = max(g.amin, min(g.amax, math.ceil(p.angle_min * g.ares / (2 * math.pi) + g.afrt)))
        end = max(start, min(g.amax, math.floor(p.angle_max * g.ares / (2 * math.pi) + g.afrt)))
        line = scip.scan_request("MD", start, end, p.cluster, p.skip, 0)
        self._transact(port, line)
        self._request = scip.ScanRequest.parse(line.strip().decode())
        self._decoder.reset()
        self._last_ts = -1
        self._offset = None          # RS reset the sensor's timer

    def _on_close(self, port: serial.SerialBase) -> None:
        port.write(b"QT\n")            # stop streaming and switch the laser off

    # -- streaming ---------------------------------------------------------------------------
    def _stamp(self, req: scip.ScanRequest) -> float:
        """Clock time of step 0, from the sensor's timer plus an offset: the smallest seen
        (arrival - sensor time - sweep to the last requested step) is the least-delayed scan,
        so it is taken at once; larger ones pull the offset up only slowly (clock drift)."""
        g = self.geometry
        sweep = (req.end + 1) * 60.0 / (g.scan_rpm * g.ares)
        sensor = self._sensor_ms / 1000.0
        cand = self.clock.now() - sensor - sweep
        if self._offset is None or cand < self._offset:
            self._offset = cand
        else:
            self._offset += 0.001 * (cand - self._offset)
        return sensor + self._offset + self.params.time_offset

    def _on_bytes(self, data: bytes) -> None:
        before = self._decoder.errors
        for rep in self._decoder.feed(data):
            if rep.status != "99":
                continue                 # a late ack or QT echo: not a scan
            try:
                sd = scip.parse_scan(rep, self._request)
            except scip.ScipError as e:
                self._reject(str(e))
                continue
            if self._last_ts >= 0:
                d = (sd.timestamp_ms - self._last_ts) % scip.TIME_WRAP
                if d == 0 or d > scip.TIME_WRAP // 2:
                    self.stale += 1
                    self._reject(f"stale scan: time stamp {sd.timestamp_ms} after {self._last_ts}")
                    continue
                self._sensor_ms += d
            else:
                self._sensor_ms = sd.timestamp_ms
            self._last_ts = sd.timestamp_ms
            msg = scip.to_laser_scan(sd, self.geometry, self._stamp(sd.request),
                                     self.params.frame_id)
            with self._lock:
                self._scan = msg
            self.delivered += 1
            self.mark_valid()
        self._reject_decoder_errors(before, self._decoder.errors, self._decoder.last_error)
