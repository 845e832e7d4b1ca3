"""ros_arduino_bridge ASCII protocol codec (reference hw_protocols.md 3.3). No I/O.

Requests are single letters with space-separated integer arguments, ended by CR; replies are one
line ended by CR LF. There is no checksum and no echo, so every reply is checked against the
shape the pending request expects, and encoder jumps beyond what the wheels can do are refused.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

from hw.drivers.lines import LineDecoder  # noqa: F401  (re-exported: the bridge's line framing)
from hw.errors import HwError

PID_RATE = 30.0                 # PID frames per second in the firmware
AUTO_STOP_INTERVAL = 2.0        # s: the firmware stops the motors without an 'm' for this long
BAUDRATE = 57600

_INT = r"-?\d{1,10}"
_ENCODERS = re.compile(rf"^({_INT}) ({_INT})$")


class ArduinoError(HwError, ValueError):
    """A reply does not have the shape its request expects; the message says what."""


def command(letter: str, *args: int | str) -> bytes:
    """``letter args...`` + CR."""
    if len(letter) != 1 or not letter.isalpha():
        raise ArduinoError(f"command must be one letter, got {letter!r}")
    return " ".join([letter, *map(str, args)]).encode("ascii") + b"\r"


def motor_command(left_ticks_per_frame: int, right_ticks_per_frame: int) -> bytes:
    return command("m", int(left_ticks_per_frame), int(right_ticks_per_frame))


def pid_command(kp: int, kd: int, ki: int, ko: int) -> bytes:
    """Gains in the firmware's order Kp, Kd, Ki, Ko, colon-separated."""
    return f"u {kp}:{kd}:{ki}:{ko}\r".encode("ascii")


def parse_encoders(line: str) -> tuple[int, int]:
    """The reply to ``e``: two signed 32-bit counts."""
    m = _ENCODERS.match(line)
    if not m:
        raise ArduinoError(f"encoder reply {line!r} is not two integers")
    left, right = int(m.group(1)), int(m.group(2))
    if not (-2**31 <= left < 2**31 and -2**31 <= right < 2**31):
        raise ArduinoError(f"encoder reply {line!r} overflows a signed long")
    return left, right


def expect_ok(line: str) -> None:
    if line != "OK":
        raise ArduinoError(f"expected OK, got {line!r}")


@dataclass(frozen=True, slots=True)
class Geometry:
    """Wheel geometry of a home-built base, ros_arduino_python's parameter meanings."""

    wheel_diameter: float = 0.146
    wheel_track: float = 0.2969
    encoder_resolution: int = 8384
    gear_reduction: float = 1.0

    @property
    def ticks_per_meter(self) -> float:
        return self.encoder_resolution * self.gear_reduction / (self.wheel_diameter * math.pi)

    def wheel_targets(self, v: float, w: float) -> tuple[int, int]:
        """Body velocity -> (left, right) targets in ticks per PID frame, as the host node does."""
        left = v - w * self.wheel_track / 2.0
        right = v + w * self.wheel_track / 2.0
        return (int(left * self.ticks_per_meter / PID_RATE),
                int(right * self.ticks_per_meter / PID_RATE))
