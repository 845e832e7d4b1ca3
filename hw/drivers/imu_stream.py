"""Shared reader for IMUs that stream one text line per sample (Razor, VectorNav)."""

from __future__ import annotations

import math
from typing import Callable

from hw.drivers.lines import LineDecoder
from hw.drivers.serial_link import SerialDriver
from navcore.clock import Clock
from navcore.types import Imu, Pose2D, angle_diff

# What a robot's IMU can report (a 2000 deg/s, 16 g part) and how fast its rate can change.
MAX_RATE = 35.0             # rad/s
MAX_ACCEL = 160.0           # m/s^2
MAX_ANGULAR_ACCEL = 200.0   # rad/s^2
SAMPLE_SLACK = 0.02         # s added to the time between samples (both stamped on arrival)


class LineImuDriver(SerialDriver):
    """Keeps the newest ``Imu`` parsed from the line stream; lines ``parse`` refuses are counted.
    Subclasses give the handshake and ``_parse(line, stamp) -> Imu | None`` (None: not a sample,
    e.g. a command reply, which is ignored)."""

    def __init__(self, url: str, clock: Clock, baudrate: int, name: str,
                 mount: Pose2D = Pose2D()) -> None:
        super().__init__(url, clock, baudrate, silence_timeout=0.5, name=name)
        self.mount = mount
        self._lines = LineDecoder(b"\n")
        self._imu: Imu | None = None
        self._parse: Callable[[str, float], Imu | None]
        self._prev: Imu | None = None     # the last sample accepted
        self._refused_in_row = 0

    def _implausibility(self, imu: Imu) -> str | None:
        """Why a decoded sample cannot be physics (None when it can). Razor lines carry no
        checksum and VectorNav's XOR misses paired flips, so a wrong digit must be caught here:
        values within the sensor's range, the yaw moving no further than the gyro allows since
        the last accepted sample, the rate changing no faster than a robot can spin up. Three
        refusals in a row mean the reference itself was bad: the new sample becomes it."""
        values = (imu.yaw, imu.angular_velocity_z, imu.linear_acceleration_x,
                  imu.linear_acceleration_y)
        if not all(math.isfinite(v) for v in values):
            return "a non-finite value"
        if abs(imu.angular_velocity_z) > MAX_RATE:
            return f"yaw rate {imu.angular_velocity_z:.2f} rad/s beyond {MAX_RATE}"
        if max(abs(imu.linear_acceleration_x), abs(imu.linear_acceleration_y)) > MAX_ACCEL:
            return f"acceleration beyond {MAX_ACCEL} m/s^2"
        prev = self._prev
        if prev is None or self._refused_in_row >= 3:
            return None
        dt = max(imu.stamp - prev.stamp, 0.0) + SAMPLE_SLACK
        rate = max(abs(prev.angular_velocity_z), abs(imu.angular_velocity_z))
        allowed = rate * dt + 0.01
        if abs(angle_diff(imu.yaw, prev.yaw)) > allowed:
            return (f"yaw jumped {angle_diff(imu.yaw, prev.yaw):.3f} rad, the gyro allows "
                    f"{allowed:.3f}")
        step = abs(imu.angular_velocity_z - prev.angular_velocity_z)
        if step > MAX_ANGULAR_ACCEL * dt + 0.05:
            return f"yaw rate changed {step:.2f} rad/s in {dt:.3f} s"
        return None

    def imu(self) -> Imu | None:
        with self._lock:
            return self._imu

    def _on_bytes(self, data: bytes) -> None:
        before = self._lines.errors
        now = self.clock.now()
        for line in self._lines.feed(data):
            try:
                msg = self._parse(line, now)
            except ValueError as e:
                self._reject(str(e))
                continue
            if msg is None:
                continue
            why = self._implausibility(msg)
            if why is not None:
                self._refused_in_row += 1
                self._implausible(why)
                continue
            self._prev, self._refused_in_row = msg, 0
            with self._lock:
                self._imu = msg
            self.delivered += 1
            self.mark_valid()
        self._reject_decoder_errors(before, self._lines.errors, "garbled line")
