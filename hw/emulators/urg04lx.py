"""Hokuyo URG-04LX emulator speaking SCIP 2.0 (reference hw_protocols.md section 1.8).

Ranges come from a data source ``ranges_source(t, angles) -> metres`` (angles in the laser frame,
counter-clockwise positive), so a simulator can ray-cast the world into the byte stream.
"""

from __future__ import annotations

from typing import Callable

import numpy as np

from hw.drivers import scip
from hw.emulators.link import Emulator
from navcore.clock import Clock

RangesSource = Callable[[float, np.ndarray], np.ndarray]

PP_LINES = ("MODL:URG-04LX(Hokuyo Automatic Co.,Ltd.)", "DMIN:20", "DMAX:5600", "ARES:1024",
            "AMIN:44", "AMAX:725", "AFRT:384", "SCAN:600")
VV_LINES = ("VEND:Hokuyo Automatic Co.,Ltd.", "PROD:SOKUIKI Sensor URG-04LX",
            "FIRM:3.1.00(18/Jan./2007)", "PROT:SCIP 2.0", "SERI:H0614967")
STEPS = 769          # steps 0..768 exist; AMIN..AMAX are measurable
GEOM = scip.UrgGeometry()


def default_ranges(t: float, angles: np.ndarray) -> np.ndarray:
    """A 2 m x 3 m room seen from its centre: something plausible with no simulator."""
    c, s = np.abs(np.cos(angles)), np.abs(np.sin(angles))
    with np.errstate(divide="ignore"):
        return np.minimum(np.where(c > 0, 1.5 / c, np.inf), np.where(s > 0, 1.0 / s, np.inf))


def kv_lines(items: tuple[str, ...]) -> list[bytes]:
    """Key:value lines with the URG-04LX sum rule (sum over the text before ';')."""
    return [it.encode("ascii") + b";" + bytes([scip.scip_sum(it.encode("ascii"))]) for it in items]


class Urg04lxEmulator(Emulator):
    """SCIP 2.0 state machine: laser on/off, one MD/MS job, TM mode, 24-bit ms timer.

    ``stale_every``: every n-th scan repeats the previous time stamp (fault injection);
    ``timer_offset_ms`` starts the sensor timer elsewhere (e.g. near the 24-bit wrap)."""

    device = "urg04lx"

    def __init__(self, clock: Clock, ranges_source: RangesSource = default_ranges,
                 scip1_at_boot: bool = False, timer_offset_ms: int = 0, rs232: bool = False,
                 stale_every: int = 0) -> None:
        super().__init__(clock)
        self.ranges_source = ranges_source
        self.scip1_at_boot = scip1_at_boot
        self.rs232 = rs232               # the RS-232 model: bit rates matter (USB ignores them)
        self._garble = np.random.default_rng(0)
        self.timer_offset_ms = timer_offset_ms
        self.stale_every = stale_every
        self._inbuf = bytearray()
        self.commands: list[str] = []      # every request line received (for tests)
        self.power_cycle()

    def power_cycle(self) -> None:
        super().power_cycle()
        self._inbuf = bytearray()
        self.scip2 = not self.scip1_at_boot
        self.device_baud = 19200
        self.laser_on = False
        self.tm_mode = False
        self.job: scip.ScanRequest | None = None
        self.job_echo = b""
        self._next_scan = 0.0
        self._remaining = 0
        self._t0 = self.clock.now()
        self._scans = 0
        self._last_ts = -1

    def timer_ms(self, now: float) -> int:
        return (int((now - self._t0) * 1000.0) + self.timer_offset_ms) % scip.TIME_WRAP

    def _garbled(self) -> bool:
        return self.rs232 and self.baudrate is not None and self.baudrate != self.device_baud

    def emit(self, data: bytes) -> None:
        if self._garbled():   # at the wrong bit rate the host sees framing errors, not text
            data = self._garble.integers(0x80, 0x100, len(data), dtype=np.uint8).tobytes()
        super().emit(data)

    def receive(self, data: bytes) -> None:
        if self._garbled():
            data = self._garble.integers(0x80, 0x100, len(data), dtype=np.uint8).tobytes()
        self._inbuf += data
        while True:
            idx = [i for i in (self._inbuf.find(b"\n"), self._inbuf.find(b"\r")) if i >= 0]
            if not idx:
                if len(self._inbuf) > 256:     # no terminator: the device discards junk
                    self._inbuf.clear()
                return
            k = min(idx)
            line = bytes(self._inbuf[:k])
            del self._inbuf[:k + 1]
            if line:
                self._command(line)

    def _reply(self, echo: bytes, status: str, lines: list[bytes] = ()) -> None:
        self.emit(scip.frame_reply(echo, status.encode(), list(lines)))

    def _command(self, line: bytes) -> None:
        text = line.decode("ascii", "replace")
        self.commands.append(text)
        if not self.scip2:
            if text == "SCIP2.0":
                self.scip2 = True
                self.emit(b"SCIP2.0\n0\n\n")
            else:
                self.emit(line + b"\nE\n\n")    # SCIP 1.1 answers anything else with an error
            return
        body, _, tag = text.partition(";")
        if tag and (len(tag) > 16 or not all(c.isalnum() or c in " ._+@" for c in tag)):
            return self._reply(line, "0G" if len(tag) > 16 else "0H")
        cmd, par = body[:2], body[2:]
        now = self.clock.now()
        if self.tm_mode and not (cmd == "TM" and par in ("1", "2")):
            return self._reply(line, "0E" if cmd != "TM" else "02")
        if body == "SCIP2.0":
            return self.emit(line + b"\n0\n\n")
        if cmd == "VV":
            return self._reply(line, "00", kv_lines(VV_LINES))
        if cmd == "PP":
            return self._reply(line, "00", kv_lines(PP_LINES))
        if cmd == "II":
            ii = ("MODL:URG-04LX(Hokuyo Automatic Co.,Ltd.)",
                  f"LASR:{'ON' if self.laser_on else 'OFF'}",
                  "SCSP:Initial(600[rpm])<-Default setting by user",
                  f"MESM:{'MEASURING' if self.job else 'IDLE'}",
                  "SBPS:19200[bps]<-Default setting by user",
                  f"TIME:{self.timer_ms(now):06X}", "STAT:Sensor works well.")
            return self._reply(line, "00", kv_lines(ii))
        if cmd == "BM":
            st = "02" if self.laser_on else "00"
            self.laser_on = True
            return self._reply(line, st)
        if cmd == "QT":
            self.laser_on = False
            self.job = None
            return self._reply(line, "00")
        if cmd == "RS":
            self.laser_on, self.job, self._t0 = False, None, now
            self.timer_offset_ms = 0
            self._reply(line, "00")
            self.device_baud = 19200                  # RS restores the default bit rate
            return
        if cmd == "TM":
            if par == "0":
                self.tm_mode, self.laser_on, self.job = True, False, None
                return self._reply(line, "00")
            if par == "1":
                if not self.tm_mode:
                    return self._reply(line, "04")
                return self._reply(line, "00", [scip.with_sum(scip.encode_value(
                    self.timer_ms(now), 4))])
            if par == "2":
                st = "00" if self.tm_mode else "03"
                self.tm_mode = False
                return self._reply(line, st)
            return self._reply(line, "01")
        if cmd == "SS":
            if not (par.isdigit() and len(par) == 6):
                return self._reply(line, "01")
            rate = int(par)
            if rate not in (19200, 38400, 57600, 115200, 250000, 500000, 750000):
                return self._reply(line, "02")
            if not self.rs232:
                return self._reply(line, "00")       # USB: accepted, nothing to change
            if rate == self.device_baud:
                return self._reply(line, "03")
            self._reply(line, "00")
            self.device_baud = rate                   # after the reply, as the sensor does
            return
        if cmd in ("CR", "HS"):
            return self._reply(line, "00" if par.isdigit() else "01")
        if cmd in ("MD", "MS", "GD", "GS"):
            return self._scan_command(line, cmd, par, now)
        self._reply(line, "0E" if len(cmd) == 2 and cmd.isalpha() else "0D")

    def _scan_command(self, line: bytes, cmd: str, par: str, now: float) -> None:
        cont = cmd in ("MD", "MS")
        need = 13 if cont else 10
        if len(par) != need:
            return self._reply(line, "0C" if len(par) < need else "0F")
        for k, (a, b) in enumerate([(0, 4), (4, 8), (8, 10)] + ([(10, 11), (11, 13)] if cont
                                                                 else [])):
            if not par[a:b].isdigit():
                return self._reply(line, f"{(1, 2, 3, 6, 7)[k]:02d}")
        req = scip.ScanRequest.parse(cmd + par) if int(par[4:8]) >= int(par[0:4]) else None
        if req is None:
            return self._reply(line, "05")
        if req.end >= STEPS:
            return self._reply(line, "04")
        if not cont:
            if not self.laser_on:
                return self._reply(line, "10")
            return self._reply(line, "00", self._scan_lines(req, now))
        self.laser_on = True
        self.job = req
        self.job_echo = line
        self._remaining = req.count
        self._next_scan = now                    # step 0 of the first sweep
        self._reply(line, "00")

    def _scan_lines(self, req: scip.ScanRequest, now: float,
                    step0: float | None = None) -> list[bytes]:
        """Lines of one scan measured around ``now`` whose step 0 was at ``step0`` (default: one
        rotation ago, the latest complete scan a GD/GS returns)."""
        steps = np.arange(STEPS)
        angles = (steps - GEOM.afrt) * (2.0 * np.pi / GEOM.ares)
        mm = np.asarray(self.ranges_source(now, angles), dtype=np.float64) * 1000.0
        vals = np.where(np.isfinite(mm), np.clip(np.round(mm), 0, 5600), 0).astype(np.int64)
        vals[mm < GEOM.dmin] = 7                 # too close: an error code, not a distance
        vals[(steps < GEOM.amin) | (steps > GEOM.amax)] = 19   # non-measurable step
        sel = vals[req.start:req.end + 1]
        c = max(req.cluster, 1)
        if c > 1:
            pad = (-len(sel)) % c
            grp = np.concatenate([sel, np.full(pad, 0)]).reshape(-1, c).astype(np.float64)
            grp[grp < GEOM.dmin] = np.inf         # cluster value = minimum valid value
            m = grp.min(axis=1)
            sel = np.where(np.isfinite(m), m, 0).astype(np.int64)
        ts = self.timer_ms(now - 0.1 if step0 is None else step0)   # stamp of step 0
        self._scans += 1
        if self.stale_every and self._scans % self.stale_every == 0 and self._last_ts >= 0:
            ts = self._last_ts
        self._last_ts = ts
        return scip.encode_scan_lines(ts, sel, req.width)

    def sweep_time(self, req: scip.ScanRequest) -> float:
        """From step 0 to the last requested step: the scan is sent when that step is done."""
        return (req.end + 1) * 60.0 / (GEOM.scan_rpm * GEOM.ares)

    def advance(self, now: float) -> None:
        while self.job is not None and now >= self._next_scan + self.sweep_time(self.job):
            t = self._next_scan                   # time of step 0 of this sweep
            req = self.job
            left = max(self._remaining - 1, 0) if req.count else 0
            echo = self.job_echo[:13] + f"{left:02d}".encode() + self.job_echo[15:]
            self.emit(scip.frame_reply(echo, b"99", self._scan_lines(req, t, t)))
            self._next_scan = t + 0.1 * (req.interval + 1)
            if req.count:
                self._remaining -= 1
                if self._remaining <= 0:
                    self.job, self.laser_on = None, False
            if now - self._next_scan > 1.0:      # clock jumped far: do not flood the wire
                self._next_scan = now
