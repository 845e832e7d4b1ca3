"""Kobuki base emulator: 50 Hz feedback, speed/radius commands, encoders with the published
constants, gyro heading, battery drain, contact sensors settable by a test or simulator.

Wheel motion comes from ``motion_source(dt, v_left, v_right) -> (left_m, right_m)``: by default
the wheels do exactly what is commanded; a simulator can block them (collision) or add slip.
"""

from __future__ import annotations

import math
import struct
from typing import Callable

from hw.drivers import kobuki_codec as kc
from hw.emulators.link import Emulator
from navcore.clock import Clock

MotionSource = Callable[[float, float, float], tuple[float, float]]
PERIOD = 0.02


def ideal_wheels(dt: float, v_left: float, v_right: float) -> tuple[float, float]:
    return v_left * dt, v_right * dt


class KobukiEmulator(Emulator):
    """The robot's side of the Kobuki protocol. ``commands`` logs (clock time, speed, radius)
    of every base-control command received; ``speed``/``radius`` is the one in force.

    Like the real firmware it has no command timeout: stopping is the host's job."""

    device = "kobuki"

    def __init__(self, clock: Clock, motion_source: MotionSource = ideal_wheels,
                 battery_v: float = 16.5, drain_v_per_s: float = 0.0,
                 accel_limit: float | None = None) -> None:
        super().__init__(clock)
        self.accel_limit = accel_limit         # m/s^2 per wheel; None: speeds change at once
        self.motion_source = motion_source
        self.battery_v = battery_v
        self.drain_v_per_s = drain_v_per_s
        self.bumper = 0
        self.cliff = 0
        self.wheel_drop = 0
        self.charger = 0
        self.buttons = 0
        self.commands: list[tuple[float, int, int]] = []
        self.power_cycle()

    def power_cycle(self) -> None:
        super().power_cycle()
        self._dec = kc.FrameDecoder()
        self.speed = 0
        self.radius = 0
        self._t_start = self.clock.now()
        self._k = 1                            # index of the next 50 Hz tick (no float drift)
        self._next = self._t_start + PERIOD
        self._t_ms = 0.0
        self._left = self._right = 0.0       # encoder ticks, fractional
        self.heading = 0.0                     # rad
        self._rate = 0.0
        self._wheels = (0.0, 0.0)              # wheel speeds in force (m/s)
        self.pose = (0.0, 0.0, 0.0)            # ground truth from the wheels, for tests
        self._extras = 0
        self.bad_frames = 0

    def receive(self, data: bytes) -> None:
        for payload in self._dec.feed(data):
            try:
                subs = kc.parse_commands(payload)
            except kc.KobukiError:
                self.bad_frames += 1
                continue
            for ident, d in subs:
                if ident == kc.BASE_CONTROL:
                    self.speed, self.radius = struct.unpack("<hh", d)
                    self.commands.append((self.clock.now(), self.speed, self.radius))
                elif ident == kc.REQUEST_EXTRA:
                    self._extras |= struct.unpack("<H", d)[0]
        self.bad_frames += self._dec.errors
        self._dec.errors = 0

    def advance(self, now: float) -> None:
        if now - self._next > 1.0:     # the clock jumped far: integrate but do not flood
            skip = int((now - self._next) / PERIOD)
            self._step(skip * PERIOD)
            self._k += skip
            self._next = self._t_start + self._k * PERIOD
        while now + 1e-9 >= self._next:
            self._step(PERIOD)
            self.emit(self._feedback())
            self._k += 1
            self._next = self._t_start + self._k * PERIOD

    def _step(self, dt: float) -> None:
        vl, vr = kc.speed_radius_to_wheels(self.speed, self.radius)
        if self.accel_limit is not None:
            step = self.accel_limit * dt
            ol, orr = self._wheels
            vl = ol + max(-step, min(step, vl - ol))
            vr = orr + max(-step, min(step, vr - orr))
        self._wheels = (vl, vr)
        dl, dr = self.motion_source(dt, vl, vr)
        self._left += dl * kc.TICKS_PER_M
        self._right += dr * kc.TICKS_PER_M
        dth = (dr - dl) / kc.WHEEL_BASE
        x, y, th = self.pose
        mid = th + dth / 2
        ds = (dl + dr) / 2
        self.pose = (x + ds * math.cos(mid), y + ds * math.sin(mid), th + dth)
        self.heading = math.remainder(self.heading + dth, 2 * math.pi)
        self._rate = dth / dt if dt > 0 else 0.0
        self._t_ms += dt * 1000.0
        self.battery_v = max(0.0, self.battery_v - self.drain_v_per_s * dt)

    def _feedback(self) -> bytes:
        basic = kc.BasicSensors(
            timestamp_ms=int(self._t_ms) & 0xFFFF, bumper=self.bumper, wheel_drop=self.wheel_drop,
            cliff=self.cliff, left_encoder=int(math.floor(self._left)) & 0xFFFF,
            right_encoder=int(math.floor(self._right)) & 0xFFFF, buttons=self.buttons,
            charger=self.charger, battery_dv=max(0, min(255, int(round(self.battery_v * 10)))))
        p = kc.sub_payload(kc.BASIC, basic.pack())
        p += kc.sub_payload(kc.DOCK_IR, bytes(3))
        p += kc.sub_payload(kc.INERTIAL, struct.pack(
            "<hh3x", int(round(math.degrees(self.heading) * 100)),
            max(-32768, min(32767, int(round(math.degrees(self._rate) * 100))))))
        p += kc.sub_payload(kc.CLIFF, struct.pack("<3H", 1800, 1800, 1800))
        p += kc.sub_payload(kc.CURRENT, bytes(2))
        p += kc.sub_payload(kc.RAW_GYRO, bytes([0, 6]) + bytes(12))      # N = 2 samples
        p += kc.sub_payload(kc.GPIO, bytes(16))
        if self._extras & 0x01:
            p += kc.sub_payload(kc.HW_VERSION, bytes([0, 0, 1, 0]))
        if self._extras & 0x02:
            p += kc.sub_payload(kc.FW_VERSION, bytes([12, 1, 1, 0]))
        if self._extras & 0x08:
            p += kc.sub_payload(kc.UDID, struct.pack("<3I", 0x1234, 0x5678, 0x9ABC))
        self._extras = 0
        return kc.frame(p)
