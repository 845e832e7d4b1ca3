"""Razor 9DOF AHRS text protocol codec (reference hw_protocols.md 4.1). No I/O.

Lines ``#YPR=<yaw>,<pitch>,<roll>`` or ``#YPRAG=<yaw>,<pitch>,<roll>,<ax>,<ay>,<az>,<gx>,<gy>,
<gz>`` ended by CR LF; angles in degrees, acceleration in raw units (256 = 1 g), gyro in rad/s,
body frame x forward, y right, z down. There is no checksum: a line must have the right prefix,
field count, number syntax and physically possible values, or it is refused.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

from navcore.types import Imu, normalize_angle
from hw.errors import HwError

ACCEL_FACTOR = 9.806 / 256.0          # raw accelerometer units -> m/s^2
_NUM = r"-?\d{1,4}\.\d{1,4}"
_YPR = re.compile(rf"^#YPR=({_NUM}),({_NUM}),({_NUM})$")
_YPRAG = re.compile(rf"^#YPRAG=({_NUM})" + rf",({_NUM})" * 8 + "$")


class RazorError(HwError, ValueError):
    """A Razor line is malformed or physically impossible; the message says which."""


@dataclass(frozen=True, slots=True)
class RazorSample:
    """One output line in the firmware's units and axes."""

    yaw: float
    pitch: float
    roll: float
    accel: tuple[float, float, float] | None = None    # raw, 256 = 1 g
    gyro: tuple[float, float, float] | None = None     # rad/s

    def line(self) -> bytes:
        """The firmware's text for this sample (two decimals, as ``Serial.print`` gives)."""
        vals = [self.yaw, self.pitch, self.roll]
        if self.accel is None:
            return ("#YPR=" + ",".join(f"{v:.2f}" for v in vals) + "\r\n").encode()
        vals += [*self.accel, *self.gyro]
        return ("#YPRAG=" + ",".join(f"{v:.2f}" for v in vals) + "\r\n").encode()


def parse_line(line: str) -> RazorSample:
    """A ``#YPR=`` or ``#YPRAG=`` line (without CR LF)."""
    m = _YPRAG.match(line) or _YPR.match(line)
    if not m:
        raise RazorError(f"not a Razor output line: {line[:40]!r}")
    v = [float(x) for x in m.groups()]
    if any(abs(a) > 180.0 for a in v[:3]):
        raise RazorError(f"angle beyond 180 degrees in {line!r}")
    if len(v) == 3:
        return RazorSample(*v)
    if any(abs(a) > 16 * 256 for a in v[3:6]) or any(abs(g) > 35.0 for g in v[6:9]):
        raise RazorError(f"acceleration or rate beyond the sensor's range in {line!r}")
    return RazorSample(v[0], v[1], v[2], (v[3], v[4], v[5]), (v[6], v[7], v[8]))


def to_imu(s: RazorSample, stamp: float, yaw_calibration_deg: float = 0.0,
           frame_id: str = "base_imu_link") -> Imu:
    """Firmware axes (x fwd, y right, z down) -> REP 103 (x fwd, y left, z up), as the
    razor_imu_9dof node converts: yaw, pitch, y and z axes change sign."""
    yaw = normalize_angle(math.radians(-s.yaw + yaw_calibration_deg))
    if s.accel is None:
        return Imu(stamp, yaw=yaw, yaw_variance=0.0025, frame_id=frame_id)
    return Imu(stamp, yaw=yaw, angular_velocity_z=-s.gyro[2],
               linear_acceleration_x=s.accel[0] * ACCEL_FACTOR,
               linear_acceleration_y=-s.accel[1] * ACCEL_FACTOR,
               yaw_variance=0.0025, angular_velocity_variance=0.02, frame_id=frame_id)
