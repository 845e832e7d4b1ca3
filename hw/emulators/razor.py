"""Razor 9DOF AHRS emulator: text output at 50 Hz, ``#o0/#o1/#ot/#ox/#f/#sXY`` control.

Motion comes from ``imu_source(t) -> (yaw, yaw_rate, ax, ay)`` in REP 103 axes (rad, rad/s,
m/s^2); the emulator converts to the firmware's axes (x forward, y right, z down) and units.
"""

from __future__ import annotations

import math
from typing import Callable

from hw.drivers import razor_codec as rc
from hw.emulators.link import Emulator
from navcore.clock import Clock

ImuSource = Callable[[float], tuple[float, float, float, float]]
PERIOD = 0.02


def slow_turn(t: float) -> tuple[float, float, float, float]:
    """Turning left at 0.2 rad/s, no linear acceleration."""
    return math.remainder(0.2 * t, 2 * math.pi), 0.2, 0.0, 0.0


class RazorEmulator(Emulator):
    """Firmware state: streaming on/off (on at boot) and output format (``t`` YPR, ``x`` YPRAG)."""

    device = "razor"

    def __init__(self, clock: Clock, imu_source: ImuSource = slow_turn) -> None:
        super().__init__(clock)
        self.imu_source = imu_source
        self.power_cycle()

    def power_cycle(self) -> None:
        super().power_cycle()
        self._in = ""
        self.streaming = True
        self.format = "t"
        self._k = 1
        self._t0 = self.clock.now()
        self.controls: list[str] = []

    def sample(self, t: float) -> rc.RazorSample:
        yaw, rate, ax, ay = self.imu_source(t)
        return rc.RazorSample(-math.degrees(yaw), 0.0, 0.0,
                              (ax / rc.ACCEL_FACTOR, -ay / rc.ACCEL_FACTOR, -256.0),
                              (0.0, 0.0, -rate))

    def _out(self, t: float) -> None:
        s = self.sample(t)
        if self.format == "t":
            s = rc.RazorSample(s.yaw, s.pitch, s.roll)
        self.emit(s.line())

    def receive(self, data: bytes) -> None:
        self._in += data.decode("latin-1")
        while True:
            k = self._in.find("#")
            if k < 0:
                self._in = ""
                return
            tok = self._in[k:]
            need = 2
            if tok[1:2] == "o":
                need = 4 if tok[2:3] == "e" else 5 if tok[2:3] == "s" else 3
            elif tok[1:2] == "s":
                need = 4
            if len(tok) < need:
                self._in = tok
                return
            self._in = tok[need:]
            self._control(tok[:need])

    def _control(self, c: str) -> None:
        self.controls.append(c)
        if c == "#o0":
            self.streaming = False
        elif c == "#o1":
            self.streaming = True
        elif c in ("#ot", "#ox"):
            self.format = c[2]
        elif c == "#f":
            self._out(self.clock.now())
        elif c.startswith("#s"):
            self.emit(f"#SYNCH{c[2:]}\r\n".encode("latin-1"))

    def advance(self, now: float) -> None:
        if now - (self._t0 + self._k * PERIOD) > 1.0:
            self._k = int((now - self._t0) / PERIOD)
        while now + 1e-9 >= self._t0 + self._k * PERIOD:
            if self.streaming:
                self._out(self._t0 + self._k * PERIOD)
            self._k += 1
