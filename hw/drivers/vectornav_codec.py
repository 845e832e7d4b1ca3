"""VectorNav ASCII codec: ``$VNYMR`` sentences and register commands (reference 4.2). No I/O.

``$VNYMR,yaw,pitch,roll,magX,magY,magZ,accX,accY,accZ,gyroX,gyroY,gyroZ*CS`` + CR LF, where CS
is two upper-case hex digits of the XOR of every character between ``$`` and ``*``. Angles in
degrees (NED body frame, yaw clockwise), magnetic field in gauss, acceleration in m/s^2, rates in
rad/s.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import reduce

from navcore.types import Imu, normalize_angle
from hw.errors import HwError

_HEX = "0123456789ABCDEF"


class VnError(HwError, ValueError):
    """A VectorNav sentence is malformed; the message says what."""


def checksum(body: str) -> int:
    return reduce(lambda a, c: a ^ ord(c), body, 0)


def sentence(body: str) -> bytes:
    """``$body*CS`` + CR LF."""
    return f"${body}*{checksum(body):02X}\r\n".encode("ascii")


def read_register(reg: int) -> bytes:
    return sentence(f"VNRRG,{reg:02d}")


def write_register(reg: int, *values: object) -> bytes:
    return sentence(",".join([f"VNWRG,{reg:02d}", *map(str, values)]))


def split_sentence(line: str) -> list[str]:
    """Check ``$...*CS`` and return the comma-separated fields of the body."""
    if len(line) < 5 or line[0] != "$" or line[-3] != "*":
        raise VnError(f"not a VectorNav sentence: {line[:40]!r}")
    body, cs = line[1:-3], line[-2:]
    if any(c not in _HEX for c in cs):
        raise VnError(f"checksum {cs!r} is not two upper-case hex digits")
    if int(cs, 16) != checksum(body):
        raise VnError(f"checksum mismatch in {line[:40]!r}")
    if any(not 0x20 <= ord(c) <= 0x7E or c in "$*" for c in body):
        raise VnError("control or framing character inside a sentence")
    return body.split(",")


@dataclass(frozen=True, slots=True)
class Ymr:
    """One ``$VNYMR`` sample in the sensor's units and axes."""

    ypr: tuple[float, float, float]
    mag: tuple[float, float, float]
    accel: tuple[float, float, float]
    gyro: tuple[float, float, float]

    def line(self) -> bytes:
        f = [f"{v:+08.3f}" for v in self.ypr] + [f"{v:+08.4f}" for v in self.mag] + \
            [f"{v:+07.3f}" for v in self.accel] + [f"{v:+010.6f}" for v in self.gyro]
        return sentence("VNYMR," + ",".join(f))


def parse_ymr(line: str) -> Ymr:
    f = split_sentence(line)
    if f[0] != "VNYMR" or len(f) != 13:
        raise VnError(f"{f[0]} with {len(f) - 1} fields is not a VNYMR sentence")
    try:
        v = [float(x) for x in f[1:]]
    except ValueError:
        raise VnError(f"non-numeric field in {line[:40]!r}") from None
    if not all(math.isfinite(x) for x in v) or any(abs(a) > 180.0 for a in v[:3]):
        raise VnError(f"impossible attitude in {line[:40]!r}")
    return Ymr(tuple(v[0:3]), tuple(v[3:6]), tuple(v[6:9]), tuple(v[9:12]))


def to_imu(s: Ymr, stamp: float, frame_id: str = "imu") -> Imu:
    """NED body frame -> REP 103: yaw counter-clockwise, y and z axes change sign."""
    return Imu(stamp, yaw=normalize_angle(-math.radians(s.ypr[0])),
               angular_velocity_z=-s.gyro[2], linear_acceleration_x=s.accel[0],
               linear_acceleration_y=-s.accel[1], yaw_variance=math.radians(0.3) ** 2,
               angular_velocity_variance=1e-5, frame_id=frame_id)
