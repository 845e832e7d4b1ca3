"""VectorNav emulator: ``$VNYMR`` async output, register 6 (async type) and 7 (rate) access.

Motion comes from ``imu_source(t) -> (yaw, yaw_rate, ax, ay)`` in REP 103 axes, converted to the
sensor's NED body frame.
"""

from __future__ import annotations

import math

from hw.drivers import vectornav_codec as vc
from hw.drivers.lines import LineDecoder
from hw.emulators.link import Emulator
from hw.emulators.razor import ImuSource, slow_turn
from navcore.clock import Clock

RATES = (1, 2, 4, 5, 10, 20, 25, 40, 50, 100, 200)
YMR = 14


class VectorNavEmulator(Emulator):
    """Async output type (register 6, 14 = YMR, 0 = off) at ``rate`` Hz (register 7)."""

    device = "vectornav"

    def __init__(self, clock: Clock, imu_source: ImuSource = slow_turn) -> None:
        super().__init__(clock)
        self.imu_source = imu_source
        self.power_cycle()

    def power_cycle(self) -> None:
        super().power_cycle()
        self._lines = LineDecoder(b"\n")
        self.async_type = YMR
        self.rate = 40
        self._next = self.clock.now()
        self.registers_written: list[tuple[int, str]] = []

    def sample(self, t: float) -> vc.Ymr:
        yaw, rate, ax, ay = self.imu_source(t)
        return vc.Ymr((-math.degrees(yaw), 0.0, 0.0), (0.2, 0.0, 0.45), (ax, -ay, -9.806),
                      (0.0, 0.0, -rate))

    def receive(self, data: bytes) -> None:
        for line in self._lines.feed(data):
            try:
                f = vc.split_sentence(line)
            except vc.VnError:
                self.emit(vc.sentence("VNERR,03"))          # invalid checksum / framing
                continue
            self._command(f)

    def _command(self, f: list[str]) -> None:
        if f[0] == "VNRRG" and len(f) == 2:
            reg = f[1]
            if reg == "06":
                return self.emit(vc.sentence(f"VNRRG,06,{self.async_type}"))
            if reg == "07":
                return self.emit(vc.sentence(f"VNRRG,07,{self.rate}"))
            if reg == "01":
                return self.emit(vc.sentence("VNRRG,01,VN-100T"))
            return self.emit(vc.sentence("VNERR,08"))
        if f[0] == "VNWRG" and len(f) == 3 and f[2].isdigit():
            reg, val = f[1], int(f[2])
            if reg == "06" and val in (0, YMR):
                self.async_type = val
            elif reg == "07" and val in RATES:
                self.rate = val
                self._next = self.clock.now()
            else:
                return self.emit(vc.sentence("VNERR,07"))
            self.registers_written.append((int(reg), f[2]))
            return self.emit(vc.sentence(",".join(f)))
        self.emit(vc.sentence("VNERR,04"))

    def advance(self, now: float) -> None:
        period = 1.0 / self.rate
        if now - self._next > 1.0:
            self._next = now
        while now >= self._next:
            if self.async_type == YMR:
                self.emit(self.sample(self._next).line())
            self._next += period
