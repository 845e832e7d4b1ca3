"""Kobuki (TurtleBot 2 base) binary protocol codec: frames, commands, feedback, odometry.

Frame: ``AA 55 <len> <payload> <cs>`` where payload is a run of sub-payloads ``<id><len><data>``
and cs is the XOR of the length byte and every payload byte (reference hw_protocols.md 3.2).
Fields are little-endian. A frame is accepted only if its checksum holds and its sub-payloads tile
the payload exactly with the documented lengths.
"""

from __future__ import annotations

import math
import struct
from dataclasses import dataclass, field

import numpy as np

from navcore.types import Pose2D, Twist, normalize_angle
from hw.errors import HwError

HEADER = b"\xaa\x55"
WHEEL_BASE = 0.230                            # m, "wheel bias"
WHEEL_RADIUS = 0.035                          # m
TICK_TO_RAD = 0.002436916871363930187454      # rad of wheel per encoder tick
TICKS_PER_M = 1.0 / (TICK_TO_RAD * WHEEL_RADIUS)

# feedback sub-payload ids and their fixed data lengths (13, the raw gyro, is variable)
BASIC, DOCK_IR, INERTIAL, CLIFF, CURRENT, HW_VERSION, FW_VERSION, RAW_GYRO, GPIO, UDID, \
    CONTROLLER = 1, 3, 4, 5, 6, 10, 11, 13, 16, 19, 21
FEEDBACK_LENGTHS = {BASIC: 15, DOCK_IR: 3, INERTIAL: 7, CLIFF: 6, CURRENT: 2, HW_VERSION: 4,
                    FW_VERSION: 4, GPIO: 16, UDID: 12, CONTROLLER: 13}
# command sub-payload ids and lengths
BASE_CONTROL, SOUND, SOUND_SEQ, REQUEST_EXTRA, GP_OUTPUT, SET_GAIN, GET_GAIN = 1, 3, 4, 9, 12, 13, 14
COMMAND_LENGTHS = {BASE_CONTROL: 4, SOUND: 3, SOUND_SEQ: 1, REQUEST_EXTRA: 2, GP_OUTPUT: 2,
                   SET_GAIN: 13, GET_GAIN: 1}


class KobukiError(HwError, ValueError):
    """A Kobuki frame or sub-payload is malformed; the message says what."""


def checksum(length_and_payload: bytes) -> int:
    """XOR of the length byte and every payload byte."""
    return int(np.bitwise_xor.reduce(np.frombuffer(length_and_payload, dtype=np.uint8))) \
        if length_and_payload else 0


def frame(payload: bytes) -> bytes:
    """Wrap sub-payloads into a frame."""
    if not 1 <= len(payload) <= 255:
        raise KobukiError(f"payload of {len(payload)} bytes does not fit a frame (1..255)")
    body = bytes([len(payload)]) + payload
    return HEADER + body + bytes([checksum(body)])


def sub_payload(ident: int, data: bytes) -> bytes:
    return bytes([ident, len(data)]) + data


def _i16(v: float) -> int:
    return max(-32768, min(32767, int(v)))


def twist_to_speed_radius(v: float, w: float, wheel_base: float = WHEEL_BASE) -> tuple[int, int]:
    """Body velocity -> Kobuki (speed mm/s, radius mm), as the ROS driver computes it
    (truncation toward zero, i16 clamp). Positive radius = centre of the arc on the left."""
    eps = 1e-4
    if abs(w) < eps:
        return _i16(1000.0 * v), 0
    radius = 1000.0 * v / w
    if abs(v) < eps or abs(radius) <= 1.0:
        return _i16(1000.0 * wheel_base * w / 2.0), 1
    half = 1000.0 * wheel_base / 2.0
    speed = (radius + half) * w if radius > 0 else (radius - half) * w
    return _i16(speed), _i16(radius)


def speed_radius_to_wheels(speed: int, radius: int,
                           wheel_base: float = WHEEL_BASE) -> tuple[float, float]:
    """Kobuki (speed, radius) -> (left, right) wheel speeds in m/s, as the firmware does."""
    s = speed / 1000.0
    half = wheel_base / 2.0
    if radius == 0:
        return s, s
    if radius == 1:
        return -s, s
    if radius == -1:
        return s, -s
    r = radius / 1000.0
    if r > 0:      # speed is the outer (right) wheel
        return s * (r - half) / (r + half), s
    return s, s * (r + half) / (r - half)


def base_control_frame(speed: int, radius: int) -> bytes:
    return frame(sub_payload(BASE_CONTROL, struct.pack("<hh", speed, radius)))


def request_extra_frame(flags: int) -> bytes:
    """Ask for hardware (0x01), firmware (0x02) and/or unique id (0x08) in the next feedback."""
    return frame(sub_payload(REQUEST_EXTRA, struct.pack("<H", flags)))


@dataclass(frozen=True, slots=True)
class BasicSensors:
    """Sub-payload 1: time stamp, contact sensors, encoders, PWM, buttons, charger, battery."""

    timestamp_ms: int = 0
    bumper: int = 0
    wheel_drop: int = 0
    cliff: int = 0
    left_encoder: int = 0
    right_encoder: int = 0
    left_pwm: int = 0
    right_pwm: int = 0
    buttons: int = 0
    charger: int = 0
    battery_dv: int = 0          # 0.1 V
    overcurrent: int = 0

    FORMAT = "<HBBBHHbbBBBB"

    def pack(self) -> bytes:
        return struct.pack(self.FORMAT, self.timestamp_ms & 0xFFFF, self.bumper, self.wheel_drop,
                           self.cliff, self.left_encoder & 0xFFFF, self.right_encoder & 0xFFFF,
                           self.left_pwm, self.right_pwm, self.buttons, self.charger,
                           self.battery_dv, self.overcurrent)

    @staticmethod
    def unpack(data: bytes) -> BasicSensors:
        return BasicSensors(*struct.unpack(BasicSensors.FORMAT, data))


@dataclass(frozen=True, slots=True)
class Feedback:
    """One decoded feedback frame. ``heading_cdeg``/``heading_rate`` are None without sub-payload
    4; ``extra`` holds the other sub-payloads' raw data by id (unknown ids included)."""

    basic: BasicSensors
    heading_cdeg: int | None = None
    heading_rate: int | None = None
    extra: dict[int, bytes] = field(default_factory=dict)

    def pack(self) -> bytes:
        out = sub_payload(BASIC, self.basic.pack())
        if self.heading_cdeg is not None:
            out += sub_payload(INERTIAL, struct.pack("<hh3x", self.heading_cdeg,
                                                     self.heading_rate or 0))
        for k, v in self.extra.items():
            out += sub_payload(k, v)
        return frame(out)


def split_sub_payloads(payload: bytes, lengths: dict[int, int]) -> list[tuple[int, bytes]]:
    """Walk ``<id><len><data>`` records; known ids must have their documented length and the
    records must tile the payload exactly."""
    out, i, n = [], 0, len(payload)
    while i < n:
        if i + 2 > n:
            raise KobukiError(f"sub-payload header cut at byte {i}")
        ident, ln = payload[i], payload[i + 1]
        if i + 2 + ln > n:
            raise KobukiError(f"sub-payload {ident} of length {ln} overruns the frame")
        data = payload[i + 2:i + 2 + ln]
        want = lengths.get(ident)
        if want is not None and ln != want:
            raise KobukiError(f"sub-payload {ident} has length {ln}, expected {want}")
        if ident == RAW_GYRO and lengths is FEEDBACK_LENGTHS and \
                (ln < 2 or data[1] * 2 != ln - 2 or data[1] % 3):
            raise KobukiError(f"raw gyro sub-payload of length {ln} is inconsistent")
        out.append((ident, bytes(data)))
        i += 2 + ln
    return out


def parse_feedback(payload: bytes) -> Feedback:
    """A feedback payload (must start with basic sensor data, as the 50 Hz stream does)."""
    subs = split_sub_payloads(payload, FEEDBACK_LENGTHS)
    if not subs or subs[0][0] != BASIC:
        raise KobukiError("feedback frame does not start with basic sensor data")
    basic = BasicSensors.unpack(subs[0][1])
    heading = rate = None
    extra: dict[int, bytes] = {}
    for ident, data in subs[1:]:
        if ident == INERTIAL:
            heading, rate = struct.unpack_from("<hh", data)
        elif ident == BASIC:
            raise KobukiError("two basic sensor sub-payloads in one frame")
        else:
            extra[ident] = data
    return Feedback(basic, heading, rate, extra)


def parse_commands(payload: bytes) -> list[tuple[int, bytes]]:
    """A host command payload, as the robot reads it."""
    return split_sub_payloads(payload, COMMAND_LENGTHS)


class FrameDecoder:
    """Incremental frame finder: feed any chunks, get checked payloads.

    Hunts for ``AA 55``; a frame with a bad checksum or length costs only its first header byte,
    so a false header inside garbage cannot swallow a real frame that follows."""

    def __init__(self) -> None:
        self._buf = bytearray()
        self.errors = 0
        self.last_error = ""

    def reset(self) -> None:
        self._buf.clear()

    def feed(self, chunk: bytes) -> list[bytes]:
        buf = self._buf
        buf += chunk
        out: list[bytes] = []
        while True:
            k = buf.find(HEADER)
            if k < 0:
                del buf[:max(0, len(buf) - 1)]     # keep a trailing AA: half a header
                return out
            if k:
                del buf[:k]
            if len(buf) < 3:
                return out
            ln = buf[2]
            if ln < 3:
                self._reject(f"frame length {ln} below 3")
                del buf[:1]
                continue
            if len(buf) < ln + 4:
                return out
            body = bytes(buf[2:ln + 4])
            if checksum(body) != 0:
                self._reject("checksum mismatch")
                del buf[:1]
                continue
            out.append(body[1:-1])
            del buf[:ln + 4]

    def _reject(self, why: str) -> None:
        self.errors += 1
        self.last_error = why


class KobukiOdometry:
    """Diff-drive dead reckoning from the u16 encoders (wrap-safe), optionally with the gyro
    heading replacing the encoder yaw (kobuki_node's ``use_imu_heading``)."""

    def __init__(self, use_imu_heading: bool = True) -> None:
        self.use_imu_heading = use_imu_heading
        self.pose = Pose2D()
        self.twist = Twist()
        self._last: BasicSensors | None = None
        self._last_heading: int | None = None
        self._heading0: float | None = None

    def implausibility(self, fb: Feedback, max_speed: float, max_rate: float) -> str | None:
        """Why ``fb`` cannot follow the last frame (None when it can): each wheel moving faster
        than ``max_speed`` m/s or the gyro heading turning faster than ``max_rate`` rad/s over
        the frames' own time step (the XOR checksum misses two flipped bits in one column)."""
        last = self._last
        if last is None:
            return None
        dt = max(((fb.basic.timestamp_ms - last.timestamp_ms) & 0xFFFF) / 1000.0, 0.02)
        for name, now, before in (("left", fb.basic.left_encoder, last.left_encoder),
                                  ("right", fb.basic.right_encoder, last.right_encoder)):
            d = abs(_wrap16(now - before)) * TICK_TO_RAD * WHEEL_RADIUS
            if d > max_speed * dt + 0.005:
                return f"{name} wheel moved {d:.3f} m in {dt:.3f} s"
        if (fb.heading_cdeg is not None and self._last_heading is not None):
            turn = abs(normalize_angle(math.radians((fb.heading_cdeg - self._last_heading)
                                                    / 100.0)))
            if turn > max_rate * dt + 0.02:
                return f"heading turned {turn:.3f} rad in {dt:.3f} s"
        return None

    def rebase(self, fb: Feedback) -> None:
        """Take ``fb`` as the new reference without moving (after repeated refusals)."""
        self._last = fb.basic
        if fb.heading_cdeg is not None:
            self._last_heading = fb.heading_cdeg

    def update(self, fb: Feedback) -> tuple[Pose2D, Twist]:
        b = fb.basic
        last, self._last = self._last, b
        if fb.heading_cdeg is not None:
            self._last_heading = fb.heading_cdeg
        if last is None:
            if fb.heading_cdeg is not None:
                self._heading0 = math.radians(fb.heading_cdeg / 100.0)
            return self.pose, self.twist
        dl = _wrap16(b.left_encoder - last.left_encoder) * TICK_TO_RAD * WHEEL_RADIUS
        dr = _wrap16(b.right_encoder - last.right_encoder) * TICK_TO_RAD * WHEEL_RADIUS
        ds, dth = (dl + dr) / 2.0, (dr - dl) / WHEEL_BASE
        th0 = self.pose.theta
        if self.use_imu_heading and fb.heading_cdeg is not None and self._heading0 is not None:
            th1 = normalize_angle(math.radians(fb.heading_cdeg / 100.0) - self._heading0)
            dth = normalize_angle(th1 - th0)
        mid = th0 + dth / 2.0
        self.pose = Pose2D(self.pose.x + ds * math.cos(mid), self.pose.y + ds * math.sin(mid),
                           normalize_angle(th0 + dth))
        dt = ((b.timestamp_ms - last.timestamp_ms) & 0xFFFF) / 1000.0
        if dt > 0:
            self.twist = Twist(ds / dt, 0.0, dth / dt)
        return self.pose, self.twist


def _wrap16(d: int) -> int:
    d &= 0xFFFF
    return d - 0x10000 if d >= 0x8000 else d
